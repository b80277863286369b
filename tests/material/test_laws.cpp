// Every point law (material/law.hpp) in 3D and in plane strain: S is the
// energy's gradient and ℂ the stress's, by the Taylor test (a remainder of
// order 2, support/taylor.hpp) with a non-zero guard; ℂ has its
// symmetries; at C = 1 the law is stress-free with the small-strain
// stiffness it reports.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <string>

#include "core/error.hpp"
#include "law_cases.hpp"
#include "support/taylor.hpp"

namespace conserve::material {
namespace {

using test::LawCase;

using conserve::test::describe;
using conserve::test::TaylorOrder;

Mat3 matrix(const Eigen::VectorXd& v) { return v.reshaped(3, 3); }
Eigen::VectorXd vec(const Mat3& A) { return A.reshaped(); }

// dΨ = ∂Ψ/∂C : dC = ½ S : dC: the Taylor test of Ψ at C along random
// symmetric dC (SVK's Ψ, quadratic in C, has the remainder ½ h² dC : ∂²Ψ :
// dC, order 2 exactly).
template <int D>
void check_stress_is_energy_gradient(const LawCase& c) {
  const auto law = test::make(c);
  std::mt19937 rng(11);
  TaylorOrder worst;
  for (int trial = 0; trial < 5; ++trial) {
    const Mat3 C = test::right_cauchy_green<D>(test::random_F<D>(rng, 0.3));
    const Mat3 S = law->stress(C);
    ASSERT_GT(S.norm(), 1e4) << c.model;  // non-zero guard (μ ≈ 3.8e5 Pa)
    const Mat3 dC = test::random_symmetric<D>(rng);
    auto energy = [&](const Eigen::VectorXd& v) { return Eigen::VectorXd::Constant(1, law->energy(matrix(v))); };
    const TaylorOrder t = conserve::test::taylor_order(
        energy, vec(C), vec(dC), Eigen::VectorXd::Constant(1, 0.5 * S.cwiseProduct(dC).sum()), 1e-2);
    conserve::test::expect_second_order(t, c.model + " " + std::to_string(D) + "D, trial " + std::to_string(trial));
    worst = trial == 0 ? t : conserve::test::worse(t, worst);
  }
  std::printf("[ measured ] %s %dD, S = 2 ∂Ψ/∂C at 5 random C, the worst: %s\n", c.model.c_str(), D,
              describe(worst).c_str());
}

// δS = ½ ℂ : δC: the Taylor test of S at C along random symmetric dC, with
// J d = ½ ℂ : dC (ℂ as the 9 × 9 matrix on vec(dC)). SVK's S is linear in
// C: its remainder has no order but is round-off at every step, where a
// wrong ℂ would leave h |½ δℂ : dC|.
template <int D>
void check_tangent_is_stress_gradient(const LawCase& c) {
  const auto law = test::make(c);
  std::mt19937 rng(12);
  TaylorOrder worst;
  for (int trial = 0; trial < 5; ++trial) {
    const Mat3 C = test::right_cauchy_green<D>(test::random_F<D>(rng, 0.3));
    const Mat9 T = law->tangent(C);
    ASSERT_GT(T.norm(), 1e5) << c.model;  // non-zero guard
    EXPECT_LT((T - T.transpose()).norm(), 1e-12 * T.norm()) << c.model << ": major symmetry";
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        for (int kl = 0; kl < 9; ++kl) EXPECT_EQ(T(i + 3 * j, kl), T(j + 3 * i, kl)) << c.model << ": minor symmetry";
    const Mat3 dC = test::random_symmetric<D>(rng);
    auto stress = [&](const Eigen::VectorXd& v) { return vec(law->stress(matrix(v))); };
    const TaylorOrder t = conserve::test::taylor_order(stress, vec(C), vec(dC), 0.5 * T * vec(dC), 1e-2);
    const std::string what = c.model + " " + std::to_string(D) + "D, trial " + std::to_string(trial);
    if (law->svk()) {
      conserve::test::expect_exact(t, what);
    } else {
      conserve::test::expect_second_order(t, what);
    }
    worst = trial == 0 ? t : conserve::test::worse(t, worst);
  }
  std::printf("[ measured ] %s %dD, ℂ = 2 ∂S/∂C at 5 random C, the worst: %s\n", c.model.c_str(), D,
              describe(worst).c_str());
}

TEST(Laws, StressIsTheEnergyGradient3d) {
  for (const auto& c : test::law_cases()) check_stress_is_energy_gradient<3>(c);
}
TEST(Laws, StressIsTheEnergyGradient2d) {
  for (const auto& c : test::law_cases()) check_stress_is_energy_gradient<2>(c);
}
TEST(Laws, TangentIsTheStressGradient3d) {
  for (const auto& c : test::law_cases()) check_tangent_is_stress_gradient<3>(c);
}
TEST(Laws, TangentIsTheStressGradient2d) {
  for (const auto& c : test::law_cases()) check_tangent_is_stress_gradient<2>(c);
}

TEST(Laws, UndeformedIsStressFreeWithTheSmallStrainStiffness) {
  for (const auto& c : test::law_cases()) {
    const auto law = test::make(c);
    const Mat3 I = Mat3::Identity();
    EXPECT_LT(std::abs(law->energy(I)), 1e-9) << c.model;
    EXPECT_LT(law->stress(I).norm(), 1e-9) << c.model;
    const Lame l = law->small_strain();
    const Mat9 expected = l.lambda * dyad(I, I) + 2.0 * l.mu * symmetric_product(I);
    EXPECT_LT((law->tangent(I) - expected).norm(), 1e-9 * expected.norm()) << c.model;
    const Lame reference = Lame::from_young_poisson(1.0e6, 0.3);  // every case is made to have it
    EXPECT_NEAR(l.mu, reference.mu, 1e-9 * reference.mu) << c.model;
    EXPECT_NEAR(l.lambda, reference.lambda, 1e-9 * reference.lambda) << c.model;
  }
}

TEST(Laws, RigidRotationIsStressFree) {
  const double c = std::cos(0.7), s = std::sin(0.7);
  Mat3 R;
  R << c, -s, 0, s, c, 0, 0, 0, 1;
  for (const auto& lc : test::law_cases()) {
    const auto law = test::make(lc);
    EXPECT_LT(law->stress(R.transpose() * R).norm(), 1e-9) << lc.model;
  }
}

TEST(Laws, OnlySvkTakesTheClosedFormKernel) {
  for (const auto& c : test::law_cases()) EXPECT_EQ(test::make(c)->svk() != nullptr, c.model == "svk") << c.model;
}

TEST(Laws, NeoHookeanResistsCompressionWhereSvkSoftens) {
  // Uniaxial compression to 30 % of the length: SVK's stress has turned
  // back towards zero (it vanishes at λ = 0), neo-Hookean's keeps growing.
  const Lame l = Lame::from_young_poisson(1.0e6, 0.3);
  const auto svk = make_law("svk", {{"young", 1.0e6}, {"poisson", 0.3}});
  const auto nh = make_law("neo_hookean", {{"young", 1.0e6}, {"poisson", 0.3}});
  auto axial_P = [](const Law& law, double stretch) {  // first Piola stress P = F S along x
    Mat3 C = Mat3::Identity();
    C(0, 0) = stretch * stretch;
    return stretch * law.stress(C)(0, 0);
  };
  EXPECT_GT(axial_P(*svk, 0.3), axial_P(*svk, 0.6));  // softening: less compressive at 0.3 than at 0.6
  EXPECT_LT(axial_P(*nh, 0.3), axial_P(*nh, 0.6));    // stiffening
  EXPECT_LT(axial_P(*nh, 0.3), -l.mu);
}

TEST(Laws, MooneyRivlinWithoutShearIsRefused) {
  EXPECT_THROW(make_law("mooney_rivlin", {{"c10", 0.0}, {"c01", 0.0}, {"bulk", 1e6}}), InputError);
  EXPECT_THROW(make_law("clay", {}), InputError);
}

}  // namespace
}  // namespace conserve::material
