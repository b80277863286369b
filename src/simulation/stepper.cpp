#include "simulation/stepper.hpp"

#include <algorithm>

#include "simulation/contact_setup.hpp"

namespace conserve::simulation {

solver::NewtonSettings newton_settings(const io::NewtonSpec& n, const io::SolverSpec& s) {
  return {.max_iterations = n.max_iterations,
          .residual_tolerance = n.residual_tolerance,
          .modified_newton = s.modified_newton,
          .forcing_max = s.forcing_max};
}

solver::LinearSolverSettings linear_settings(const io::SolverSpec& s) {
  solver::LinearSolverSettings l;
  l.method = s.method == "direct" ? solver::Method::direct : solver::Method::krylov;
  l.preconditioner = s.preconditioner == "ilu"    ? solver::Preconditioner::ilu
                     : s.preconditioner == "gamg" ? solver::Preconditioner::gamg
                                                  : solver::Preconditioner::automatic;
  l.gamg_from = s.gamg_from;
  l.max_iterations = s.max_linear_iterations;
  l.petsc_options = s.petsc_options;
  return l;
}

namespace {

fem::StressScheme stress_scheme(io::StressScheme s) {
  return s == io::StressScheme::midpoint ? fem::StressScheme::midpoint : fem::StressScheme::conserving;
}

}  // namespace

template <int D>
Stepper<D>::Stepper(const io::Scenario& scenario)
    : scenario_(scenario),
      problem_(setup<D>(scenario)),
      assembler_(std::make_unique<assembly::Assembler<D>>(problem_.model, scenario.time.mass == io::MassKind::lumped)),
      contacts_(std::make_unique<contact::ActiveSet<D>>(problem_.model, make_contact_pairs<D>(scenario, problem_.model))),
      integrator_(std::make_unique<time::Integrator<D>>(*assembler_, stress_scheme(scenario.time.scheme),
                                                         newton_settings(scenario.newton, scenario.solver),
                                                         contacts_.get(), scenario.active_set.max_passes,
                                                         linear_settings(scenario.solver))),
      control_{.dt = scenario.time.step} {
  integrator_->set_persistent_contact(scenario.active_set.scheme == io::ContactScheme::persistent);
}

template <int D>
StepRecord Stepper<D>::advance(model::State& state, double& dt_used, int& failures) {
  const std::vector<contact::Constraint<D>> saved = contacts_->constraints();
  failures = 0;
  for (;;) {
    try {
      dt_used = control_.dt;
      StepRecord record{integrator_->step(state, dt_used), integrator_->contact_stats()};
      if (++control_.good_steps >= StepControl::kGrowAfter && control_.dt < scenario_.time.step) {
        control_.dt = std::min(2.0 * control_.dt, scenario_.time.step);
        control_.good_steps = 0;
        integrator_->drop_factorization();
      }
      return record;
    } catch (const SolverError& e) {
      last_failure_ = e.what();
      contacts_->set_constraints(saved);
      integrator_->drop_factorization();
      if (0.5 * control_.dt < scenario_.time.min_step) throw FloorReached(e.what(), control_.dt);
      control_.dt *= 0.5;
      control_.good_steps = 0;
      ++control_.cutbacks;
      ++failures;
    }
  }
}

template class Stepper<2>;
template class Stepper<3>;

}  // namespace conserve::simulation
