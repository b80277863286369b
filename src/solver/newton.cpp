#include "solver/newton.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace conserve::solver {

namespace {

constexpr const char* kIterate = "not converged";
/// Iterations a fresh tangent is left to finish a step in (modified Newton).
constexpr int kSpareIterations = 4;

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

/// The relative linear tolerances η_k of an inexact Newton iteration
/// (NewtonSettings::forcing_max).
class Forcing {
 public:
  Forcing(double max, double nonlinearity) : max_(max), eta_(max), c_(nonlinearity) {}

  /// η for the solve at residual norm r towards |r| ≤ target.
  double next(double r, double target) {
    // No tighter than needed to end well inside the tolerance (the energy
    // error of a step grows with its residual: 1/50 of the tolerance keeps
    // the drift of long runs near a direct solver's).
    const double floor = 0.02 * target / r;
    // Unknown C (the first solve of a run): solve to the tolerance, which
    // measures C without the elastic errors a loose solve would add.
    if (c_ < 0.0 || c_ * r * r <= 0.02 * target) return std::min(floor, max_);  // the last iteration
    return std::clamp(eta_, floor, max_);
  }

  /// After the solve at r_old reached the linear residual `linear` and
  /// the new residual is r_new. C is measured only while r_new is well
  /// above the tolerance: below, the remainder is round-off, not |r|².
  void observe(double r_old, double linear, double r_new, double target) {
    const double remainder = std::max(r_new - linear, 0.0);  // ≤ |nonlinear remainder|
    const double eta = remainder / r_old;                    // choice 1
    const double safeguard = std::pow(eta_, kGolden);
    eta_ = std::min(safeguard > 0.1 ? std::max(eta, safeguard) : eta, max_);
    if (r_new > 4.0 * target) c_ = remainder / (r_old * r_old);
  }
  [[nodiscard]] double nonlinearity() const { return c_; }

 private:
  static constexpr double kGolden = 1.618033988749895;
  double max_, eta_, c_;
};

/// Modified Newton: whether the tangent of the last solve serves the next
/// one. It does while it contracts the residual by reuse_ratio or better
/// per iteration and, at the rate it shows, reaches the tolerance with
/// iterations to spare for a fresh tangent should it slow down.
bool keep_tangent(const NewtonReport& report, const NewtonSettings& settings) {
  if (!settings.modified_newton) return false;
  const auto& norms = report.residual_norms;
  const double r = norms.back(), ratio = r / norms[norms.size() - 2];
  if (!(ratio <= settings.reuse_ratio)) return false;
  if (!(r > report.tolerance) || !(ratio > 0.0)) return true;
  const double needed = std::log(report.tolerance / r) / std::log(ratio);
  return needed <= settings.max_iterations - report.iterations - kSpareIterations;
}

/// Modified Newton: whether the next iterate takes a fresh tangent with its
/// residual (NewtonSettings::fresh_ratio), judged before this iteration's
/// solve, at residual r, with `ratio` the kept tangent's contraction (last
/// iteration's, or a previous solve's; ≤ 0: unknown). Only where a new
/// operator costs the solver little (LinearSolver::cheap_setup).
bool fresh_next(double r, double ratio, double tolerance, const NewtonSettings& settings, const LinearSolver& solver) {
  if (!settings.modified_newton || !(settings.fresh_ratio > 0.0) || !(ratio > settings.fresh_ratio)) return false;
  if (!solver.cheap_setup()) return false;
  if (!(ratio < 1.0)) return true;
  const double projected = std::log(tolerance / r) / std::log(ratio);
  return projected >= settings.fresh_after + 1;  // this iteration and fresh_after more
}

}  // namespace

NewtonReport solve_newton(NewtonProblem& problem, LinearSolver& solver, const NewtonSettings& settings,
                          bool reusable, NewtonMemory* memory) {
  NewtonMemory unused;
  NewtonMemory& kept = memory ? *memory : unused;
  NewtonReport report;
  Eigen::VectorXd r, dx;
  problem.residual(r);
  report.residual_norms.push_back(r.norm());
  report.floor = problem.residual_floor();
  bool refactor = !(settings.modified_newton && reusable);
  bool fresh = false;     // this iteration's tangent was set at its iterate
  bool prepared = false;  // the last residual came with its tangent (prepare_tangent)
  Forcing forcing(settings.forcing_max, kept.nonlinearity);
  for (;;) {
    const double scale = problem.force_scale();
    if (!std::isfinite(scale)) {
      report.failure = fmt::format("the step's force scale is {} N", scale);
      return report;
    }
    report.tolerance = settings.residual_tolerance * scale;
    report.failure = judge(report, problem.floor_scale(), settings);
    if (report.failure.empty()) {
      // A tangent assembled for an iterate that turned out to be the
      // solution is kept for the next solves: it is the freshest.
      if (prepared) solver.set_operator(problem.tangent()), ++report.tangents;
      report.converged = true;
      return report;
    }
    if (report.failure != kIterate) return report;  // nothing to iterate on
    if (report.iterations == settings.max_iterations) {
      report.failure = fmt::format("{} iterations were not enough", settings.max_iterations);
      return report;
    }
    if (refactor) solver.set_operator(problem.tangent()), ++report.tangents;
    fresh = refactor;
    const double r_old = report.residual_norms.back();
    // The kept tangent's contraction: this solve's last, or before the
    // first ratio, the previous solve's first.
    const auto& norms = report.residual_norms;
    const double ratio = report.iterations > 0 ? (fresh ? 0.0 : norms.back() / norms[norms.size() - 2])
                                               : (fresh ? 0.0 : kept.kept_ratio);
    prepared = fresh_next(r_old, ratio, report.tolerance, settings, solver);
    if (prepared) problem.prepare_tangent();
    const double eta = solver.exact() ? 0.0 : forcing.next(r_old, report.tolerance);
    const LinearSolve linear = solver.solve(-r, dx, eta);
    report.linear_iterations += linear.iterations;
    if (!dx.allFinite()) {
      report.failure = "the Newton increment is not finite";
      return report;
    }
    problem.update(dx);
    ++report.iterations;
    problem.residual(r);
    double r_new = r.norm();
    if (settings.line_search_halvings > 0 && !(r_new < r_old) && std::isfinite(r_old)) {
      // Backtrack: try Δ/2, Δ/4, … from the same iterate, keep the best.
      double best = r_new, best_fraction = 1.0, fraction = 1.0;
      for (int h = 0; h < settings.line_search_halvings && !(best < r_old); ++h) {
        if (!problem.revert()) break;
        fraction *= 0.5;
        problem.update(fraction * dx);
        problem.residual(r);
        ++report.backtracks;
        if (r.norm() < best) best = r.norm(), best_fraction = fraction;
      }
      if (best_fraction != fraction && problem.revert()) {
        problem.update(best_fraction * dx);
        problem.residual(r);
      }
      r_new = r.norm();
    }
    report.residual_norms.push_back(r_new);
    report.floor = problem.residual_floor();
    if (problem.abandon(r_new, scale)) {
      report.abandoned = true;
      report.failure = "abandoned by the problem";
      return report;
    }
    forcing.observe(r_old, linear.residual, report.residual_norms.back(), report.tolerance);
    kept.nonlinearity = forcing.nonlinearity();
    if (report.iterations == 1 && !fresh) kept.kept_ratio = r_new / r_old;
    refactor = prepared || !keep_tangent(report, settings);
  }
}

}  // namespace conserve::solver
