#pragma once
/// The point laws the tests run every check on, with parameters of the
/// same small-strain stiffness (E = 1e6 Pa, ν = 0.3), and random
/// deformations of 30 % and more.
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "material/law.hpp"

namespace conserve::material::test {

struct LawCase {
  std::string model;
  std::map<std::string, double> parameters;
};

/// svk, neo_hookean and mooney_rivlin (c10 = 3c01, μ = 2(c10 + c01) and κ
/// those of E = `young` [Pa], ν = `poisson`).
inline std::vector<LawCase> law_cases(double young = 1.0e6, double poisson = 0.3) {
  const Lame l = Lame::from_young_poisson(young, poisson);
  return {{"svk", {{"young", young}, {"poisson", poisson}}},
          {"neo_hookean", {{"young", young}, {"poisson", poisson}}},
          {"mooney_rivlin", {{"c10", 0.375 * l.mu}, {"c01", 0.125 * l.mu}, {"bulk", l.lambda + 2.0 * l.mu / 3.0}}}};
}

inline std::shared_ptr<const Law> make(const LawCase& c) { return make_law(c.model, c.parameters); }

/// A deformation gradient 1 + A with entries of A in ±`amount`, det > 0.
template <int D>
Mat<D> random_F(std::mt19937& rng, double amount) {
  std::uniform_real_distribution<double> u(-amount, amount);
  for (;;) {
    Mat<D> F = Mat<D>::Identity();
    for (int i = 0; i < D; ++i)
      for (int j = 0; j < D; ++j) F(i, j) += u(rng);
    if (F.determinant() > 0.3) return F;
  }
}

/// A random symmetric direction of C, entries in ±1 within the first D rows
/// and columns (plane strain keeps C_i3 fixed).
template <int D>
Mat3 random_symmetric(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Mat3 d = Mat3::Zero();
  for (int i = 0; i < D; ++i)
    for (int j = 0; j <= i; ++j) d(i, j) = d(j, i) = u(rng);
  return d;
}

/// C = FᵀF embedded in 3 × 3 (C_33 = 1 in 2D).
template <int D>
Mat3 right_cauchy_green(const Mat<D>& F) {
  return embed_plane_strain<D>(Mat<D>(F.transpose() * F));
}

}  // namespace conserve::material::test
