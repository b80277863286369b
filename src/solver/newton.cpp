#include "solver/newton.hpp"

#include <cmath>

namespace conserve::solver {

NewtonReport solve_newton(NewtonProblem& problem, LinearSolver& solver, const NewtonSettings& settings,
                          bool reusable) {
  NewtonReport report;
  Eigen::VectorXd r, dx;
  problem.residual(r);
  report.residual_norms.push_back(r.norm());
  const double r_tol = settings.residual_tolerance * problem.force_scale();
  const double dx_tol = settings.increment_tolerance * problem.length_scale();
  bool refactor = !(settings.reuse_factorization && reusable);
  while (report.residual_norms.back() > r_tol) {
    if (report.iterations == settings.max_iterations || !std::isfinite(report.residual_norms.back())) return report;
    if (refactor) solver.factorize(problem.tangent());
    solver.solve(-r, dx);
    problem.update(dx);
    ++report.iterations;
    problem.residual(r);
    report.residual_norms.push_back(r.norm());
    const double ratio = report.residual_norms.back() / report.residual_norms[report.residual_norms.size() - 2];
    refactor = !settings.reuse_factorization || !(ratio <= settings.reuse_ratio);
    if (dx.lpNorm<Eigen::Infinity>() <= dx_tol && std::isfinite(report.residual_norms.back())) break;
  }
  report.converged = true;
  return report;
}

}  // namespace conserve::solver
