// The zero-work force directions (contact/elimination/zero_work.hpp): no work over the
// step, no resultant, and the slip rows of a frictionless constraint keep
// their rank when the direction turns tangential.
#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <cmath>
#include <cstdio>
#include <Eigen/Geometry>

#include "contact/elimination/zero_work.hpp"

namespace conserve::contact {
namespace {

using Nodes3 = zero_work::Nodes<3, double>;

// A slave pushed straight out of a facet that does not move: the only
// non-rigid motion is the push-out itself, so the zero-work direction on
// the slave is exactly tangential (ā_s·n = 0: zero_work.hpp's ā = a + βw
// with w the push-out's non-rigid part).
struct PushOut {
  Nodes3 x, dx;
  PushOut() {
    x << 0.3, 0.0, 1.0, 0.0,  //
        0.3, 0.0, 0.0, 1.0,   //
        0.0, 0.0, 0.0, 0.0;
    dx.setZero();
    dx(2, 0) = 1e-3;  // the slave moves out along the facet's normal +z
  }
};

TEST(ZeroWork, FrictionlessDirectionDoesNoWorkAndHasNoResultant) {
  PushOut p;
  p.dx.col(0) += Eigen::Vector3d(2e-3, -1e-3, 0.0);  // and slides
  p.dx.col(2) += Eigen::Vector3d(0.0, 0.0, 1e-4);    // a facet node moves
  zero_work::Plane<3, double> mid;
  const Nodes3 abar = zero_work::frictionless_direction<3, double>(p.x, p.dx, mid);
  const double work = abar.cwiseProduct(p.dx).sum();
  EXPECT_LT(std::abs(work), 1e-18);
  EXPECT_LT(abar.rowwise().sum().norm(), 1e-14);
  EXPECT_GT(abar.col(0).dot(mid.normal), 0.5);  // not the push-out alone: still mostly normal
}

TEST(ZeroWork, SlipRowsKeepTheirRankWhenTheDirectionTurnsTangential) {
  const PushOut p;
  zero_work::Plane<3, double> mid;
  const Nodes3 abar = zero_work::frictionless_direction<3, double>(p.x, p.dx, mid);
  const Eigen::Vector3d as = abar.col(0);
  EXPECT_LT(std::abs(as.dot(mid.normal)), 1e-12 * as.norm());  // tangential
  const auto t = zero_work::frictionless_test<3, double>(p.x, p.dx);
  const Eigen::JacobiSVD<Eigen::Matrix<double, 3, 2>> svd(t.slip);
  std::printf("[ measured ] slip rows' singular values with ā_s ⟂ n: %.3f %.3f\n", svd.singularValues()(0),
              svd.singularValues()(1));
  EXPECT_GT(svd.singularValues()(1), 0.5);  // rank 2 (the tangents have length 1)
  EXPECT_LT((t.slip.transpose() * as).norm(), 1e-14 * as.norm());  // and orthogonal to ā_s
  // Negative control: the tangents projected orthogonally to ā_s (the rows
  // used until 2026-11-24) lose a rank here.
  Eigen::Matrix<double, 3, 2> projected = mid.tangents;
  for (int j = 0; j < 2; ++j) projected.col(j) -= (as.dot(projected.col(j)) / as.squaredNorm()) * as;
  const Eigen::JacobiSVD<Eigen::Matrix<double, 3, 2>> old_rows(projected);
  EXPECT_LT(old_rows.singularValues()(1), 1e-12);
}

TEST(ZeroWork, SlipRowsAreTheTangentsWhenTheDirectionIsTheNormal) {
  PushOut p;
  p.dx.setZero();
  p.dx.row(0).setConstant(1e-3);  // a translation: ā = a
  const auto t = zero_work::frictionless_test<3, double>(p.x, p.dx);
  zero_work::Plane<3, double> mid = zero_work::project_on_plane<3, double>(p.x.col(0), p.x.rightCols<3>());
  EXPECT_LT((t.slip - mid.tangents).norm(), 1e-15);  // the paper's τ (56)
}

// Coulomb friction on a slipping slave (zero_work::friction_direction):
// a general step of a slave 0.2 above a tilted, stretching facet.
template <int D>
struct Slipping {
  zero_work::Nodes<D, double> x_n, x, dx;
  Slipping() {
    if constexpr (D == 3) {
      x_n << 0.35, 0.0, 1.0, 0.1,  //
          0.25, 0.0, 0.1, 1.0,     //
          0.2, 0.0, 0.05, -0.1;
    } else {
      x_n << 0.35, 0.0, 1.0,  //
          0.2, 0.0, 0.1;
    }
    dx.setZero();
    dx.col(0).setConstant(2e-3);
    dx(0, 0) = 5e-3;
    dx.col(1).setConstant(-1e-3);
    dx(D - 1, D) = 7e-4;
    x = x_n + dx;
  }
};

/// The mid-point rule's discrete rigid motion x_n → R x_n + c as
/// displacements.
template <int D>
zero_work::Nodes<D, double> rigid_step(const zero_work::Nodes<D, double>& x_n, double angle) {
  Eigen::Matrix<double, D, D> R = Eigen::Matrix<double, D, D>::Identity();
  if constexpr (D == 3) {
    R = Eigen::AngleAxisd(angle, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  } else {
    R << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
  }
  return ((R * x_n).colwise() + Eigen::Matrix<double, D, 1>::Constant(0.3)) - x_n;
}

template <int D>
Eigen::Vector3d moment(const zero_work::Nodes<D, double>& y, const zero_work::Nodes<D, double>& f) {
  Eigen::Vector3d m = Eigen::Vector3d::Zero();
  for (int a = 0; a <= D; ++a) {
    Eigen::Vector3d y3 = Eigen::Vector3d::Zero(), f3 = Eigen::Vector3d::Zero();
    y3.head<D>() = y.col(a);
    f3.head<D>() = f.col(a);
    m += y3.cross(f3);
  }
  return m;
}

template <int D>
void friction_keeps_momenta_and_dissipates() {
  const Slipping<D> p;
  const double eps = 1e-6;
  double slip = 0.0;
  const zero_work::Nodes<D, double> phi = zero_work::friction_direction<D, double>(p.x, p.dx, eps, slip);
  const zero_work::Nodes<D, double> y = p.x - 0.5 * p.dx;
  EXPECT_GT(slip, 1e-3);
  EXPECT_LT(phi.rowwise().sum().norm(), 1e-15);  // no resultant: L
  EXPECT_LT(moment<D>(y, phi).norm(), 1e-15);    // no moment about the mid-point positions: J
  EXPECT_NEAR(phi.col(0).norm(), slip / std::sqrt(slip * slip + eps * eps), 1e-15);  // unit on the slave
  const double work = phi.cwiseProduct(p.dx).sum();
  EXPECT_NEAR(work, -slip * slip / std::sqrt(slip * slip + eps * eps), 1e-17);  // −|Δs|: dissipation
  // A superposed rigid motion of the mid-point rule changes neither the slip nor the work.
  const zero_work::Nodes<D, double> rigid = rigid_step<D>(p.x_n, 0.4);
  double rotated = 0.0;
  const zero_work::Nodes<D, double> phi_rigid =
      zero_work::friction_direction<D, double>(p.x_n + rigid, rigid, eps, rotated);
  EXPECT_LT(rotated, 1e-15);  // a rigid motion does not slip, although the slave is 0.2 off its facet
  EXPECT_LT(std::abs(phi_rigid.cwiseProduct(rigid).sum()), 1e-15);
  // Without the facet's rotation term the relative motion of a slave off
  // its facet would count a rigid rotation as slip (negative control).
  const zero_work::Nodes<D, double> y_rigid = p.x_n + 0.5 * rigid;
  const zero_work::Plane<D, double> mid =
      zero_work::project_on_plane<D, double>(y_rigid.col(0), y_rigid.template rightCols<D>());
  Eigen::Matrix<double, D, 1> relative = rigid.col(0);
  const Eigen::Matrix<double, D, 1> N = zero_work::shape<D, double>(mid.xi);
  for (int b = 0; b < D; ++b) relative -= N(b) * rigid.col(b + 1);
  EXPECT_GT((relative - mid.normal * mid.normal.dot(relative)).norm(), 1e-2);
}

TEST(ZeroWork, FrictionHasNoResultantNorMomentAndDissipatesItsSlip3d) { friction_keeps_momenta_and_dissipates<3>(); }
TEST(ZeroWork, FrictionHasNoResultantNorMomentAndDissipatesItsSlip2d) { friction_keeps_momenta_and_dissipates<2>(); }

// Stick with the slave held off its facet (γ = 0.2): the test map A takes
// the facet's displacement to the slave's (no work), its blocks sum to 1
// (no resultant) and the slave's force f with the master's −A_bᵀ f has no
// moment about the mid-point positions (J), for a deforming facet and for
// a rigid one (a rigid body's, where the correction along the non-rigid
// motion must not divide round-off by round-off). Negative control: the
// paper's N(ξ̄) ⊗ 1 has the moment γ n × f.
template <int D>
void stick_test_keeps_momenta() {
  const double gamma = 0.2;
  Xi<D> xi;
  xi.setConstant(0.3);
  const Slipping<D> p;
  const zero_work::Facet<D, double> xm_n = p.x_n.template rightCols<D>();
  for (const bool rigid : {false, true}) {
    const zero_work::Facet<D, double> dxm =
        rigid ? zero_work::Facet<D, double>(rigid_step<D>(p.x_n, 0.4).template rightCols<D>())
              : zero_work::Facet<D, double>(p.dx.template rightCols<D>());
    const zero_work::Facet<D, double> xm = xm_n + dxm;
    const Vec<D> xs_n = zero_work::stick_position<D, double>(xm_n, xi, gamma);
    const Vec<D> dxs = zero_work::stick_position<D, double>(xm, xi, gamma) - xs_n;
    const zero_work::FacetJacobian<D, double> A =
        zero_work::stick_test<D, double>(xm, dxm, xm_n, Vec<D>::Zero(), xi, gamma);
    ASSERT_TRUE(A.allFinite());
    EXPECT_LT((A * dxm.reshaped() - dxs).norm(), 1e-14) << "rigid " << rigid;  // no work: dxs is 1e-3, positions 1
    Eigen::Matrix<double, D, D> sum = Eigen::Matrix<double, D, D>::Zero();
    for (int b = 0; b < D; ++b) sum += A.template middleCols<D>(b * D);
    EXPECT_LT((sum - Eigen::Matrix<double, D, D>::Identity()).norm(), 1e-13) << "rigid " << rigid;  // L
    zero_work::Nodes<D, double> y, f, f_paper;
    y.col(0) = xs_n + 0.5 * dxs;
    y.template rightCols<D>() = xm - 0.5 * dxm;
    const Vec<D> force = Vec<D>::LinSpaced(1.0, 2.0);
    f.col(0) = f_paper.col(0) = force;
    const Vec<D> N = zero_work::shape<D, double>(xi);
    for (int b = 0; b < D; ++b) {
      f.col(b + 1) = -A.template middleCols<D>(b * D).transpose() * force;
      f_paper.col(b + 1) = -N(b) * force;
    }
    std::printf("[ measured ] %dD stick map, %s facet: moment %.1e (paper's map %.1e), |Σ A_b − 1| %.1e, work %.1e\n",
                D, rigid ? "rigid" : "deforming", moment<D>(y, f).norm(), moment<D>(y, f_paper).norm(),
                (sum - Eigen::Matrix<double, D, D>::Identity()).norm(), (A * dxm.reshaped() - dxs).norm());
    EXPECT_LT(moment<D>(y, f).norm(), 1e-12) << "rigid " << rigid;  // J (the old map: 1e-7 to 1e-2)
    EXPECT_GT(moment<D>(y, f_paper).norm(), 1e-2) << "rigid " << rigid;
  }
}

TEST(ZeroWork, StickTestMapKeepsMomentaOffTheFacet3d) { stick_test_keeps_momenta<3>(); }
TEST(ZeroWork, StickTestMapKeepsMomentaOffTheFacet2d) { stick_test_keeps_momenta<2>(); }

// The test columns with friction: Wᵀg = 0 for g = λ ā + μ f_N φ, f_N = n·g_s.
template <int D>
void friction_test_columns_hold_the_cone() {
  const Slipping<D> p;
  const double mu = 0.4, eps = 1e-6, lambda = 3.0;
  zero_work::Plane<D, double> mid;
  const zero_work::Nodes<D, double> abar = zero_work::frictionless_direction<D, double>(p.x, p.dx, mid);
  double slip = 0.0;
  const zero_work::Nodes<D, double> phi = zero_work::friction_direction<D, double>(p.x, p.dx, eps, slip);
  const double f_n = lambda * mid.normal.dot(abar.col(0));
  const zero_work::Nodes<D, double> g = lambda * abar + mu * f_n * phi;
  EXPECT_NEAR(mid.normal.dot(g.col(0)), f_n, 1e-14);  // friction has no normal part on the slave
  const auto t = zero_work::frictionless_test<D, double>(p.x, p.dx, true, mu, eps);
  for (int j = 0; j < D - 1; ++j) EXPECT_LT(std::abs(t.slip.col(j).dot(g.col(0))), 1e-14);
  for (int b = 0; b < D; ++b)
    for (int i = 0; i < D; ++i) EXPECT_LT(std::abs(g(i, b + 1) + t.master.col(b * D + i).dot(g.col(0))), 1e-14);
  // The same force is not balanced by the frictionless columns (negative control).
  const auto plain = zero_work::frictionless_test<D, double>(p.x, p.dx);
  double off = 0.0;
  for (int j = 0; j < D - 1; ++j) off = std::max(off, std::abs(plain.slip.col(j).dot(g.col(0))));
  EXPECT_GT(off, 0.1);
  // Its work over the step is the dissipation μ f_N |Δs| (ā does none).
  EXPECT_NEAR(g.cwiseProduct(p.dx).sum(), -mu * f_n * slip * slip / std::sqrt(slip * slip + eps * eps), 1e-16);
}

TEST(ZeroWork, FrictionTestColumnsBalanceAForceOnTheCone3d) { friction_test_columns_hold_the_cone<3>(); }
TEST(ZeroWork, FrictionTestColumnsBalanceAForceOnTheCone2d) { friction_test_columns_hold_the_cone<2>(); }

}  // namespace
}  // namespace conserve::contact
