#pragma once
/// A run built from scenario text through the same wiring as `conserve run`
/// (simulation/stepper.hpp), stepped by hand so that tests can look at the
/// state and the active set between steps.
#include <memory>
#include <string>

#include "io/scenario.hpp"
#include "simulation/stepper.hpp"
#include "time/diagnostics.hpp"

namespace conserve::test {

template <int D>
struct ContactRun {
  io::Scenario scenario;
  std::unique_ptr<simulation::Stepper<D>> stepper;
  const simulation::Problem<D>& problem;
  const assembly::Assembler<D>* assembler;
  contact::Method<D>* method;     ///< the contact method (null without contact)
  contact::ActiveSet<D>* contacts;  ///< its active set when it is elimination, else null
  time::Integrator<D>* integrator;
  model::State state;
  simulation::StepRecord last;  ///< what the last step() did

  explicit ContactRun(const std::string& toml)
      : scenario(io::parse_scenario(toml, "test.toml")),
        stepper(std::make_unique<simulation::Stepper<D>>(scenario)),
        problem(stepper->problem()),
        assembler(&stepper->assembler()),
        method(stepper->contact()),
        contacts(stepper->active_set()),
        integrator(&stepper->integrator()),
        state(problem.initial) {}
  ContactRun(const ContactRun&) = delete;
  ContactRun& operator=(const ContactRun&) = delete;

  /// One converged step as `conserve run` takes it (with cutback): the
  /// report of its last, successful attempt.
  solver::NewtonReport step() {
    double dt = 0.0;
    int failures = 0;
    last = stepper->advance(state, dt, failures);
    return last.newton;
  }
  /// The state's energies and momenta, the method's stored energy (the
  /// last step's contact_energy) in the total.
  [[nodiscard]] time::Diagnostics diagnostics() const {
    time::Diagnostics d = time::diagnostics<D>(*assembler, state);
    d.contact = last.contact.contact_energy;
    d.total += d.contact;
    return d;
  }
  [[nodiscard]] contact::Positions<D> positions() const {
    return problem.model.X + state.u.reshaped(D, problem.model.num_nodes());
  }
};

}  // namespace conserve::test
