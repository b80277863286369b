// The direct-elimination map T (ALGORITHM.md §4): Δu_s = N Δu_m (35) or
// N Δu_m + τ Δξ (49), chains by substitution, cycles refused, the reduced
// residual (41) and the dummy diagonal β = tr(K_ss)/D (44).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <random>

#include "contact/elimination.hpp"
#include "core/error.hpp"

namespace conserve::contact {
namespace {

Constraint<3> stick(int slave, std::array<int, 3> master, double xi, double eta) {
  Constraint<3> c;
  c.slave = slave;
  c.master = master;
  c.xi << xi, eta;
  c.kind = Kind::stick;
  return c;
}

Eigen::VectorXd random_vector(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::VectorXd v(n);
  for (int i = 0; i < n; ++i) v[i] = u(rng);
  return v;
}

TEST(Elimination, StickSlaveFollowsItsMasterPoint) {
  const Elimination<3> e(8, {stick(0, {1, 2, 3}, 0.2, 0.3)});
  const Eigen::VectorXd q = random_vector(24, 1);
  Eigen::VectorXd du;
  e.expand(q, du);
  const Vec3 expected = 0.5 * q.segment<3>(3) + 0.2 * q.segment<3>(6) + 0.3 * q.segment<3>(9);  // (35)
  EXPECT_LT((du.segment<3>(0) - expected).norm(), 1e-15);
  EXPECT_EQ((du.tail(15) - q.tail(15)).norm(), 0.0);  // free nodes unchanged
}

TEST(Elimination, FrictionlessSlaveSlidesAlongTangents) {
  Constraint<3> c = stick(0, {1, 2, 3}, 0.2, 0.3);
  c.kind = Kind::frictionless;
  c.tangents << 1, 0, 0, 1, 0, 0;  // τ_ξ = x̂, τ_η = ŷ
  const Elimination<3> e(4, {c});
  const Eigen::VectorXd q = random_vector(12, 2);
  Eigen::VectorXd du;
  e.expand(q, du);
  const Vec3 expected = 0.5 * q.segment<3>(3) + 0.2 * q.segment<3>(6) + 0.3 * q.segment<3>(9) +
                        Vec3(q[0], q[1], 0.0);  // (49): slave slots 0, 1 carry Δξ, Δη; slot 2 is the dummy
  EXPECT_LT((du.segment<3>(0) - expected).norm(), 1e-15);
}

TEST(Elimination, ChainsAreComposed) {
  // Node 0 is a slave on (1, 2, 3); node 1 is itself a slave on (4, 5, 6).
  const Elimination<3> e(7, {stick(0, {1, 2, 3}, 0.25, 0.25), stick(1, {4, 5, 6}, 0.1, 0.6)});
  const Eigen::VectorXd q = random_vector(21, 3);
  Eigen::VectorXd du;
  e.expand(q, du);
  const Vec3 du1 = 0.3 * q.segment<3>(12) + 0.1 * q.segment<3>(15) + 0.6 * q.segment<3>(18);
  const Vec3 du0 = 0.5 * du1 + 0.25 * q.segment<3>(6) + 0.25 * q.segment<3>(9);
  EXPECT_LT((du.segment<3>(3) - du1).norm(), 1e-15);
  EXPECT_LT((du.segment<3>(0) - du0).norm(), 1e-15);
}

TEST(Elimination, CyclesAreRefused) {
  EXPECT_THAT([] { Elimination<3>(7, {stick(0, {1, 2, 3}, 0.2, 0.2), stick(1, {0, 5, 6}, 0.2, 0.2)}); },
              ::testing::ThrowsMessage<SolverError>(::testing::HasSubstr("cycle")));
  EXPECT_THROW(Elimination<3>(7, {stick(0, {1, 2, 3}, 0.2, 0.2), stick(0, {4, 5, 6}, 0.2, 0.2)}), SolverError);
}

// (41): slave rows vanish, master rows get Nᵀ g_s, the others are untouched.
TEST(Elimination, ReducedResidualIsPaperEquation41) {
  const Elimination<3> e(5, {stick(0, {1, 2, 3}, 0.2, 0.3)});
  const Eigen::VectorXd g = random_vector(15, 4);
  Eigen::VectorXd r;
  e.reduce_residual(g, r);
  EXPECT_EQ(r.segment<3>(0).norm(), 0.0);
  const double N[3] = {0.5, 0.2, 0.3};
  for (int a = 0; a < 3; ++a)
    EXPECT_LT((r.segment<3>(3 * (a + 1)) - g.segment<3>(3 * (a + 1)) - N[a] * g.segment<3>(0)).norm(), 1e-15);
  EXPECT_EQ((r.segment<3>(12) - g.segment<3>(12)).norm(), 0.0);
}

// (43)–(44): K_r = Tᵀ K T with β = tr(K_ss)/D on the slave's dummy diagonal.
TEST(Elimination, ReducedTangentHasBetaOnDummyRows) {
  const Elimination<3> e(5, {stick(0, {1, 2, 3}, 0.2, 0.3)});
  Eigen::MatrixXd Kd = Eigen::MatrixXd::Random(15, 15) + 10.0 * Eigen::MatrixXd::Identity(15, 15);
  const SparseMatrix K = Kd.sparseView();
  SparseMatrix Kr;
  e.reduce_tangent(K, Eigen::VectorXd::Zero(15), Kr);
  const Eigen::MatrixXd T(e.map());
  const Eigen::MatrixXd expected = T.transpose() * Kd * T;
  const double beta = (Kd(0, 0) + Kd(1, 1) + Kd(2, 2)) / 3.0;
  Eigen::MatrixXd Kr_d(Kr);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(Kr_d(i, i), beta, 1e-14);
  Kr_d.topLeftCorner<3, 3>().setZero();
  EXPECT_LT((Kr_d - expected).norm(), 1e-12);
  EXPECT_EQ(Kr.rows(), K.rows());  // the number of equations stays the same
}

}  // namespace
}  // namespace conserve::contact
