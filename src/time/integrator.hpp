#pragma once
/// Advances the state step by step with the conserving mid-point scheme,
/// reusing the tangent's pattern and the linear solver.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "assembly/assembler.hpp"
#include "assembly/dirichlet.hpp"
#include "contact/method.hpp"
#include "model/state.hpp"
#include "solver/newton.hpp"
#include "time/free_bodies.hpp"
#include "time/predictor.hpp"
#include "time/step_terms.hpp"

namespace conserve::time {

/// What a support (model::Support) applied to the bodies over a step.
struct SupportReaction {
  Vec3 force = Vec3::Zero();   ///< Σ of its dofs' reactions [N] (2D: z = 0)
  Vec3 moment = Vec3::Zero();  ///< their moment about the origin at the mid-point positions [N m]
};

template <int D>
class Integrator {
 public:
  /// `contact` (may be null) is the contact method (contact/method.hpp);
  /// it must outlive the integrator. `max_passes` bounds the solves of one
  /// step while the contact state changes.
  Integrator(const assembly::Assembler<D>& assembler, fem::StressScheme scheme, solver::NewtonSettings newton,
             contact::Method<D>* contact = nullptr, int max_passes = 10,
             const solver::LinearSolverSettings& linear = {});

  /// Advances `state` by `dt` [s]: the predictor (set_predictor) with prescribed
  /// values at t_{n+1}, Newton on the system the contact method's coupling
  /// forms, the method's verdict and, if its state changed, the same step
  /// again (docs/theory.md, "The step with contact"); then
  /// V_{n+1} = (2/Δt)Δu − V_n (19), as the method leaves it.
  /// The report's iterations count all passes. Throws SolverError naming
  /// the step if Newton does not converge (and why), if the active set does
  /// not settle in max_passes, or if a cell ends the step inverted
  /// (det F ≤ 0, naming body and cell); the state is then left unchanged.
  /// A step the method splits at an impact is not taken either: the report
  /// is not converged and contact_stats().split_fraction < 1 tells where
  /// the step should end; the caller restores the method's state
  /// (Method::load) and steps again with that Δt.
  /// That shorter step starts from the longer one's last iterate (its
  /// correction to the predictor, scaled by the ratio of the steps).
  solver::NewtonReport step(model::State& state, double dt);

  /// Forgets the matrix kept for reuse (modified Newton) and what the
  /// solver keeps across matrices: at a change of Δt and after a failed
  /// attempt, as every run does.
  void drop_factorization() {
    plain_factorization_ = false;
    memory_ = {};
    kept_.reset();
    source_.reset();
    solver_->reset();
  }

  /// Modified Newton (solver::NewtonSettings::modified_newton) for the
  /// steps that follow: simulation::Stepper tries a step that failed with
  /// a kept tangent again with fresh ones before it halves Δt.
  void set_modified_newton(bool on) { newton_.modified_newton = on; }
  [[nodiscard]] bool modified_newton() const { return newton_.modified_newton; }

  /// What the next steps take from the earlier ones beyond the state: the
  /// tangent kept for reuse (modified Newton) and what the solver derived
  /// from earlier matrices, as the states and iterates those matrices were
  /// assembled at (not the matrices), the forcing terms' measure and the
  /// solver's own state. load() assembles those matrices again and sets
  /// the solver with them, so that a run restarted from a checkpoint
  /// repeats the uninterrupted one bit for bit, and writing a checkpoint
  /// changes nothing. Throws InputError naming `what` on bytes it cannot read.
  [[nodiscard]] std::string save() const;
  void load(const std::string& bytes, const std::string& what);

  /// After each step, set the active slaves' relative velocity to zero
  /// and give its energy back (contact/elimination/persistent_velocity.hpp); off: the
  /// mid-point velocity (19) alone, as in the paper.
  void set_persistent_contact(bool on);

  /// Newton's start for each step (time/predictor.hpp); `velocity` until set.
  void set_predictor(Predictor predictor);

  /// The mean force over the last step that the prescribed motions applied
  /// at their dofs (a support's reaction, a rigid tool's driving force),
  /// persistent contact's impulses at its end included; 0 on free dofs [N].
  /// Its work is added to State::support_work.
  [[nodiscard]] const Eigen::VectorXd& reactions() const { return reaction_; }
  /// reactions() summed per support (model::Prescribed::supports).
  [[nodiscard]] const std::vector<SupportReaction>& supports() const { return supports_; }

  /// What contact did in the last step.
  [[nodiscard]] const contact::StepContactStats& contact_stats() const { return stats_; }
  [[nodiscard]] const solver::LinearSolver& linear_solver() const { return *solver_; }
  /// Accumulated time per phase since construction.
  [[nodiscard]] const solver::Timings& timings() const { return timings_; }

 private:
  const assembly::Assembler<D>& assembler_;
  solver::NewtonSettings newton_;
  assembly::DirichletMask mask_;
  SparseMatrix K_;
  StepTerms<D> terms_;  ///< the step's residual is their sum
  contact::Method<D>* contact_;
  FreeBodies<D> bodies_;  ///< the free rigid bodies' motions (time/free_bodies.hpp)
  int max_passes_;
  std::optional<RigidMotion<D>> rigid_;  ///< set: Predictor::rigid
  std::unique_ptr<solver::LinearSolver> solver_;
  contact::StepContactStats stats_;
  Eigen::VectorXd reaction_;  ///< reactions()
  Eigen::VectorXd impulse_;   ///< the part of it from impulses at the step's end (empty: none)
  std::vector<SupportReaction> supports_;
  solver::Timings timings_;
  /// The last iterate of a step that was not taken because it met an
  /// impact (step()), which starts the shorter step from the same state.
  struct Interrupted {
    std::int64_t step = -1;      ///< the state's step it started from; −1: none
    double dt = 0.0;             ///< its Δt [s]
    Eigen::VectorXd correction;  ///< its last iterate u_{n+1} − its predictor [m]
  };
  Interrupted interrupted_;
  /// The relative residual (× the force scale) at which a solve's iterate
  /// is searched for an impact within the step (StepProblem::abandon). A
  /// first attempt is searched early: a rough fraction costs at most one
  /// more split, whereas every solve past it is thrown away with the
  /// attempt. A retry, already shortened to an estimate, is searched late:
  /// its fraction decides whether the slave ends the step within its gap
  /// tolerance (docs/theory.md, "Impacts located in time", 4).
  static constexpr double kSearchFirst = 1e-2;
  static constexpr double kSearchRetry = 1e-6;
  /// Where a plain (unreduced) tangent the solver was set with was
  /// assembled: the step's start and the iterate.
  struct Origin {
    Eigen::VectorXd u, v, iterate;
    double time = 0.0, dt = 0.0;
  };
  std::optional<Origin> kept_;    ///< the present matrix's, if plain
  std::optional<Origin> source_;  ///< the first of the solver's present generation, if plain
  std::uint64_t generation_ = 0;  ///< the solver's generation() at the last solve
  /// Assembles the plain tangent at `origin` into K_ and sets the solver with it.
  void set_again(const Origin& origin);
  bool plain_factorization_ = false;  ///< the solver holds a factorization of the unreduced system
  solver::NewtonMemory memory_;       ///< what the last solves measured (solver/newton.hpp)

  [[nodiscard]] std::string not_converged(const solver::NewtonReport& report, std::int64_t step, double t) const;
  void check_orientation(const Eigen::VectorXd& u, std::int64_t step, double t) const;
  /// impulse_ from the contact method's persistency impulses.
  void add_impulses(double dt);
  /// supports_ from reaction_ (at the mid-point positions of u_n → u_np1)
  /// and impulse_ (at the end ones), which joins reaction_; their work over
  /// the step added to state.support_work.
  void sum_supports(model::State& state, const Eigen::VectorXd& u_np1, const Eigen::VectorXd& work);
  [[nodiscard]] Eigen::VectorXd predictor(const model::State& state, double dt) const;
};

}  // namespace conserve::time
