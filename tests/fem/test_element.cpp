#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <string>

#include "material/svk_law.hpp"
#include "fem/element.hpp"
#include "material/law_cases.hpp"
#include "support/random_cell.hpp"
#include "support/taylor.hpp"

namespace conserve::fem {
namespace {

const material::Svk kSvk(material::Lame::from_young_poisson(1.0e4, 0.3));

template <int D>
StepPositions<D> random_step(std::mt19937& rng, const NodeMatrix<D>& X) {
  return {test::random_deformed<D>(rng, X, 0.05), test::random_deformed<D>(rng, X, 0.05)};
}

// The element tangent ∂f/∂x_{n+1} by the Taylor test of the internal force
// along a random direction of the nodes' x_{n+1}, on 20 random cells and
// steps (a remainder of order 2, support/taylor.hpp); the worst is
// printed.
template <int D>
void check_tangent(StressScheme scheme, const material::Law& kLame = kSvk, const char* name = "svk") {
  constexpr int N = D * (D + 1);
  std::mt19937 rng(11);
  test::TaylorOrder worst;
  for (int trial = 0; trial < 20; ++trial) {
    const NodeMatrix<D> X = test::random_reference_cell<D>(rng, 0.1);
    const SimplexGeometry<D> g = simplex_geometry<D>(X, 1.0);
    StepPositions<D> x = random_step<D>(rng, X);
    NodeMatrix<D> f;
    ElementMatrix<D> K;
    internal_force_tangent<D>(g, kLame, x, scheme, f, K);
    ASSERT_GT(K.norm(), 1.0);  // non-zero guard
    EXPECT_LT((f - internal_force<D>(g, kLame, x, scheme)).norm(), 1e-12 * f.norm());
    auto force = [&](const Eigen::VectorXd& x_np1) {
      StepPositions<D> at = x;
      at.x_np1 = x_np1.reshaped(D, D + 1);
      return Eigen::VectorXd(internal_force<D>(g, kLame, at, scheme).reshaped());
    };
    const Eigen::VectorXd d = test::random_direction(rng, N);
    const test::TaylorOrder t = test::taylor_order(force, x.x_np1.reshaped(), d, K * d, 1e-3 * 0.1);
    test::expect_second_order(t, "trial " + std::to_string(trial));
    worst = trial == 0 ? t : test::worse(t, worst);
  }
  std::printf("[ measured ] element tangent (%s, %dD, %s), 20 random cells: worst %s\n", name, D,
              scheme == StressScheme::conserving ? "conserving" : "midpoint", test::describe(worst).c_str());
}

TEST(ElementTangent, Conserving2d) { check_tangent<2>(StressScheme::conserving); }
TEST(ElementTangent, Conserving3d) { check_tangent<3>(StressScheme::conserving); }
TEST(ElementTangent, Midpoint2d) { check_tangent<2>(StressScheme::midpoint); }
TEST(ElementTangent, Midpoint3d) { check_tangent<3>(StressScheme::midpoint); }

TEST(ElementTangent, IsNotSymmetric) {
  std::mt19937 rng(3);
  const NodeMatrix<3> X = test::random_reference_cell<3>(rng);
  const SimplexGeometry<3> g = simplex_geometry<3>(X, 1.0);
  NodeMatrix<3> f;
  ElementMatrix<3> K;
  internal_force_tangent<3>(g, kSvk, random_step<3>(rng, X), StressScheme::conserving, f, K);
  EXPECT_GT((K - K.transpose()).norm(), 1e-3 * K.norm());
}

// Paper (25)–(26): Σ f_A = 0, Σ x_{A,n+½} × f_A = 0 and, for the conserving
// stress only, Σ f_A·Δx_A = W_{n+1} − W_n exactly.
template <int D>
double energy_identity_error(StressScheme scheme, bool print, const material::Law& kLame = kSvk,
                             const char* name = "svk") {
  std::mt19937 rng(5);
  double worst = 0.0;
  for (int trial = 0; trial < 50; ++trial) {
    const NodeMatrix<D> X = test::random_reference_cell<D>(rng);
    const SimplexGeometry<D> g = simplex_geometry<D>(X, 1.0);
    const StepPositions<D> x = random_step<D>(rng, X);
    const NodeMatrix<D> f = internal_force<D>(g, kLame, x, scheme);
    const double dW = strain_energy<D>(g, kLame, x.x_np1) - strain_energy<D>(g, kLame, x.x_n);
    const double work = (f.array() * (x.x_np1 - x.x_n).array()).sum();
    const double scale = strain_energy<D>(g, kLame, x.x_np1) + strain_energy<D>(g, kLame, x.x_n);
    worst = std::max(worst, std::abs(work - dW) / scale);
    EXPECT_LT(f.rowwise().sum().norm(), 1e-12 * f.norm());
    const NodeMatrix<D> x_mid = 0.5 * (x.x_n + x.x_np1);
    double moment = 0.0;
    if constexpr (D == 2) {
      for (int a = 0; a <= D; ++a) moment += x_mid(0, a) * f(1, a) - x_mid(1, a) * f(0, a);
    } else {
      Vec3 m = Vec3::Zero();
      for (int a = 0; a <= D; ++a) m += Vec3(x_mid.col(a)).cross(Vec3(f.col(a)));
      moment = m.norm();
    }
    EXPECT_LT(std::abs(moment), 1e-12 * f.norm() * x_mid.norm());
  }
  if (print)
    std::printf("[ measured ] max relative |Σf·Δx − ΔW| / W (%s, %dD, %s): %.3e\n", name, D,
                scheme == StressScheme::conserving ? "conserving" : "midpoint", worst);
  return worst;
}

TEST(ElementEnergy, ConservingIsExact2d) { EXPECT_LT(energy_identity_error<2>(StressScheme::conserving, true), 1e-12); }
TEST(ElementEnergy, ConservingIsExact3d) { EXPECT_LT(energy_identity_error<3>(StressScheme::conserving, true), 1e-12); }
TEST(ElementEnergy, MidpointIsNot2d) { EXPECT_GT(energy_identity_error<2>(StressScheme::midpoint, true), 1e-3); }
TEST(ElementEnergy, MidpointIsNot3d) { EXPECT_GT(energy_identity_error<3>(StressScheme::midpoint, true), 1e-3); }

// Every law of the catalog (svk through its closed form, the others
// through S, ℂ and the discrete gradient): the element force and tangent
// by the Taylor test, and the energy identity, to the same bounds.
TEST(ElementTangent, EveryLaw) {
  for (const auto& c : material::test::law_cases()) {
    const auto law = material::test::make(c);
    SCOPED_TRACE(c.model);
    for (StressScheme scheme : {StressScheme::conserving, StressScheme::midpoint}) {
      check_tangent<2>(scheme, *law, c.model.c_str());
      check_tangent<3>(scheme, *law, c.model.c_str());
    }
  }
}

TEST(ElementEnergy, ConservingIsExactForEveryLaw) {
  for (const auto& c : material::test::law_cases()) {
    const auto law = material::test::make(c);
    EXPECT_LT(energy_identity_error<2>(StressScheme::conserving, true, *law, c.model.c_str()), 1e-12) << c.model;
    EXPECT_LT(energy_identity_error<3>(StressScheme::conserving, true, *law, c.model.c_str()), 1e-12) << c.model;
    EXPECT_GT(energy_identity_error<3>(StressScheme::midpoint, true, *law, c.model.c_str()), 1e-3) << c.model;
  }
}

TEST(Simplex, GradientsReproduceLinearFields) {
  std::mt19937 rng(1);
  const NodeMatrix<3> X = test::random_reference_cell<3>(rng, 2.0);
  const SimplexGeometry<3> g = simplex_geometry<3>(X, 1.0);
  Mat3 A;
  A << 1, 2, 3, -1, 0.5, 0.25, 4, -2, 1;
  EXPECT_LT((deformation_gradient<3>(A * X, g) - A).norm(), 1e-12);
  EXPECT_LT(g.grad.rowwise().sum().norm(), 1e-12);
  EXPECT_GT(g.volume, 0.0);
}

TEST(Simplex, AreaTimesThicknessIn2d) {
  NodeMatrix<2> X;
  X << 0, 2, 0, 0, 0, 3;
  EXPECT_DOUBLE_EQ(simplex_geometry<2>(X, 0.5).volume, 1.5);
  NodeMatrix<2> flipped = X;
  flipped.col(1).swap(flipped.col(2));
  EXPECT_LT(signed_measure<2>(flipped), 0.0);
}

TEST(Simplex, MassTotals) {
  for (bool lumped : {false, true}) {
    EXPECT_NEAR(element_mass<3>(2500.0, 0.2, lumped).sum(), 500.0, 1e-10);
    EXPECT_NEAR(element_mass<2>(1000.0, 0.3, lumped).sum(), 300.0, 1e-10);
  }
  // Consistent mass integrates N_A N_B exactly: ∫N_0² = 2V/((D+1)(D+2)).
  EXPECT_NEAR(element_mass<3>(1.0, 1.0, false)(0, 0), 2.0 / 20.0, 1e-15);
  EXPECT_NEAR(element_mass<2>(1.0, 1.0, false)(0, 1), 1.0 / 12.0, 1e-15);
}

}  // namespace
}  // namespace conserve::fem
