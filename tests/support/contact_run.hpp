#pragma once
/// A run built from scenario text, stepped by hand, so that tests can look
/// at the state and the active set between steps.
#include <memory>
#include <string>

#include "contact/active_set.hpp"
#include "io/scenario.hpp"
#include "simulation/contact_setup.hpp"
#include "simulation/setup.hpp"
#include "time/diagnostics.hpp"
#include "time/integrator.hpp"

namespace conserve::test {

template <int D>
struct ContactRun {
  io::Scenario scenario;
  simulation::Problem<D> problem;
  std::unique_ptr<assembly::Assembler<D>> assembler;
  std::unique_ptr<contact::ActiveSet<D>> contacts;
  std::unique_ptr<time::Integrator<D>> integrator;
  model::State state;

  explicit ContactRun(const std::string& toml)
      : scenario(io::parse_scenario(toml, "test.toml")), problem(simulation::setup<D>(scenario)) {
    assembler = std::make_unique<assembly::Assembler<D>>(problem.model, false);
    contacts = std::make_unique<contact::ActiveSet<D>>(problem.model,
                                                       simulation::make_contact_pairs<D>(scenario, problem.model));
    integrator = std::make_unique<time::Integrator<D>>(
        *assembler, fem::StressScheme::conserving,
        solver::NewtonSettings{.max_iterations = scenario.newton.max_iterations,
                               .residual_tolerance = scenario.newton.residual_tolerance},
        contacts.get(), scenario.active_set.max_passes);
    state = problem.initial;
  }
  solver::NewtonReport step() { return integrator->step(state, scenario.time.step); }
  [[nodiscard]] time::Diagnostics diagnostics() const { return time::diagnostics<D>(*assembler, state); }
  [[nodiscard]] contact::Positions<D> positions() const {
    return problem.model.X + state.u.reshaped(D, problem.model.num_nodes());
  }
};

}  // namespace conserve::test
