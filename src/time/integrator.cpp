#include "time/integrator.hpp"

#include <fmt/format.h>

#include "core/error.hpp"
#include "time/step_problem.hpp"

namespace conserve::time {

void apply_prescribed(const model::Prescribed& p, double t, Eigen::VectorXd& u, Eigen::VectorXd* v) {
  for (std::size_t i = 0; i < p.dofs.size(); ++i) {
    u[p.dofs[i]] = p.value[i] + p.rate[i] * t;
    if (v) (*v)[p.dofs[i]] = p.rate[i];
  }
}

template <int D>
Integrator<D>::Integrator(const assembly::Assembler<D>& assembler, fem::StressScheme scheme,
                          solver::NewtonSettings newton)
    : assembler_(assembler),
      scheme_(scheme),
      newton_(newton),
      mask_(assembler.mass(), assembler.model().prescribed.dofs),
      K_(assembler.pattern().make_matrix()) {}

template <int D>
solver::NewtonReport Integrator<D>::step(model::State& state, double dt) {
  const double t_np1 = state.time + dt;
  Eigen::VectorXd u_np1 = state.u + dt * state.v;
  apply_prescribed(assembler_.model().prescribed, t_np1, u_np1);
  StepProblem<D> problem(assembler_, mask_, scheme_, state, dt, u_np1, K_);
  solver::NewtonReport report = solver::solve_newton(problem, solver_, newton_);
  if (!report.converged)
    throw SolverError(
        fmt::format("Newton did not converge in step {} (t = {:.6g} s): residual {:.3e} after {} iterations "
                    "(try a smaller time step or more [newton].max_iterations)",
                    state.step + 1, t_np1, report.final_residual(), report.iterations));
  state.v = (2.0 / dt) * (u_np1 - state.u) - state.v;  // (19)
  state.u = std::move(u_np1);
  state.time = t_np1;
  ++state.step;
  return report;
}

template class Integrator<2>;
template class Integrator<3>;

}  // namespace conserve::time
