#pragma once
/// Advances the state step by step with the conserving mid-point scheme,
/// reusing the tangent's pattern and UMFPACK's symbolic analysis.
#include "assembly/assembler.hpp"
#include "assembly/dirichlet.hpp"
#include "model/state.hpp"
#include "solver/newton.hpp"

namespace conserve::time {

template <int D>
class Integrator {
 public:
  Integrator(const assembly::Assembler<D>& assembler, fem::StressScheme scheme, solver::NewtonSettings newton);

  /// Advances `state` by `dt` [s]: predictor u_n + Δt V_n with prescribed
  /// values at t_{n+1}, Newton, then V_{n+1} = (2/Δt)Δu − V_n (19).
  /// Throws SolverError naming the step if Newton does not converge; the
  /// state is then left unchanged.
  solver::NewtonReport step(model::State& state, double dt);

  [[nodiscard]] const solver::LinearSolver& linear_solver() const { return solver_; }

 private:
  const assembly::Assembler<D>& assembler_;
  fem::StressScheme scheme_;
  solver::NewtonSettings newton_;
  assembly::DirichletMask mask_;
  SparseMatrix K_;
  solver::LinearSolver solver_;
};

/// Puts the prescribed values u(t) on `u` and the rates on `v` (if given).
void apply_prescribed(const model::Prescribed& prescribed, double t, Eigen::VectorXd& u, Eigen::VectorXd* v = nullptr);

}  // namespace conserve::time
