#pragma once
/// A run built from scenario text through the same wiring as `conserve run`
/// (simulation/stepper.hpp), stepped by hand so that tests can look at the
/// state and the active set between steps.
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <string_view>

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
  int cutbacks = 0;             ///< failed attempts so far (each retried with a halved Δt)

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
    cutbacks += failures;
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
  /// The last step's value of the method's own statistic `column`
  /// (contact::Method::statistics, e.g. elimination's "pushes").
  [[nodiscard]] double own(std::string_view column) const {
    return contact::own_statistic<D>(*method, last.contact, column);
  }
  [[nodiscard]] contact::Positions<D> positions() const {
    return problem.model.X + state.u.reshaped(D, problem.model.num_nodes());
  }
};

/// What a run measured over its steps: the largest relative drifts (of
/// E with the method's stored energy, of L, of J) against the largest
/// K + W, Σ|p| and Σ|p| × size seen (summary.json's references), and
/// what contact did.
struct Drift {
  double energy = 0.0, linear = 0.0, angular = 0.0;
  double counted = 0.0;      ///< E + Σ contact_released's drift
  double released = 0.0;    ///< Σ contact_released [J]
  double penetration = 0.0;  ///< the deepest slave node behind a facet [m]
  double master_penetration = 0.0;  ///< the deepest master node behind a facet of its pair's slave [m]
  double spring = 0.0;       ///< the largest contact energy [J]
  int contact_steps = 0;     ///< steps ending with a contact carrying force
};

/// Steps `run` to its scenario's end time and measures it.
template <int D>
Drift measure(ContactRun<D>& run) {
  const time::Diagnostics d0 = run.diagnostics();
  const int steps = static_cast<int>(std::round(run.scenario.time.end / run.scenario.time.step));
  double e_ref = std::abs(d0.total), l_ref = d0.linear.norm();
  Drift r;
  for (int n = 0; n < steps; ++n) {
    run.step();
    const time::Diagnostics d = run.diagnostics();
    const auto& c = run.last.contact;
    r.released += c.contact_released;
    e_ref = std::max(e_ref, d.kinetic + d.strain);
    l_ref = std::max(l_ref, d.linear.norm());
    r.energy = std::max(r.energy, std::abs(d.total - d0.total) / e_ref);
    r.counted = std::max(r.counted, std::abs(d.total + r.released - d0.total) / e_ref);
    r.linear = std::max(r.linear, (d.linear - d0.linear).cwiseAbs().maxCoeff() / l_ref);
    r.angular = std::max(r.angular, (d.angular - d0.angular).cwiseAbs().maxCoeff() / (l_ref * run.problem.model.size()));
    r.penetration = std::max(r.penetration, c.slave_penetration);
    r.master_penetration = std::max(r.master_penetration, c.master_penetration);
    r.spring = std::max(r.spring, c.contact_energy);
    r.contact_steps += run.method && !run.method->contact_forces().empty();
  }
  return r;
}

}  // namespace conserve::test
