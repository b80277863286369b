// Every point law (material/law.hpp) in 3D and in plane strain: S is the
// energy's gradient and ℂ the stress's, against central differences with
// a non-zero guard; ℂ has its symmetries; at C = 1 the law is stress-free
// with the small-strain stiffness it reports.
#include <gtest/gtest.h>

#include <random>

#include "core/error.hpp"
#include "law_cases.hpp"

namespace conserve::material {
namespace {

using test::LawCase;

/// A symmetric perturbation of C in components (i, j) and (j, i), within
/// the first D rows and columns (plane strain keeps C_i3 fixed).
Mat3 unit(int i, int j) {
  Mat3 d = Mat3::Zero();
  d(i, j) += 0.5;
  d(j, i) += 0.5;
  return d;
}

template <int D>
void check_stress_is_energy_gradient(const LawCase& c) {
  const auto law = test::make(c);
  std::mt19937 rng(11);
  for (int trial = 0; trial < 5; ++trial) {
    const Mat3 C = test::right_cauchy_green<D>(test::random_F<D>(rng, 0.3));
    const Mat3 S = law->stress(C);
    ASSERT_GT(S.norm(), 1e4) << c.model;  // non-zero guard (μ ≈ 3.8e5 Pa)
    const double h = 1e-6;
    for (int i = 0; i < D; ++i)
      for (int j = 0; j < D; ++j) {
        // dΨ = ∂Ψ/∂C : dC = ½ S : dC, and unit(i, j) : S = S_ij
        const double fd = (law->energy(C + h * unit(i, j)) - law->energy(C - h * unit(i, j))) / (2.0 * h);
        EXPECT_NEAR(2.0 * fd, S(i, j), 1e-6 * S.norm()) << c.model << " " << D << "D (" << i << ", " << j << ")";
      }
  }
}

template <int D>
void check_tangent_is_stress_gradient(const LawCase& c) {
  const auto law = test::make(c);
  std::mt19937 rng(12);
  for (int trial = 0; trial < 5; ++trial) {
    const Mat3 C = test::right_cauchy_green<D>(test::random_F<D>(rng, 0.3));
    const Mat9 T = law->tangent(C);
    ASSERT_GT(T.norm(), 1e5) << c.model;  // non-zero guard
    EXPECT_LT((T - T.transpose()).norm(), 1e-12 * T.norm()) << c.model << ": major symmetry";
    const double h = 1e-6;
    for (int k = 0; k < D; ++k)
      for (int l = 0; l < D; ++l) {
        const Mat3 dS = (law->stress(C + h * unit(k, l)) - law->stress(C - h * unit(k, l))) / (2.0 * h);
        // δS = ½ ℂ : δC; minor symmetry makes ℂ : unit(k, l) = column (k, l)
        for (int i = 0; i < D; ++i)
          for (int j = 0; j < D; ++j) {
            EXPECT_NEAR(2.0 * dS(i, j), T(i + 3 * j, k + 3 * l), 1e-6 * T.norm())
                << c.model << " " << D << "D (" << i << j << k << l << ")";
            EXPECT_EQ(T(i + 3 * j, k + 3 * l), T(j + 3 * i, k + 3 * l)) << c.model << ": minor symmetry";
          }
      }
  }
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
