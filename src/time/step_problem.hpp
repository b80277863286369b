#pragma once
/// One step of the energy–momentum conserving mid-point scheme as a Newton
/// problem in u_{n+1} (paper (19)–(20)): the residual g(u_{n+1}) is the sum
/// of the step's terms (time/step_terms.hpp; inertia, internal force, body
/// force), the tangent the sum of their derivatives. A contact method's
/// coupling (contact/method.hpp) forms the system from them: the reduced
/// q of the direct elimination (Δu = T q, r = Wᵀ g, K_r = Wᵀ K T + V + β),
/// a penalty's added forces, multipliers' added unknowns; without, q = Δu.
/// Prescribed dofs carry their prescribed value; their rows are trivial.
#include <functional>
#include <optional>

#include "assembly/assembler.hpp"
#include "assembly/dirichlet.hpp"
#include "contact/method.hpp"
#include "model/state.hpp"
#include "solver/newton.hpp"
#include "solver/timings.hpp"
#include "time/free_bodies.hpp"
#include "time/step_terms.hpp"

namespace conserve::time {

template <int D>
class StepProblem final : public solver::NewtonProblem {
 public:
  /// `terms` have begun the step from `start` with this Δt and must
  /// outlive the problem. `u_np1` holds the predictor on entry and the
  /// iterate throughout; `K` has the assembler's pattern and is
  /// overwritten. `coupling` may be null (no contact).
  StepProblem(const assembly::Assembler<D>& assembler, const assembly::DirichletMask& mask, StepTerms<D>& terms,
              const model::State& start, double dt, Eigen::VectorXd& u_np1, SparseMatrix& K,
              contact::Coupling* coupling = nullptr);
  /// The free rigid bodies' unknowns appended to the system (they must
  /// have begun the step and outlive the problem; null: none).
  void add_bodies(FreeBodies<D>* bodies) { bodies_ = bodies && !bodies->empty() ? bodies : nullptr; }
  /// With its own elastodynamic terms (time/step_terms.hpp), begun here.
  StepProblem(const assembly::Assembler<D>& assembler, const assembly::DirichletMask& mask, fem::StressScheme scheme,
              const model::State& start, double dt, Eigen::VectorXd& u_np1, SparseMatrix& K,
              contact::Coupling* coupling = nullptr);

  void residual(Eigen::VectorXd& r) override;
  const SparseMatrix& tangent() override;
  /// The next residual() assembles the terms' derivatives too, in the same
  /// pass over the cells; tangent() at that iterate uses them.
  void prepare_tangent() override { assemble_with_residual_ = true; }
  void update(const Eigen::VectorXd& increment) override;
  /// Back to the iterate before the last update, with the coupling's state
  /// as it was (an elimination's facets, ξ and maps move with the update).
  bool revert() override;
  /// The largest of the inertia, load and elastic force norms at the start
  /// of the step and of the prescribed dofs' reactions at the last residual.
  [[nodiscard]] double force_scale() const override { return force_scale_; }
  /// ε times the magnitudes the residual is a sum of (the cells' forces,
  /// their unit-strain forces, inertia and loads), masked: |r| cannot be
  /// computed more accurately than this [N].
  [[nodiscard]] double residual_floor() const override { return floor_; }
  /// A residual at its floor is judged by the energy error it can cause,
  /// |r|·|Δu| (Δu of the free dofs: the prescribed ones' residual is masked),
  /// against the step's energy, max(K_n + W_n + |Π_n|, force_scale·|Δu|):
  /// the force scale, or (K_n + W_n + |Π_n|)/|Δu| if larger (infinite when
  /// nothing moves beyond the round-off of the positions: no work is done).
  [[nodiscard]] double floor_scale() const override;
  /// Once the residual is below the level set by check_iterate() × the
  /// force scale, the iterate is shown once to its check: the iteration is
  /// abandoned if it returns true.
  bool abandon(double residual, double force_scale) override;
  /// The check of abandon(), given the iterate u_{n+1} (may be empty:
  /// none), and the relative residual at which it is made.
  void check_iterate(std::function<bool(const Eigen::VectorXd&)> check, double at) {
    check_ = std::move(check);
    check_at_ = at;
  }
  /// The full residual g at the last residual() call, contact forces a
  /// coupling adds included: on a slave held by a constraint, the contact
  /// force it receives (33) [N].
  [[nodiscard]] const Eigen::VectorXd& full_residual() const { return g_; }
  /// The force the prescribed motion applies at each prescribed dof at the
  /// last residual: the system's residual there, what a constraint method
  /// passed on to a prescribed master included; 0 on the free dofs [N].
  /// Σ Δu·reactions() is the work of the prescribed motion over the step.
  [[nodiscard]] const Eigen::VectorXd& reactions() const { return reaction_; }
  /// Called at each tangent() with the iterate it is taken at (before the
  /// coupling reduces it): what the solver is then set with comes from
  /// there (Integrator's checkpoints).
  void observe_tangents(std::function<void(const Eigen::VectorXd&)> observer) { observer_ = std::move(observer); }
  /// Accumulate assembly and contact-coupling times there (may be null).
  void set_timings(solver::Timings* timings) { timings_ = timings; }
  /// Unknowns of the system (its free ones), as of the last residual.
  [[nodiscard]] int equations() const { return equations_; }

 private:
  [[nodiscard]] bool coupled() const { return coupling_ && !coupling_->plain(); }
  /// The largest of the terms' start forces and the sum of their energies.
  void take_scales();
  StepTerms<D> own_terms_;  ///< the terms, if the problem made its own
  const assembly::Assembler<D>& assembler_;
  const assembly::DirichletMask& mask_;
  StepTerms<D>& terms_;
  const model::State& start_;
  double dt_;
  Eigen::VectorXd& u_np1_;
  SparseMatrix& K_;
  contact::Coupling* coupling_;
  FreeBodies<D>* bodies_ = nullptr;
  SparseMatrix K_reduced_;  ///< the coupled system's tangent
  SparseMatrix K_bodies_;   ///< the system's tangent with the free bodies' unknowns
  assembly::DirichletMask reduced_mask_;
  Eigen::VectorXd g_, du_, magnitude_, reaction_;
  Eigen::VectorXd u_before_;  ///< the iterate before the last update (revert)
  double start_scale_ = 0.0, force_scale_ = 0.0;
  double energy_n_ = 0.0;  ///< the terms' energies at the start: K_n + W_n + |Π_n| [J]
  double motion_ = 0.0;    ///< |Δu| over the free dofs at the last residual [m]
  double floor_ = 0.0;
  int equations_ = 0;
  solver::Timings* timings_ = nullptr;
  std::function<bool(const Eigen::VectorXd&)> check_;
  std::function<void(const Eigen::VectorXd&)> observer_;
  double check_at_ = 0.0;
  bool checked_ = false;
  bool assemble_with_residual_ = false;  ///< prepare_tangent() was called
  bool assembled_ = false;               ///< K_ holds the terms' derivatives at the iterate
  double unused_ = 0.0;
  double& clock(double solver::Timings::*phase) { return timings_ ? timings_->*phase : unused_; }
};

}  // namespace conserve::time
