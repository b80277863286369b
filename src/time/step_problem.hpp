#pragma once
/// One step of the energy–momentum conserving mid-point scheme as a Newton
/// problem in u_{n+1} (paper (19)–(20)):
///   g(u_{n+1}) = (2/Δt²) M Δu − (2/Δt) M V_n + f_int(u_n, u_{n+1}) − f_ext
/// With active contact constraints the unknowns are the reduced q of the
/// direct elimination (Δu = T q, r = Tᵀ g, K_r = Tᵀ K T + β); without,
/// q = Δu. Prescribed dofs carry their prescribed value; their rows are
/// trivial.
#include "assembly/assembler.hpp"
#include "assembly/dirichlet.hpp"
#include "contact/elimination.hpp"
#include "model/state.hpp"
#include "solver/newton.hpp"
#include "solver/timings.hpp"

namespace conserve::time {

template <int D>
class StepProblem final : public solver::NewtonProblem {
 public:
  /// `u_np1` holds the predictor on entry and the iterate throughout;
  /// `K` has the assembler's pattern and is overwritten. `elimination`
  /// may be null (no active constraint).
  StepProblem(const assembly::Assembler<D>& assembler, const assembly::DirichletMask& mask, fem::StressScheme scheme,
              const model::State& start, double dt, Eigen::VectorXd& u_np1, SparseMatrix& K,
              contact::Elimination<D>* elimination = nullptr);

  void residual(Eigen::VectorXd& r) override;
  const SparseMatrix& tangent() override;
  void update(const Eigen::VectorXd& increment) override;
  [[nodiscard]] double force_scale() const override { return force_scale_; }
  [[nodiscard]] double length_scale() const override { return assembler_.model().size(); }
  /// The full residual g at the last residual() call: on an active slave,
  /// the contact force it receives (33) [N].
  [[nodiscard]] const Eigen::VectorXd& full_residual() const { return g_; }
  /// Accumulate assembly and elimination times there (may be null).
  void set_timings(solver::Timings* timings) { timings_ = timings; }

 private:
  [[nodiscard]] bool eliminating() const { return elimination_ && !elimination_->empty(); }
  const assembly::Assembler<D>& assembler_;
  const assembly::DirichletMask& mask_;
  fem::StressScheme scheme_;
  const model::State& start_;
  double dt_;
  Eigen::VectorXd& u_np1_;
  SparseMatrix& K_;
  contact::Elimination<D>* elimination_;
  SparseMatrix K_reduced_;
  assembly::DirichletMask reduced_mask_;
  Eigen::VectorXd inertia_n_;  ///< (2/Δt) M V_n + f_ext: the constant part
  Eigen::VectorXd f_int_, g_, du_;
  double force_scale_ = 0.0;
  solver::Timings* timings_ = nullptr;
  double unused_ = 0.0;
  double& clock(double solver::Timings::*phase) { return timings_ ? timings_->*phase : unused_; }
};

}  // namespace conserve::time
