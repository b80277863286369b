#include "solver/newton.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace conserve::solver {

namespace {

constexpr const char* kIterate = "not converged";

/// The reason the residual at the end of `report` is not a solution, or
/// empty if it is one (converged), or kIterate to iterate on. At the
/// round-off floor the iteration goes on while it still halves the
/// residual (the floor is an upper estimate), so that a step ends as close
/// to the solution as double precision allows; then the residual is
/// accepted if it is at most floor_limit · floor_scale.
std::string judge(NewtonReport& report, double floor_scale, const NewtonSettings& settings) {
  const auto& norms = report.residual_norms;
  const double r = norms.back();
  if (!std::isfinite(r)) return fmt::format("the residual is {} N", r);
  if (r <= report.tolerance) return {};
  if (r <= report.floor) {
    const bool stagnates = norms.size() > 1 && r > 0.5 * norms[norms.size() - 2];
    if (!stagnates && report.iterations < settings.max_iterations) return kIterate;
    if (r <= settings.floor_limit * floor_scale) return {};
    return fmt::format(
        "the residual stays at its round-off floor, {:.2e} N, above {:g} of the step's force scale {:.2e} N: the "
        "model is too stiff for double precision at this time step",
        r, settings.floor_limit, floor_scale);
  }
  return kIterate;
}

}  // namespace

NewtonReport solve_newton(NewtonProblem& problem, LinearSolver& solver, const NewtonSettings& settings,
                          bool reusable) {
  NewtonReport report;
  Eigen::VectorXd r, dx;
  problem.residual(r);
  report.residual_norms.push_back(r.norm());
  report.floor = problem.residual_floor();
  bool refactor = !(settings.reuse_factorization && reusable);
  for (;;) {
    const double scale = problem.force_scale();
    if (!std::isfinite(scale)) {
      report.failure = fmt::format("the step's force scale is {} N", scale);
      return report;
    }
    report.tolerance = settings.residual_tolerance * scale;
    report.failure = judge(report, problem.floor_scale(), settings);
    if (report.failure.empty()) {
      report.converged = true;
      return report;
    }
    if (report.failure != kIterate) return report;  // nothing to iterate on
    if (report.iterations == settings.max_iterations) {
      report.failure = fmt::format("{} iterations were not enough", settings.max_iterations);
      return report;
    }
    if (refactor) solver.factorize(problem.tangent());
    solver.solve(-r, dx);
    if (!dx.allFinite()) {
      report.failure = "the Newton increment is not finite";
      return report;
    }
    problem.update(dx);
    ++report.iterations;
    problem.residual(r);
    report.residual_norms.push_back(r.norm());
    report.floor = problem.residual_floor();
    const double ratio = report.residual_norms.back() / report.residual_norms[report.residual_norms.size() - 2];
    refactor = !settings.reuse_factorization || !(ratio <= settings.reuse_ratio);
  }
}

}  // namespace conserve::solver
