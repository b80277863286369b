#pragma once
/// A scenario wired into a stepper: the model it describes, its assembler,
/// contact set and integrator with the scenario's settings, and the step
/// control around them (cutback). The one wiring used by `conserve run`
/// (simulation/run.hpp) and by the tests, so that both step alike.
#include <memory>
#include <string>

#include "assembly/threads.hpp"
#include "contact/elimination/held_method.hpp"
#include "contact/method.hpp"
#include "core/error.hpp"
#include "io/scenario.hpp"
#include "simulation/checkpoint.hpp"
#include "simulation/fingerprint.hpp"
#include "simulation/setup.hpp"
#include "solver/newton.hpp"
#include "time/integrator.hpp"

namespace conserve::simulation {

/// The Newton and linear-solver settings of a scenario's [newton] and
/// [solver] tables: the one mapping, used by the Stepper and by tests that
/// drive the time layer with the program's defaults.
[[nodiscard]] solver::NewtonSettings newton_settings(const io::NewtonSpec& newton, const io::SolverSpec& solver);
[[nodiscard]] solver::LinearSolverSettings linear_settings(const io::SolverSpec& solver);

/// The last converged state could not be advanced even at the cutback
/// floor [time].min_step.
class FloorReached : public SolverError {
 public:
  FloorReached(const std::string& reason, double dt) : SolverError(reason), dt_(dt) {}
  [[nodiscard]] double dt() const { return dt_; }  ///< the step size that failed [s]

 private:
  double dt_;
};

template <int D>
class Stepper {
 public:
  /// Builds the model (simulation/setup.hpp) and its contact pairs; throws
  /// InputError on bad input. `scenario` must outlive the stepper. On
  /// several ranks the model then keeps this rank's cells alone
  /// (model::keep_cells): everything that needs every cell is built here.
  explicit Stepper(const io::Scenario& scenario);
  Stepper(const Stepper&) = delete;
  Stepper& operator=(const Stepper&) = delete;

  [[nodiscard]] const io::Scenario& scenario() const { return scenario_; }
  [[nodiscard]] const Problem<D>& problem() const { return problem_; }
  [[nodiscard]] const assembly::Assembler<D>& assembler() const { return *assembler_; }
  /// The contact method; null without contact pairs.
  [[nodiscard]] contact::Method<D>* contact() { return contact_.get(); }
  /// The contact pairs (none without contact).
  [[nodiscard]] const std::vector<contact::ContactPair<D>>& pairs() const { return pairs_; }
  /// What `conserve check` warns of in the scenario (simulation/plausibility.hpp).
  [[nodiscard]] const std::vector<std::string>& warnings() const { return warnings_; }
  /// The scenario's and the model's fingerprint for checkpoints (simulation/fingerprint.hpp).
  [[nodiscard]] const Fingerprint& fingerprint() const { return fingerprint_; }
  /// The active set when the method holds constraints (elimination, multipliers), else null.
  [[nodiscard]] contact::ActiveSet<D>* active_set() {
    auto* e = dynamic_cast<contact::HeldMethod<D>*>(contact_.get());
    return e ? &e->active_set() : nullptr;
  }
  [[nodiscard]] time::Integrator<D>& integrator() { return *integrator_; }
  /// Δt to try next and the cutback counters (saved in checkpoints).
  [[nodiscard]] StepControl& control() { return control_; }
  /// The assembly's threads ([solver] threads), re-chosen before each step.
  [[nodiscard]] const assembly::ThreadGovernor& threads() const { return threads_; }

  /// One converged step from `state`: retried from the same state (and the
  /// same active set) after a failure, first at the same Δt with fresh
  /// tangents if it kept one (modified Newton), then with Δt halved after
  /// each failure; Δt doubles back
  /// towards the scenario's after StepControl::kGrowAfter good steps.
  /// With impacts located, a step that meets an impact is retried ending
  /// where the integrator says (at most kMaxSplits times); the steps
  /// after it are full ones again. No step goes past the scenario's end
  /// time. `dt_used` and `failures` tell what it took. Throws FloorReached.
  StepRecord advance(model::State& state, double& dt_used, int& failures);
  /// Why the last failed attempt of advance() failed (empty if none has).
  [[nodiscard]] const std::string& last_failure() const { return last_failure_; }

 private:
  /// Attempts of one step given up to end it at an impact before the
  /// slaves are activated with whatever gap they have.
  static constexpr int kMaxSplits = 8;
  const io::Scenario& scenario_;
  Problem<D> problem_;
  std::unique_ptr<assembly::Assembler<D>> assembler_;
  std::vector<contact::ContactPair<D>> pairs_;  ///< as built (the method holds its own)
  std::unique_ptr<contact::Method<D>> contact_;
  std::unique_ptr<time::Integrator<D>> integrator_;
  StepControl control_;
  assembly::ThreadGovernor threads_;
  std::vector<std::string> warnings_;
  Fingerprint fingerprint_;
  std::string last_failure_;
};

}  // namespace conserve::simulation
