#include <gtest/gtest.h>

#include <random>

#include "material/svk.hpp"

namespace conserve::material {
namespace {

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
  const double h = 1e-6;
  for (int i = 0; i < D; ++i) {
    for (int j = 0; j < D; ++j) {
      Mat<D> dE = Mat<D>::Zero();
      dE(i, j) += 0.5 * h;
      dE(j, i) += 0.5 * h;  // symmetric perturbation: dΨ = S:dE = S_ij h
      const double fd = (svk_energy_density<D>(lame, E + dE) - svk_energy_density<D>(lame, E - dE)) / (2 * h);
      EXPECT_NEAR(fd, S(i, j), 1e-7 * S.norm()) << i << "," << j;
    }
  }
}

TEST(Svk, StressIsEnergyGradient2d) { check_stress_is_energy_gradient<2>(); }
TEST(Svk, StressIsEnergyGradient3d) { check_stress_is_energy_gradient<3>(); }

// The material tangent ℂ_IJKL = λ δ_IJ δ_KL + μ(δ_IK δ_JL + δ_IL δ_JK)
// against finite differences of S(E).
TEST(Svk, TangentMatchesFiniteDifferences) {
  const Lame lame = Lame::from_young_poisson(3.0e3, 0.25);
  Mat3 E;
  E << 0.1, 0.02, -0.03, 0.02, -0.05, 0.04, -0.03, 0.04, 0.07;
  const double h = 1e-6;
  double max_entry = 0.0, err = 0.0;
  for (int K = 0; K < 3; ++K)
    for (int L = 0; L < 3; ++L) {
      Mat3 dE = Mat3::Zero();
      dE(K, L) += 0.5 * h;
      dE(L, K) += 0.5 * h;
      const Mat3 dS = (svk_stress<3>(lame, E + dE) - svk_stress<3>(lame, E - dE)) / (2 * h);
      for (int I = 0; I < 3; ++I)
        for (int J = 0; J < 3; ++J) {
          const double C = lame.lambda * (I == J) * (K == L) + lame.mu * ((I == K) * (J == L) + (I == L) * (J == K));
          // a symmetric unit perturbation picks ½(ℂ_IJKL + ℂ_IJLK) = ℂ_IJKL
          err = std::max(err, std::abs(dS(I, J) - C));
          max_entry = std::max(max_entry, std::abs(C));
        }
    }
  ASSERT_GT(max_entry, 1e3);  // non-zero guard
  EXPECT_LT(err, 1e-6 * max_entry);
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
