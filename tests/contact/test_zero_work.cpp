// The zero-work force directions (contact/elimination/zero_work.hpp): no work over the
// step, no resultant, and the slip rows of a frictionless constraint keep
// their rank when the direction turns tangential.
#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <cstdio>

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

}  // namespace
}  // namespace conserve::contact
