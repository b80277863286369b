#include <gtest/gtest.h>

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
  void residual(Eigen::VectorXd& r) override { r = x_.array().cube() + x_.array() - a_.array(); }
  const SparseMatrix& tangent() override {
    for (int i = 0; i < x_.size(); ++i) K_.coeffRef(i, i) = 3.0 * x_[i] * x_[i] + 1.0;
    return K_;
  }
  void update(const Eigen::VectorXd& dx) override { x_ += dx; }
  [[nodiscard]] double force_scale() const override { return a_.norm(); }
  [[nodiscard]] double length_scale() const override { return 1.0; }
  Eigen::VectorXd x_, a_;
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
  const NewtonReport rep = solve_newton(p, s, NewtonSettings{1, 1e-12, 1e-13});
  EXPECT_FALSE(rep.converged);
  EXPECT_EQ(rep.iterations, 1);
}

}  // namespace
}  // namespace conserve::solver
