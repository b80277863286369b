#include "simulation/stepper.hpp"

#include <algorithm>

#include "simulation/contact_setup.hpp"
#include "simulation/plausibility.hpp"
#include "solver/ranks.hpp"

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
      pairs_(make_contact_pairs<D>(scenario, problem_.model)),
      contact_(pairs_.empty() ? nullptr
                              : contact::make_method<D>(scenario, problem_.model, assembler_->node_mass(), pairs_)),
      integrator_(std::make_unique<time::Integrator<D>>(*assembler_, stress_scheme(scenario.time.scheme),
                                                         newton_settings(scenario.newton, scenario.solver),
                                                         contact_.get(), scenario.active_set.max_passes,
                                                         linear_settings(scenario.solver))),
      control_{.dt = scenario.time.step},
      threads_(scenario.solver.threads, problem_.model.num_cells()) {
  integrator_->set_predictor(scenario.newton.predictor == io::PredictorKind::rigid ? time::Predictor::rigid
                                                                                   : time::Predictor::velocity);
  warnings_ = plausibility_warnings<D>(scenario, problem_.model, pairs_);
  fingerprint_ = scenario_fingerprint<D>(scenario, problem_.model);
  // On several ranks each assembles the forces and tangents of its nodes,
  // from the cells around them, which are all the model keeps from now on.
  if (solver::ranks::size() > 1) {
    assembler_->share({&solver::ranks::gather_segments, &solver::ranks::all});
    model::keep_cells(problem_.model, assembler_->pattern().kept_cell_ids());
    assembler_->cells_kept();
  }
}

template <int D>
StepRecord Stepper<D>::advance(model::State& state, double& dt_used, int& failures) {
  threads_.update();
  const std::string saved = contact_ ? contact_->save() : std::string();
  const auto restore = [&] {
    if (contact_) contact_->load(saved, "the step's start");
  };
  failures = 0;
  // After a step cut short at an impact the steps go on at the full Δt
  // from there (off the scenario's grid, as after a cutback): the step
  // that holds an unresolved collision is as long as the scenario's, not
  // whatever is left of the step that was cut. The last step ends at the
  // end time.
  double dt = control_.dt;
  if (contact_ && scenario_.active_set.locate_releases)  // shorter ahead of a lift-off, not below the floor
    dt = std::max(
        std::min(dt, contact_->next_step(state.step, scenario_.time.step, control_.last_dt, control_.previous_dt)),
        std::min(dt, scenario_.time.min_step));
  const double left = scenario_.time.end - state.time;
  if (left < dt * (1.0 - 1e-9)) dt = left;
  int splits = 0, split_passes = 0;
  bool locate = true;
  // A step that fails with a kept tangent (modified Newton, whose
  // convergence is linear) is tried again at the same Δt with a fresh
  // tangent at every iteration, and so are its cutbacks; the later steps
  // keep tangents again.
  struct Fresh {
    time::Integrator<D>& integrator;
    bool modified = integrator.modified_newton();
    ~Fresh() { integrator.set_modified_newton(modified); }
  } fresh{*integrator_};
  for (;;) {
    if (contact_) contact_->allow_splits(locate && splits < kMaxSplits);
    try {
      dt_used = dt;
      const solver::NewtonReport report = integrator_->step(state, dt);
      contact::StepContactStats stats = integrator_->contact_stats();
      if (stats.split_fraction < 1.0) {  // an impact within the step: end the step there
        restore();
        ++splits;
        split_passes += stats.passes;
        const double shorter = dt * stats.split_fraction;
        if (shorter >= scenario_.time.min_step)
          dt = shorter;
        else
          locate = false;  // activate with the gap it has rather than step below the floor
        continue;
      }
      stats.splits = splits;
      stats.split_passes = split_passes;
      StepRecord record{report, stats, integrator_->supports()};
      control_.previous_dt = control_.last_dt;
      control_.last_dt = dt;
      if (++control_.good_steps >= StepControl::kGrowAfter && control_.dt < scenario_.time.step) {
        control_.dt = std::min(2.0 * control_.dt, scenario_.time.step);
        control_.good_steps = 0;
        integrator_->drop_factorization();
      }
      return record;
    } catch (const SolverError& e) {
      last_failure_ = e.what();
      restore();
      integrator_->drop_factorization();
      ++failures;
      if (integrator_->modified_newton()) {
        integrator_->set_modified_newton(false);
        continue;
      }
      if (0.5 * dt < scenario_.time.min_step) throw FloorReached(e.what(), dt);
      control_.dt = 0.5 * dt;
      control_.good_steps = 0;
      ++control_.cutbacks;
      dt = control_.dt;
    }
  }
}

template class Stepper<2>;
template class Stepper<3>;

}  // namespace conserve::simulation
