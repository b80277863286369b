#pragma once
/// One step of the energy–momentum conserving mid-point scheme as a Newton
/// problem in u_{n+1} (paper (19)–(20)):
///   g(u_{n+1}) = (2/Δt²) M Δu − (2/Δt) M V_n + f_int(u_n, u_{n+1}) − f_ext
/// Prescribed dofs carry their prescribed value; their rows are trivial.
#include "assembly/assembler.hpp"
#include "assembly/dirichlet.hpp"
#include "model/state.hpp"
#include "solver/newton.hpp"

namespace conserve::time {

template <int D>
class StepProblem final : public solver::NewtonProblem {
 public:
  /// `u_np1` holds the predictor on entry and the iterate throughout;
  /// `K` has the assembler's pattern and is overwritten.
  StepProblem(const assembly::Assembler<D>& assembler, const assembly::DirichletMask& mask, fem::StressScheme scheme,
              const model::State& start, double dt, Eigen::VectorXd& u_np1, SparseMatrix& K);

  void residual(Eigen::VectorXd& r) override;
  const SparseMatrix& tangent() override;
  void update(const Eigen::VectorXd& increment) override { u_np1_ += increment; }
  [[nodiscard]] double force_scale() const override { return force_scale_; }
  [[nodiscard]] double length_scale() const override { return assembler_.model().size(); }

 private:
  const assembly::Assembler<D>& assembler_;
  const assembly::DirichletMask& mask_;
  fem::StressScheme scheme_;
  const model::State& start_;
  double dt_;
  Eigen::VectorXd& u_np1_;
  SparseMatrix& K_;
  Eigen::VectorXd inertia_n_;  ///< (2/Δt) M V_n + f_ext: the constant part
  Eigen::VectorXd f_int_;
  double force_scale_ = 0.0;
};

}  // namespace conserve::time
