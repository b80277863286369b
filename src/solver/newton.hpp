#pragma once
/// Newton–Raphson on an abstract problem that knows its residual, tangent
/// and how to apply an increment (the increment may be post-processed, e.g.
/// by constraint updates). Newton itself knows nothing of mechanics.
#include <vector>

#include "solver/linear_solver.hpp"

namespace conserve::solver {

class NewtonProblem {
 public:
  virtual ~NewtonProblem() = default;
  /// Residual at the current iterate.
  virtual void residual(Eigen::VectorXd& r) = 0;
  /// Tangent ∂r/∂(unknowns) at the current iterate.
  virtual const SparseMatrix& tangent() = 0;
  /// Applies the increment Δ solved from K Δ = −r.
  virtual void update(const Eigen::VectorXd& increment) = 0;
  /// Scale of the forces in the problem [N]: |r| ≤ tol · scale converges.
  [[nodiscard]] virtual double force_scale() const = 0;
  /// Scale of the unknowns [m]: |Δ|∞ ≤ tol · scale converges.
  [[nodiscard]] virtual double length_scale() const = 0;
};

struct NewtonSettings {
  int max_iterations = 20;
  double residual_tolerance = 1e-12;
  double increment_tolerance = 1e-13;
  /// Modified Newton: keep the last factorization (across iterations and
  /// steps) while each iteration reduces the residual by at least
  /// `reuse_ratio`; refactorize otherwise. Convergence becomes linear but an
  /// iteration costs a residual and a solve instead of a factorization.
  /// Conservation is unaffected: it depends on the residual only.
  bool reuse_factorization = false;
  double reuse_ratio = 0.25;
};

struct NewtonReport {
  bool converged = false;
  int iterations = 0;                  ///< linear solves done
  std::vector<double> residual_norms;  ///< |r| before each solve and at the end
  [[nodiscard]] double final_residual() const { return residual_norms.empty() ? 0.0 : residual_norms.back(); }
};

/// Iterates until |r| ≤ residual_tolerance·force_scale or, after a solve,
/// |Δ|∞ ≤ increment_tolerance·length_scale. Does not throw on
/// non-convergence: the report says so, and the caller decides.
/// `reusable`: the solver's current factorization belongs to a matrix of the
/// same structure as this problem's tangent (used with reuse_factorization).
NewtonReport solve_newton(NewtonProblem& problem, LinearSolver& solver, const NewtonSettings& settings,
                          bool reusable = false);

}  // namespace conserve::solver
