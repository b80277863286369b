// The Taylor test itself (support/taylor.hpp) on f(x) = sin x componentwise:
// order 2 with its exact Jacobian diag(cos x), order 1 with the Jacobian
// perturbed (the negative control: the test can fail); and an affine f's
// remainder within round-off with its matrix, order 1 above it with the
// matrix perturbed.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "support/taylor.hpp"

namespace conserve::test {
namespace {

// A Jacobian error δ shows as order 1 at the steps h where δ h is above
// both the remainder's h² term and the round-off floor. With the floor at
// 16 ε |f| (sin's own round-off) δ = 1e-6 does; with the default floor,
// 1e4 ε |f| (the tests' margin for assembled round-off), the same steps
// see δ from about 1e-5.
TEST(TaylorOrder, TwoForTheExactJacobianOneForAPerturbedOne) {
  std::mt19937 rng(1);
  const Eigen::VectorXd x = 3.0 * random_direction(rng, 6), d = random_direction(rng, 6);
  auto f = [](const Eigen::VectorXd& v) { return Eigen::VectorXd(v.array().sin()); };
  const Eigen::VectorXd Jd = x.array().cos() * d.array();
  for (const double floor_factor : {16.0, 1e4}) {
    const TaylorOrder exact = taylor_order(f, x, d, Jd, 1e-4, 12, floor_factor);
    const double error = floor_factor < 100.0 ? 1e-6 : 1e-5;
    const TaylorOrder perturbed = taylor_order(f, x, d, Jd + error * d, 1e-4, 12, floor_factor);
    std::printf("[ measured ] sin, floor %g ε |f|: exact %s; Jacobian + %.0e: %s\n", floor_factor,
                describe(exact).c_str(), error, describe(perturbed).c_str());
    expect_second_order(exact, "exact");
    EXPECT_GE(perturbed.pairs, 3);
    EXPECT_NEAR(perturbed.order, 1.0, 0.1) << "perturbed: " << describe(perturbed);
  }
}

// expect_exact's f: the remainder with the exact matrix is round-off at
// every step; a matrix wrong by a relative 1e-9 leaves h |δA d| above the
// floor, of order 1.
TEST(TaylorOrder, AnAffineMapsRemainderIsRoundOff) {
  std::mt19937 rng(2);
  Eigen::MatrixXd A(5, 5);
  for (int j = 0; j < 5; ++j) A.col(j) = 1e3 * random_direction(rng, 5);
  const Eigen::VectorXd x = random_direction(rng, 5), d = random_direction(rng, 5);
  auto f = [&](const Eigen::VectorXd& v) { return Eigen::VectorXd(A * v); };
  const TaylorOrder exact = taylor_order(f, x, d, A * d, 1.0);
  const TaylorOrder perturbed = taylor_order(f, x, d, (A * d).array() * (1.0 + 1e-9), 1.0);
  std::printf("[ measured ] affine: exact %s; Jacobian × (1 + 1e-9): %s\n", describe(exact).c_str(),
              describe(perturbed).c_str());
  expect_exact(exact, "exact");
  EXPECT_GT(largest_remainder(perturbed), 1.0);
  EXPECT_NEAR(perturbed.order, 1.0, 0.1) << describe(perturbed);
}

}  // namespace
}  // namespace conserve::test
