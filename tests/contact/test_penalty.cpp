// The penalty force of one slave–facet coupling (contact/penalty/
// penalty_force.hpp): its work over a step is the potential's change to
// round-off (the mid-point force, the negative control, misses it), it has
// no resultant and no moment about the mid-point, it is along the normal on a fixed
// facet, and its derivative, taken by automatic differentiation, passes
// the Taylor test (support/taylor.hpp).
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <unsupported/Eigen/AutoDiff>

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstdio>
#include <random>
#include <string>

#include "contact/facet.hpp"
#include "contact/penalty/penalty_force.hpp"
#include "support/taylor.hpp"

namespace conserve::contact::penalty {
namespace {

template <int D>
using Nodes = CouplingNodes<D, double>;

/// A unit facet at the origin (normal +z or +y) and a slave above it at
/// height `height`, off its centre; randomly perturbed by `jitter`.
template <int D>
Nodes<D> coupling(double height, double jitter, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Nodes<D> y = Nodes<D>::Zero();
  if constexpr (D == 2) {
    y.col(1) << 1.0, 0.0;  // facet from (1, 0) to (0, 0): outward normal +y
    y.col(2) << 0.0, 0.0;
    y.col(0) << 0.4, height;
  } else {
    y.col(1) << 0.0, 0.0, 0.0;
    y.col(2) << 1.0, 0.0, 0.0;
    y.col(3) << 0.0, 1.0, 0.0;
    y.col(0) << 0.3, 0.25, height;
  }
  for (int a = 0; a <= D; ++a)
    for (int i = 0; i < D; ++i) y(i, a) += jitter * u(rng);
  return y;
}

template <int D>
double work(const Nodes<D>& f, const Nodes<D>& y_n, const Nodes<D>& y_1) {
  return f.cwiseProduct(y_1 - y_n).sum();
}

template <int D>
Eigen::Matrix<double, 3, 1> moment(const Nodes<D>& f, const Nodes<D>& y_mid) {
  Eigen::Matrix<double, 3, 1> m = Eigen::Matrix<double, 3, 1>::Zero();
  for (int a = 0; a <= D; ++a) {
    Eigen::Matrix<double, 3, 1> x = Eigen::Matrix<double, 3, 1>::Zero(), g = x;
    x.head<D>() = y_mid.col(a);
    g.head<D>() = f.col(a);
    m += x.cross(g);
  }
  return m;
}

/// A stick anchor at ξ = (0.2[, 0.3]).
template <int D>
Eigen::Matrix<double, D - 1, 1> anchor_at() {
  Eigen::Matrix<double, D - 1, 1> xi;
  xi.setConstant(0.2);
  if constexpr (D == 3) xi(1) = 0.3;
  return xi;
}

template <int D>
void check_energy_and_momenta(bool stick) {
  std::mt19937 rng(7 + D + (stick ? 10 : 0));
  const double k = 3.0e5;
  const auto xi0 = anchor_at<D>();
  const Anchor<D> anchor = stick ? &xi0 : nullptr;
  double worst_conserving = 0.0, worst_midpoint = 0.0;
  for (int trial = 0; trial < 40; ++trial) {
    // Both ends behind, crossing in, crossing out; the facet moving and
    // deforming too.
    const double h_n = (trial % 3 == 1) ? 0.05 : -0.04, h_1 = (trial % 3 == 2) ? 0.03 : -0.07;
    const Nodes<D> y_n = coupling<D>(h_n, 0.02, rng), y_1 = coupling<D>(h_1, 0.02, rng);
    const double dphi = penalty_energy<D>(y_1, k, anchor) - penalty_energy<D>(y_n, k, anchor);
    ASSERT_GT(std::abs(dphi), 1.0) << "the step changes the potential";
    const Nodes<D> f = penalty_force<D, double>(y_n, y_1, k, true, anchor);
    const Nodes<D> f_mid = penalty_force<D, double>(y_n, y_1, k, false, anchor);
    const double scale = std::max(penalty_energy<D>(y_1, k, anchor), penalty_energy<D>(y_n, k, anchor));
    worst_conserving = std::max(worst_conserving, std::abs(work<D>(f, y_n, y_1) - dphi) / scale);
    worst_midpoint = std::max(worst_midpoint, std::abs(work<D>(f_mid, y_n, y_1) - dphi) / scale);
    const double force = f.cwiseAbs().maxCoeff();
    ASSERT_GT(force, 0.0);
    EXPECT_LT(f.rowwise().sum().cwiseAbs().maxCoeff(), 1e-12 * force) << "resultant, trial " << trial;
    EXPECT_LT(moment<D>(f, 0.5 * (y_n + y_1)).norm(), 1e-12 * force) << "moment, trial " << trial;
  }
  std::printf("[ measured ] %dD %s: |work − ΔΦ|/Φ at most %.1e (discrete gradient), %.1e (mid-point)\n", D,
              stick ? "stick" : "frictionless", worst_conserving, worst_midpoint);
  EXPECT_LT(worst_conserving, 1e-13);
  EXPECT_GT(worst_midpoint, 1e-4);  // the negative control
}

TEST(PenaltyForce, WorkIsTheChangeOfPotentialWithMomentaKept2d) { check_energy_and_momenta<2>(false); }
TEST(PenaltyForce, WorkIsTheChangeOfPotentialWithMomentaKept3d) { check_energy_and_momenta<3>(false); }
TEST(PenaltyForce, StickWorkIsTheChangeOfPotentialWithMomentaKept2d) { check_energy_and_momenta<2>(true); }
TEST(PenaltyForce, StickWorkIsTheChangeOfPotentialWithMomentaKept3d) { check_energy_and_momenta<3>(true); }

// On a facet that does not move the force on the slave is along the facet's
// normal, however far the slave slides, and the facet's nodes take the
// reaction: frictionless.
template <int D>
void check_normal_on_a_fixed_facet() {
  std::mt19937 rng(11);
  const Nodes<D> y_n = coupling<D>(-0.01, 0.0, rng);
  Nodes<D> y_1 = y_n;
  y_1.col(0)(0) += 0.3;  // slides
  y_1.col(0)(D - 1) -= 0.02;  // and sinks
  const Nodes<D> f = penalty_force<D, double>(y_n, y_1, 1e5, true);
  FacetNodes<D> facet = y_n.template rightCols<D>();
  const Vec<D> n = facet_normal<D>(facet);
  ASSERT_GT(f.col(0).norm(), 0.0);
  EXPECT_LT((f.col(0) - f.col(0).dot(n) * n).norm(), 1e-14 * f.col(0).norm());
  EXPECT_LT(f.col(0).dot(n), 0.0);  // ∂Φ/∂x_s points into the master: the force on the slave pushes it out
}
TEST(PenaltyForce, AlongTheNormalOnAFixedFacet2d) { check_normal_on_a_fixed_facet<2>(); }
TEST(PenaltyForce, AlongTheNormalOnAFixedFacet3d) { check_normal_on_a_fixed_facet<3>(); }

// Φ = ½ k g² with g the gap of the closest-point projection (facet.hpp).
template <int D>
void check_potential_is_half_k_g_squared() {
  std::mt19937 rng(5);
  const Nodes<D> y = coupling<D>(-0.03, 0.02, rng);
  const Projection<D> p = project<D>(y.col(0), FacetNodes<D>(y.template rightCols<D>()));
  ASSERT_LT(p.gap, 0.0);
  EXPECT_NEAR(penalty_energy<D>(y, 2.0e5), 0.5 * 2.0e5 * p.gap * p.gap, 1e-12 * 2.0e5 * p.gap * p.gap);
  EXPECT_EQ(penalty_energy<D>(coupling<D>(0.03, 0.0, rng), 2.0e5), 0.0);
}
TEST(PenaltyForce, PotentialIsHalfKGapSquared2d) { check_potential_is_half_k_g_squared<2>(); }
TEST(PenaltyForce, PotentialIsHalfKGapSquared3d) { check_potential_is_half_k_g_squared<3>(); }

/// y's entries as the unknowns of fixed-size automatic differentiation
/// (entry a D + i: y(i, a)).
template <int D, class Ad>
CouplingNodes<D, Ad> seeded(const Nodes<D>& y) {
  CouplingNodes<D, Ad> y_ad;
  for (int a = 0; a <= D; ++a)
    for (int i = 0; i < D; ++i) y_ad(i, a) = Ad(y(i, a), D * (D + 1), a * D + i);
  return y_ad;
}

/// The derivatives of a force by those unknowns: row a D + i is f(i, a)'s.
template <int D, class Ad>
Eigen::Matrix<double, D*(D + 1), D*(D + 1)> derivative_of(const CouplingNodes<D, Ad>& f) {
  Eigen::Matrix<double, D*(D + 1), D*(D + 1)> K;
  for (int a = 0; a <= D; ++a)
    for (int i = 0; i < D; ++i) K.row(a * D + i) = f(i, a).derivatives().transpose();
  return K;
}

// The derivative by y_{n+1} by automatic differentiation (what the tangent
// assembles, PenaltyMethod::add_force) by the Taylor test of the force
// along random directions (a remainder of order 2, support/taylor.hpp),
// for both forces and both kinds. Behind the facet, a stick spring's
// potential and the gap's add up to ½ k |x_s − x(ξ₀)|², quadratic in y:
// the mid-point force is then linear in y_{n+1}, and its remainder has no
// order but is round-off at every step.
template <int D>
void check_tangent(bool conserving, bool stick) {
  constexpr int N = D * (D + 1);
  using Ad = Eigen::AutoDiffScalar<Eigen::Matrix<double, N, 1>>;
  std::mt19937 rng(13);
  const auto xi0 = anchor_at<D>();
  const Anchor<D> anchor = stick ? &xi0 : nullptr;
  const Nodes<D> y_n = coupling<D>(-0.02, 0.02, rng), y_1 = coupling<D>(-0.05, 0.02, rng);
  const double k = 1e5;
  const Eigen::Matrix<double, N, N> K =
      derivative_of<D, Ad>(penalty_force<D, Ad>(y_n, seeded<D, Ad>(y_1), k, conserving, anchor));
  ASSERT_GT(K.norm(), 1e3) << "the tangent is not zero";
  auto force = [&](const Eigen::VectorXd& y) {
    return Eigen::VectorXd(
        penalty_force<D, double>(y_n, Nodes<D>(y.reshaped(D, D + 1)), k, conserving, anchor).reshaped());
  };
  const std::string what =
      std::string(conserving ? "conserving" : "mid-point") + (stick ? ", stick" : ", frictionless");
  for (int direction = 0; direction < 3; ++direction) {
    const Eigen::VectorXd d = test::random_direction(rng, N);
    const test::TaylorOrder t = test::taylor_order(force, y_1.reshaped(), d, K * d, 1e-3);
    std::printf("[ measured ] penalty force tangent %dD, %s, direction %d: %s\n", D, what.c_str(), direction + 1,
                test::describe(t).c_str());
    if (stick && !conserving) {
      test::expect_exact(t, what);
    } else {
      test::expect_second_order(t, what);
    }
  }
}
TEST(PenaltyForce, TangentMatchesFiniteDifferences2d) {
  for (bool conserving : {true, false})
    for (bool stick : {false, true}) check_tangent<2>(conserving, stick);
}
TEST(PenaltyForce, TangentMatchesFiniteDifferences3d) {
  for (bool conserving : {true, false})
    for (bool stick : {false, true}) check_tangent<3>(conserving, stick);
}

// A Coulomb spring (finite μ): its anchor slips by the return map. Over
// every step the force's work is the potential's change (each end with its
// own anchor) plus the friction's work D ≥ 0 to round-off, with no
// resultant and no moment; a slipping step leaves the spring's mid-point
// stretch at μ g_m (|f_T| = μ f_N), an infinite μ is the stick spring
// bit for bit, and a mid-point force (the negative control) misses the
// balance.
template <int D>
void check_coulomb_balance() {
  std::mt19937 rng(23 + D);
  const double k = 3.0e5, mu = 0.3;
  double worst = 0.0, worst_midpoint = 0.0, largest_d = 0.0;
  int slipped = 0, stuck = 0;
  for (int trial = 0; trial < 60; ++trial) {
    // Slaves sliding far (slip) and little (stick), facets moving and
    // deforming.
    const double h_n = -0.04, h_1 = (trial % 2) ? -0.07 : -0.03;
    const Nodes<D> y_n = coupling<D>(h_n, 0.02, rng);
    Nodes<D> y_1 = coupling<D>(h_1, 0.02, rng);
    if (trial % 3 == 0) y_1.col(0)(0) += 0.3;  // a long slide
    if (trial % 3 == 1) y_1 = y_n + 1e-2 * (y_1 - y_n);  // a short one
    // The anchor near the slave's projection (a short step stays in the
    // cone, 0.005 against μ |g| = 0.012) or further off.
    const Eigen::Matrix<double, D - 1, 1> xi0 =
        projected_xi<D>(y_n) + Eigen::Matrix<double, D - 1, 1>::Constant(trial % 3 == 1 ? 0.004 : 0.05);
    CoulombStep<D, double> step, step_mid;
    const Nodes<D> f = penalty_force<D, double>(y_n, y_1, k, true, &xi0, mu, &step);
    const Nodes<D> f_mid = penalty_force<D, double>(y_n, y_1, k, false, &xi0, mu, &step_mid);
    const double phi_n = penalty_energy<D>(y_n, k, &xi0), phi_1 = penalty_energy<D>(y_1, k, &step.anchor);
    const double scale = std::max({phi_n, phi_1, step.dissipated});
    ASSERT_GT(scale, 1.0);
    worst = std::max(worst, std::abs(work<D>(f, y_n, y_1) - (phi_1 - phi_n) - step.dissipated) / scale);
    const double phi_1_mid = penalty_energy<D>(y_1, k, &step_mid.anchor);
    worst_midpoint = std::max(
        worst_midpoint, std::abs(work<D>(f_mid, y_n, y_1) - (phi_1_mid - phi_n) - step_mid.dissipated) / scale);
    EXPECT_GE(step.dissipated, 0.0) << "trial " << trial;
    const double force = f.cwiseAbs().maxCoeff();
    ASSERT_GT(force, 0.0);
    EXPECT_LT(f.rowwise().sum().cwiseAbs().maxCoeff(), 1e-12 * force) << "resultant, trial " << trial;
    EXPECT_LT(moment<D>(f, 0.5 * (y_n + y_1)).norm(), 1e-12 * force) << "moment, trial " << trial;
    if (step.slips) {
      ++slipped;
      largest_d = std::max(largest_d, step.dissipated);
      EXPECT_GT(step.dissipated, 0.0);
    } else {
      ++stuck;
      EXPECT_EQ(step.dissipated, 0.0);
      EXPECT_EQ(step.anchor, xi0);
      EXPECT_EQ(f, (penalty_force<D, double>(y_n, y_1, k, true, &xi0))) << "a stuck step is the stick spring's";
    }
    // An infinite μ is the stick spring.
    EXPECT_EQ((penalty_force<D, double>(y_n, y_1, k, true, &xi0, std::numeric_limits<double>::infinity())),
              (penalty_force<D, double>(y_n, y_1, k, true, &xi0)));
  }
  std::printf("[ measured ] %dD Coulomb: |work − ΔΦ − D| / scale at most %.1e (discrete gradient), %.1e (mid-point); "
              "%d slipping and %d sticking steps, D up to %.3g J\n",
              D, worst, worst_midpoint, slipped, stuck, largest_d);
  EXPECT_GT(slipped, 10);
  EXPECT_GT(stuck, 10);
  EXPECT_LT(worst, 1e-12);
  EXPECT_GT(worst_midpoint, 1e-4);  // the negative control
}
TEST(PenaltyForce, CoulombWorkIsThePotentialsChangeAndTheDissipation2d) { check_coulomb_balance<2>(); }
TEST(PenaltyForce, CoulombWorkIsThePotentialsChangeAndTheDissipation3d) { check_coulomb_balance<3>(); }

// On a facet that does not move, a slave sliding along it and sinking:
// the force on it has the tangential part μ times the normal part, against
// the slide, in the steps it slips (all but the first, which starts the
// spring from its anchor), crossing into the facet too.
template <int D>
void check_coulomb_cone() {
  std::mt19937 rng(31);
  const double k = 1e5, mu = 0.4;
  Nodes<D> y = coupling<D>(0.004, 0.0, rng);
  const FacetNodes<D> facet = y.template rightCols<D>();
  const Vec<D> n = facet_normal<D>(facet);
  Eigen::Matrix<double, D - 1, 1> xi0 = projected_xi<D>(y);
  int slipped = 0;
  double worst = 0.0;
  for (int step = 0; step < 8; ++step) {
    Nodes<D> y_1 = y;
    y_1.col(0)(0) += 0.01;       // slides along x
    y_1.col(0)(D - 1) -= 0.002;  // and sinks (in at the second step)
    CoulombStep<D, double> slip;
    const Nodes<D> f = penalty_force<D, double>(y, y_1, k, true, &xi0, mu, &slip);
    const double normal = -f.col(0).dot(n);  // ∂Φ/∂x_s points into the master
    const Vec<D> tangential = f.col(0) + normal * n;
    if (slip.slips && normal > 0.0) {
      ++slipped;
      worst = std::max(worst, std::abs(tangential.norm() / normal - mu));
      EXPECT_GT(tangential(0), 0.0) << "∂Φ/∂x_s along the slide: the force on the slave is against it";
    }
    xi0 = slip.anchor;
    y = y_1;
  }
  std::printf("[ measured ] %dD Coulomb spring on a fixed facet: |f_T| / f_N − μ at most %.1e over %d slipping steps\n",
              D, worst, slipped);
  EXPECT_GE(slipped, 6);
  EXPECT_LT(worst, 1e-11);
}
TEST(PenaltyForce, CoulombForceOnAFixedFacetIsOnTheCone2d) { check_coulomb_cone<2>(); }
TEST(PenaltyForce, CoulombForceOnAFixedFacetIsOnTheCone3d) { check_coulomb_cone<3>(); }

// The Coulomb force's derivative (the return map's included) by the
// Taylor test, slipping and sticking.
template <int D>
void check_coulomb_tangent() {
  constexpr int N = D * (D + 1);
  using Ad = Eigen::AutoDiffScalar<Eigen::Matrix<double, N, 1>>;
  std::mt19937 rng(29);
  const double k = 1e5;
  for (const bool slide : {true, false}) {
    const Nodes<D> y_n = coupling<D>(-0.04, 0.02, rng);
    Nodes<D> y_1 = coupling<D>(-0.05, 0.02, rng);
    if (slide) y_1.col(0)(0) += 0.3;
    else y_1 = y_n + 1e-2 * (y_1 - y_n);
    const Eigen::Matrix<double, D - 1, 1> xi0 =
        projected_xi<D>(y_n) + Eigen::Matrix<double, D - 1, 1>::Constant(slide ? 0.05 : 0.004);
    CoulombStep<D, Ad> step;
    const Eigen::Matrix<double, N, N> K =
        derivative_of<D, Ad>(penalty_force<D, Ad>(y_n, seeded<D, Ad>(y_1), k, true, &xi0, 0.3, &step));
    ASSERT_EQ(step.slips, slide);
    ASSERT_GT(K.norm(), 1e3) << "the tangent is not zero";
    auto force = [&](const Eigen::VectorXd& y) {
      return Eigen::VectorXd(
          penalty_force<D, double>(y_n, Nodes<D>(y.reshaped(D, D + 1)), k, true, &xi0, 0.3).reshaped());
    };
    for (int direction = 0; direction < 3; ++direction) {
      const Eigen::VectorXd d = test::random_direction(rng, N);
      const test::TaylorOrder t = test::taylor_order(force, y_1.reshaped(), d, K * d, 1e-3);
      std::printf("[ measured ] Coulomb penalty force tangent %dD, %s, direction %d: %s\n", D,
                  slide ? "slipping" : "sticking", direction + 1, test::describe(t).c_str());
      test::expect_second_order(t, slide ? "slipping" : "sticking");
    }
  }
}
TEST(PenaltyForce, CoulombTangentMatchesFiniteDifferences2d) { check_coulomb_tangent<2>(); }
TEST(PenaltyForce, CoulombTangentMatchesFiniteDifferences3d) { check_coulomb_tangent<3>(); }

}  // namespace
}  // namespace conserve::contact::penalty

namespace conserve::contact::penalty {
namespace {

// Off a facet's face the potential is ½ k d² to the nearest edge or vertex
// (point_potential): its gradient is the derivative (the nearest point's
// parameter held, the envelope theorem) by the Taylor test of the
// potential along a random direction of (s, a, b), and through automatic
// differentiation with a dynamic number of unknowns (the switching steps'
// tangent) the slave's row matches the closed form.
TEST(PenaltyForce, EdgeAndVertexPotentialsDifferentiate) {
  using Ad = Eigen::AutoDiffScalar<Eigen::VectorXd>;
  const Eigen::Vector3d s(0.3, -0.2, -0.05), a(0.0, 0.0, 0.0), b(1.0, 0.1, 0.0);
  const double k = 2e5;
  std::mt19937 rng(17);
  for (const bool edge : {true, false}) {
    Eigen::Matrix<double, 3, 3> grad;
    const double phi = point_potential<3, double>(s, a, edge ? &b : nullptr, k, &grad);
    ASSERT_GT(phi, 0.0);
    auto potential = [&](const Eigen::VectorXd& y) {
      const Eigen::Vector3d yb = y.segment<3>(6);
      return Eigen::VectorXd::Constant(
          1, point_potential<3, double>(y.segment<3>(0), y.segment<3>(3), edge ? &yb : nullptr, k));
    };
    Eigen::VectorXd y(9);
    y << s, a, b;
    const Eigen::VectorXd d = test::random_direction(rng, 9);
    const test::TaylorOrder t =
        test::taylor_order(potential, y, d, Eigen::VectorXd::Constant(1, grad.reshaped().dot(d)), 1e-3);
    std::printf("[ measured ] %s potential's gradient: %s\n", edge ? "edge" : "vertex", test::describe(t).c_str());
    test::expect_second_order(t, edge ? "edge" : "vertex");
    // The gradient's own derivative by automatic differentiation.
    Eigen::Matrix<Ad, 3, 1> s_ad, a_ad, b_ad;
    for (int i = 0; i < 3; ++i) {
      s_ad(i) = Ad(s(i), 9, i);
      a_ad(i) = Ad(a(i), 9, 3 + i);
      b_ad(i) = Ad(b(i), 9, 6 + i);
    }
    Eigen::Matrix<Ad, 3, 3> g_ad;
    point_potential<3, Ad>(s_ad, a_ad, edge ? &b_ad : nullptr, k, &g_ad);
    const Eigen::Matrix<double, 3, 1> slave_row = g_ad(0, 0).derivatives().head<3>();
    EXPECT_NEAR(slave_row(0), edge ? k * (1.0 - std::pow(b.normalized()(0), 2)) : k, 1e-6 * k);
  }
}

}  // namespace
}  // namespace conserve::contact::penalty
