#pragma once
/// Newton–Raphson on an abstract problem that knows its residual, tangent
/// and how to apply an increment (the increment may be post-processed, e.g.
/// by constraint updates). Newton itself knows nothing of mechanics.
#include <string>
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
  /// Announces that tangent() will be asked for at the iterate of the next
  /// residual() call: a problem whose residual and tangent share their
  /// work may assemble both there in one pass. Only a hint: tangent() is
  /// right wherever it is called.
  virtual void prepare_tangent() {}
  /// Applies the increment Δ solved from K Δ = −r.
  virtual void update(const Eigen::VectorXd& increment) = 0;
  /// Undoes the last update() (for the line search); returns false, doing
  /// nothing, if the problem cannot.
  virtual bool revert() { return false; }
  /// Reference force of the problem at the last residual [N]: |r| ≤ tol ·
  /// force_scale converges.
  [[nodiscard]] virtual double force_scale() const = 0;
  /// Round-off floor of the last residual's norm [N]: below it the residual
  /// cannot be computed, so no iteration can bring it lower.
  [[nodiscard]] virtual double residual_floor() const = 0;
  /// The force a residual at its floor is judged against [N] (≥
  /// force_scale; infinite when nothing moves): it is a solution only if it
  /// is at most floor_limit times this.
  [[nodiscard]] virtual double floor_scale() const { return force_scale(); }
  /// Called after each iteration with the new residual's norm and the
  /// force scale [N]: true ends the iteration unconverged, as abandoned
  /// (a problem that can tell from an iterate that its solution will not
  /// be used).
  virtual bool abandon(double /*residual*/, double /*force_scale*/) { return false; }
};

struct NewtonSettings {
  int max_iterations = 20;
  /// Converged when |r| ≤ residual_tolerance · force_scale.
  double residual_tolerance = 1e-12;
  /// Or when |r| is at its round-off floor and no longer halves, provided
  /// it is at most floor_limit · floor_scale: a residual that cannot be
  /// brought to 1e-6 of the forces at play is no solution (a model too
  /// stiff for double precision at this Δt).
  double floor_limit = 1e-6;
  /// Modified Newton: keep the last tangent and what the solver derived
  /// from it (factorization, preconditioner) across iterations and steps
  /// while each iteration reduces the residual by at least `reuse_ratio`
  /// and, at the rate shown, reaches the tolerance with iterations to spare;
  /// take a new tangent otherwise. Convergence becomes linear but an
  /// iteration costs a residual and a solve instead of an assembly and a
  /// set-up (bench/results/speed.md: 1.6–1.7× faster on the cube and the
  /// ball). Conservation is unaffected: it depends on the residual only.
  /// Off here (the textbook iteration); on in a scenario ([solver]
  /// modified_newton).
  bool modified_newton = false;
  double reuse_ratio = 0.25;
  /// Modified Newton: a kept tangent that contracts the residual by less
  /// than this per iteration (r_{k+1}/r_k above it) while at least
  /// fresh_after more iterations are projected at that rate is replaced
  /// at the next iterate, assembled in the same pass as its residual
  /// (NewtonProblem::prepare_tangent). Before a solve's first residual
  /// ratio is known, the previous solve's first ratio with a kept tangent
  /// (NewtonMemory::kept_ratio) stands for it. A fresh tangent converges
  /// nearly quadratically; a kept one whose iterate has moved on (a
  /// vibrating body whose strains change a few per cent a step) contracts
  /// 20–50× per iteration and slows as the residual falls
  /// (bench/results/newton.md). 0: never (the reuse_ratio rule alone).
  double fresh_ratio = 1e-2;
  int fresh_after = 3;
  /// Inexact Newton: an iterative solver solves K Δ = −r_k only to
  /// |K Δ + r_k| ≤ η_k |r_k|. η_k follows Eisenstat & Walker (1996), choice
  /// 1: η_k = |r_k| − |r_{k−1} + K Δ_{k−1}| over |r_{k−1}|, the part of the
  /// new residual that linearisation could not predict (safeguarded by
  /// η_{k−1}^φ when that exceeds 0.1), at most forcing_max. With the
  /// nonlinear remainder modelled as C |r|² (C measured, and carried over
  /// from the previous solve as a start), an iteration whose exact solve
  /// would reach the tolerance solves to it: the iteration ends in one more
  /// step instead of two (a nearly linear step takes one). Never tighter
  /// than 1/50 of the nonlinear tolerance requires. Convergence is judged on the nonlinear residual alone.
  double forcing_max = 0.1;
  /// Backtracking line search: an increment that does not lower |r| is
  /// halved, up to line_search_halvings times, keeping the fraction with
  /// the smallest |r| (0: full steps only). Far from the solution (a
  /// vibrating body at a step many times its wave-transit time) a full
  /// Newton step can overshoot by orders of magnitude.
  int line_search_halvings = 4;
};

/// What one solve of a run passes to the next (modified Newton, forcing
/// terms): measures of earlier iterations, in and out; negative: unknown.
struct NewtonMemory {
  double nonlinearity = -1.0;  ///< C of the forcing terms' model |r_{k+1}| ≈ C |r_k|²
  double kept_ratio = -1.0;    ///< r₁/r₀ of the last solve whose first iteration used a kept tangent
};

struct NewtonReport {
  bool converged = false;
  int iterations = 0;                  ///< linear solves done
  int backtracks = 0;                  ///< line-search halvings
  int tangents = 0;                    ///< tangents set (set_operator calls)
  long long linear_iterations = 0;     ///< Krylov iterations over those solves
  std::vector<double> residual_norms;  ///< |r| before each solve and at the end
  double tolerance = 0.0;              ///< residual_tolerance · force_scale [N]
  double floor = 0.0;                  ///< round-off floor of the last residual [N]
  /// Why the iteration did not converge (empty if it did): too many
  /// iterations, a non-finite residual, increment or force scale, or a
  /// floor above floor_limit · force_scale.
  std::string failure;
  bool abandoned = false;  ///< ended by NewtonProblem::abandon
  [[nodiscard]] double final_residual() const { return residual_norms.empty() ? 0.0 : residual_norms.back(); }
};

/// Iterates until |r| ≤ residual_tolerance · force_scale, or until |r| is
/// at its round-off floor, no longer halves, and is at most floor_limit ·
/// floor_scale. The residual criterion alone decides:
/// a small increment never ends the iteration. Does not throw on
/// non-convergence: the report says so and why, and the caller decides.
/// `reusable`: the solver's current matrix has the structure of this
/// problem's tangent (used with modified_newton).
/// `memory`: what earlier solves measured, in and out (may be null).
NewtonReport solve_newton(NewtonProblem& problem, LinearSolver& solver, const NewtonSettings& settings,
                          bool reusable = false, NewtonMemory* memory = nullptr);

}  // namespace conserve::solver
