#include <gtest/gtest.h>

#include <limits>

#include <random>

#include "core/error.hpp"
#include "solver/newton.hpp"

namespace conserve::solver {
namespace {

/// A random non-symmetric, diagonally dominant tridiagonal-plus matrix.
SparseMatrix random_matrix(int n, int band, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, i, 2.0 * band + 1.0);
    for (int k = 1; k <= band; ++k)
      if (i + k < n) t.emplace_back(i, i + k, u(rng)), t.emplace_back(i + k, i, u(rng));
  }
  SparseMatrix A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

TEST(LinearSolver, SolvesNonSymmetricSystems) {
  const SparseMatrix A = random_matrix(200, 3, 1);
  ASSERT_GT((Eigen::MatrixXd(A) - Eigen::MatrixXd(A).transpose()).norm(), 1.0);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(200, -1.0, 1.0);
  LinearSolver s;
  s.factorize(A);
  Eigen::VectorXd x;
  s.solve(b, x);
  EXPECT_LT((A * x - b).norm(), 1e-12 * b.norm());
}

TEST(LinearSolver, ReusesSymbolicAnalysisWhilePatternIsUnchanged) {
  LinearSolver s;
  SparseMatrix A = random_matrix(100, 2, 1);
  s.factorize(A);
  A.coeffs() *= 1.5;
  s.factorize(A);
  s.factorize(random_matrix(100, 2, 2));  // same pattern, new values
  EXPECT_EQ(s.analyses(), 1);
  s.factorize(random_matrix(100, 3, 2));  // new pattern
  EXPECT_EQ(s.analyses(), 2);
}

TEST(LinearSolver, SingularMatrixIsAClearError) {
  SparseMatrix A(3, 3);
  A.insert(0, 0) = 1.0;
  A.insert(1, 1) = 0.0;
  A.insert(2, 2) = 1.0;
  A.makeCompressed();
  LinearSolver s;
  EXPECT_THROW(s.factorize(A), SolverError);
}

/// r_i(x) = x_i³ + x_i − a_i: a diagonal nonlinear problem.
class CubicProblem final : public NewtonProblem {
 public:
  explicit CubicProblem(int n) : x_(Eigen::VectorXd::Zero(n)), a_(Eigen::VectorXd::LinSpaced(n, 1.0, 5.0)) {
    K_.resize(n, n);
    for (int i = 0; i < n; ++i) K_.insert(i, i) = 1.0;
    K_.makeCompressed();
  }
  void residual(Eigen::VectorXd& r) override {
    r = x_.array().cube() + x_.array() - a_.array();
    floor_ = 8 * 2.2e-16 * (x_.array().cube().abs() + x_.array().abs() + a_.array().abs()).matrix().norm();
  }
  const SparseMatrix& tangent() override {
    for (int i = 0; i < x_.size(); ++i) K_.coeffRef(i, i) = 3.0 * x_[i] * x_[i] + 1.0;
    return K_;
  }
  void update(const Eigen::VectorXd& dx) override { x_ += dx; }
  [[nodiscard]] double force_scale() const override { return a_.norm(); }
  [[nodiscard]] double residual_floor() const override { return floor_; }
  Eigen::VectorXd x_, a_;
  double floor_ = 0.0;
  SparseMatrix K_;
};

TEST(Newton, ConvergesToRoundOff) {
  CubicProblem p(10);
  LinearSolver s;
  const NewtonReport rep = solve_newton(p, s, NewtonSettings{});
  ASSERT_TRUE(rep.converged);
  Eigen::VectorXd r;
  p.residual(r);
  EXPECT_LT(r.norm(), 1e-12 * p.a_.norm());
  EXPECT_LE(rep.iterations, 8);
  // quadratic tail: the last ratios shrink
  const auto& h = rep.residual_norms;
  ASSERT_GE(h.size(), 4u);
  EXPECT_LT(h[h.size() - 2] / h[h.size() - 3], 0.1);
}

TEST(Newton, ReportsNonConvergence) {
  CubicProblem p(10);
  LinearSolver s;
  const NewtonReport rep = solve_newton(p, s, NewtonSettings{.max_iterations = 1});
  EXPECT_FALSE(rep.converged);
  EXPECT_EQ(rep.iterations, 1);
  EXPECT_EQ(rep.failure, "1 iterations were not enough");
}

/// r(x) = x − a with a tangent 1e20 times too stiff: every increment is
/// tiny (1e-20 |r|) and the residual hardly moves, as with a material so
/// stiff that the tangent swamps the inertia (issue 11: young = 1e30).
class StiffTangentProblem final : public NewtonProblem {
 public:
  StiffTangentProblem() : x_(Eigen::VectorXd::Zero(3)), a_(Eigen::VectorXd::Ones(3)) {
    K_.resize(3, 3);
    for (int i = 0; i < 3; ++i) K_.insert(i, i) = 1e20;
    K_.makeCompressed();
  }
  void residual(Eigen::VectorXd& r) override { r = x_ - a_; }
  const SparseMatrix& tangent() override { return K_; }
  void update(const Eigen::VectorXd& dx) override { x_ += dx; }
  [[nodiscard]] double force_scale() const override { return scale_; }
  [[nodiscard]] double residual_floor() const override { return 1e-15; }
  Eigen::VectorXd x_, a_;
  SparseMatrix K_;
  double scale_ = 1.0;
};

// A small increment never ends the iteration: only the residual does.
TEST(Newton, TinyIncrementsDoNotConverge) {
  StiffTangentProblem p;
  LinearSolver s;
  const NewtonReport rep = solve_newton(p, s, NewtonSettings{});
  EXPECT_FALSE(rep.converged);
  EXPECT_EQ(rep.iterations, 20);
  EXPECT_GT(rep.final_residual(), 0.5);
}

// A residual at its round-off floor converges only if that floor is small
// against the force scale.
TEST(Newton, RoundOffFloorMustBeSmallAgainstTheForceScale) {
  StiffTangentProblem p;
  p.a_.setZero();
  p.x_.setConstant(1e-14);  // |r| = 1.7e-14
  LinearSolver s;
  NewtonSettings settings{.max_iterations = 0};
  p.scale_ = 1e-4;  // tolerance 1e-16 < |r|; floor 1e-15 < |r| too: not converged
  EXPECT_FALSE(solve_newton(p, s, settings).converged);
  p.x_.setConstant(4e-16);  // |r| = 6.9e-16: above the tolerance, below the floor 1e-15 ≤ 1e-6 · 1e-4
  const NewtonReport at_floor = solve_newton(p, s, settings);
  EXPECT_TRUE(at_floor.converged) << at_floor.failure;
  p.scale_ = 1e-10;  // the same residual, but the floor is above 1e-6 of the force scale
  const NewtonReport too_stiff = solve_newton(p, s, settings);
  EXPECT_FALSE(too_stiff.converged);
  EXPECT_NE(too_stiff.failure.find("stays at its round-off floor"), std::string::npos) << too_stiff.failure;
}

// Non-finite residuals, increments or force scales fail the solve.
TEST(Newton, NonFiniteValuesFail) {
  StiffTangentProblem p;
  LinearSolver s;
  p.scale_ = std::numeric_limits<double>::infinity();
  const NewtonReport inf_scale = solve_newton(p, s, NewtonSettings{});
  EXPECT_FALSE(inf_scale.converged);
  EXPECT_NE(inf_scale.failure.find("force scale is inf"), std::string::npos) << inf_scale.failure;
  p.scale_ = 1.0;
  p.a_.setConstant(std::numeric_limits<double>::quiet_NaN());
  const NewtonReport nan_residual = solve_newton(p, s, NewtonSettings{});
  EXPECT_FALSE(nan_residual.converged);
  EXPECT_NE(nan_residual.failure.find("residual is nan"), std::string::npos) << nan_residual.failure;
}

}  // namespace
}  // namespace conserve::solver
