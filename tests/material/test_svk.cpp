#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <string>

#include "material/svk.hpp"
#include "support/taylor.hpp"

namespace conserve::material {
namespace {

using conserve::test::TaylorOrder;

/// A random symmetric D × D direction, entries in ±1.
template <int D>
Mat<D> random_symmetric(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Mat<D> d;
  for (int i = 0; i < D; ++i)
    for (int j = 0; j <= i; ++j) d(i, j) = d(j, i) = u(rng);
  return d;
}

// dΨ = S : dE: the Taylor test of Ψ at E along random symmetric dE (Ψ is
// quadratic in E: the remainder is ½ h² dE : ℂ : dE, order 2 exactly).
template <int D>
void check_stress_is_energy_gradient() {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  const Lame lame = Lame::from_young_poisson(2.0e3, 0.3);
  Mat<D> E;
  for (int i = 0; i < D; ++i)
    for (int j = 0; j <= i; ++j) E(i, j) = E(j, i) = u(rng);
  const Mat<D> S = svk_stress<D>(lame, E);
  ASSERT_GT(S.norm(), 1.0);  // non-zero guard
  const Mat<D> dE = random_symmetric<D>(rng);
  auto energy = [&](const Eigen::VectorXd& v) {
    return Eigen::VectorXd::Constant(1, svk_energy_density<D>(lame, Mat<D>(v.reshaped(D, D))));
  };
  const TaylorOrder t = conserve::test::taylor_order(energy, E.reshaped(), dE.reshaped(),
                                                     Eigen::VectorXd::Constant(1, S.cwiseProduct(dE).sum()), 1e-2);
  std::printf("[ measured ] svk %dD, S = ∂Ψ/∂E: %s\n", D, conserve::test::describe(t).c_str());
  conserve::test::expect_second_order(t, std::to_string(D) + "D");
}

TEST(Svk, StressIsEnergyGradient2d) { check_stress_is_energy_gradient<2>(); }
TEST(Svk, StressIsEnergyGradient3d) { check_stress_is_energy_gradient<3>(); }

// The material tangent ℂ_IJKL = λ δ_IJ δ_KL + μ(δ_IK δ_JL + δ_IL δ_JK) by
// the Taylor test of S(E) along random symmetric dE, J d = ℂ : dE. S is
// linear in E: the remainder has no order but is round-off at every step,
// where a wrong ℂ would leave h |δℂ : dE|.
TEST(Svk, TangentMatchesFiniteDifferences) {
  const Lame lame = Lame::from_young_poisson(3.0e3, 0.25);
  Mat3 E;
  E << 0.1, 0.02, -0.03, 0.02, -0.05, 0.04, -0.03, 0.04, 0.07;
  std::mt19937 rng(8);
  const Mat3 dE = random_symmetric<3>(rng);
  Mat3 CdE = Mat3::Zero();
  for (int I = 0; I < 3; ++I)
    for (int J = 0; J < 3; ++J)
      for (int K = 0; K < 3; ++K)
        for (int L = 0; L < 3; ++L)
          CdE(I, J) +=
              (lame.lambda * (I == J) * (K == L) + lame.mu * ((I == K) * (J == L) + (I == L) * (J == K))) * dE(K, L);
  auto stress = [&](const Eigen::VectorXd& v) {
    return Eigen::VectorXd(svk_stress<3>(lame, v.reshaped(3, 3)).reshaped());
  };
  const TaylorOrder t = conserve::test::taylor_order(stress, E.reshaped(), dE.reshaped(), CdE.reshaped(), 1e-2);
  std::printf("[ measured ] svk ℂ = ∂S/∂E: %s\n", conserve::test::describe(t).c_str());
  EXPECT_GT(t.slope, 1e3);  // non-zero guard
  conserve::test::expect_exact(t, "svk ℂ");
}

TEST(Svk, LameConstants) {
  const Lame l = Lame::from_young_poisson(210e9, 0.3);
  EXPECT_NEAR(l.mu, 210e9 / 2.6, 1.0);
  EXPECT_NEAR(l.lambda, 210e9 * 0.3 / (1.3 * 0.4), 1.0);
}

TEST(Svk, RigidRotationIsStressFree) {
  const double c = std::cos(0.7), s = std::sin(0.7);
  Mat3 R;
  R << c, -s, 0, s, c, 0, 0, 0, 1;
  const Mat3 E = green_lagrange<3>(R);
  EXPECT_LT(E.norm(), 1e-15);
  EXPECT_LT(svk_energy_density<3>(Lame{1e9, 1e9}, E), 1e-20);
  EXPECT_LT(svk_stress<3>(Lame{1e9, 1e9}, E).norm(), 1e-5);
}

}  // namespace
}  // namespace conserve::material
