#include "time/step_problem.hpp"

namespace conserve::time {

template <int D>
StepProblem<D>::StepProblem(const assembly::Assembler<D>& assembler, const assembly::DirichletMask& mask,
                            fem::StressScheme scheme, const model::State& start, double dt, Eigen::VectorXd& u_np1,
                            SparseMatrix& K, contact::Elimination<D>* elimination)
    : assembler_(assembler),
      mask_(mask),
      scheme_(scheme),
      start_(start),
      dt_(dt),
      u_np1_(u_np1),
      K_(K),
      elimination_(elimination) {
  const Eigen::VectorXd momentum_term = (2.0 / dt) * (assembler.mass() * start.v);
  inertia_n_ = momentum_term + assembler.gravity_force();
  Eigen::VectorXd f_n;
  assembler.internal_force(start.u, start.u, scheme, f_n);
  force_scale_ = std::max({momentum_term.norm(), assembler.gravity_force().norm(), f_n.norm()});
}

template <int D>
void StepProblem<D>::residual(Eigen::VectorXd& r) {
  {
    solver::ScopedTimer timer(clock(&solver::Timings::assembly));
    assembler_.internal_force(start_.u, u_np1_, scheme_, f_int_);
    g_ = (2.0 / (dt_ * dt_)) * (assembler_.mass() * (u_np1_ - start_.u)) - inertia_n_ + f_int_;
  }
  if (eliminating()) {
    solver::ScopedTimer timer(clock(&solver::Timings::elimination));
    elimination_->reduce_residual(g_, r);  // (41), (56)
  } else {
    r = g_;
  }
  mask_.apply(r);
}

template <int D>
const SparseMatrix& StepProblem<D>::tangent() {
  {
    solver::ScopedTimer timer(clock(&solver::Timings::assembly));
    assembler_.internal_force_tangent(start_.u, u_np1_, scheme_, f_int_, K_);
  }
  const double c = 2.0 / (dt_ * dt_);
  const SparseMatrix& M = assembler_.mass();
  Eigen::Map<Eigen::VectorXd>(K_.valuePtr(), K_.nonZeros()) +=
      c * Eigen::Map<const Eigen::VectorXd>(M.valuePtr(), M.nonZeros());
  const double diagonal = c * M.diagonal().mean();
  if (!eliminating()) {
    mask_.apply(K_, diagonal);
    return K_;
  }
  solver::ScopedTimer timer(clock(&solver::Timings::elimination));
  elimination_->reduce_tangent(K_, g_, K_reduced_);  // (43), (58)
  if (!reduced_mask_.fits(K_reduced_))  // facet switches change the pattern
    reduced_mask_ = assembly::DirichletMask(K_reduced_, mask_.dofs());
  reduced_mask_.apply(K_reduced_, diagonal);
  return K_reduced_;
}

template <int D>
void StepProblem<D>::update(const Eigen::VectorXd& increment) {
  if (eliminating()) {
    solver::ScopedTimer timer(clock(&solver::Timings::elimination));
    elimination_->update(increment, u_np1_);  // (45), (60)–(64)
  } else {
    u_np1_ += increment;
  }
}

template class StepProblem<2>;
template class StepProblem<3>;

}  // namespace conserve::time
