#include "time/step_problem.hpp"
#include <algorithm>
#include <cmath>
#include <limits>

namespace conserve::time {

/// Residual round-off per unit magnitude: a few ε (ε = 2.2e-16), for the
/// sums of a few terms per dof.
constexpr double kRoundOff = 32 * 2.2e-16;

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
      elimination_(elimination),
      cells_n_(assembler.step_start(start.u)) {
  const Eigen::VectorXd momentum_term = (2.0 / dt) * assembler.mass_times(start.v);
  inertia_n_ = momentum_term + assembler.gravity_force();
  Eigen::VectorXd f_n;
  assembler.internal_force(cells_n_, start.u, scheme, f_n);
  start_scale_ = std::max({momentum_term.norm(), assembler.gravity_force().norm(), f_n.norm()});
  force_scale_ = start_scale_;
  magnitude_n_ = (2.0 / dt) * assembler.mass_times(start.v.cwiseAbs()) + assembler.gravity_force().cwiseAbs() +
                 assembler.stiffness_scale();
  energy_n_ = 0.25 * dt * start.v.dot(momentum_term) + assembler.strain_energy(start.u) +
              std::abs(assembler.gravity_force().dot(start.u));
}

template <int D>
double StepProblem<D>::floor_scale() const {
  // Motion below the round-off of the positions does no work (a body at
  // rest: every scale is round-off there).
  const double still = 1e-14 * assembler_.model().size() * std::sqrt(static_cast<double>(du_.size()));
  if (!(motion_ > still)) return std::numeric_limits<double>::infinity();
  return std::max(force_scale_, energy_n_ / motion_);
}

template <int D>
void StepProblem<D>::residual(Eigen::VectorXd& r) {
  {
    solver::ScopedTimer timer(clock(&solver::Timings::assembly));
    assembler_.internal_force(cells_n_, u_np1_, scheme_, f_int_, &magnitude_);
    du_ = u_np1_ - start_.u;
    g_ = (2.0 / (dt_ * dt_)) * assembler_.mass_times(du_) - inertia_n_ + f_int_;
    // Δu = u_{n+1} − u_n is exact only to ε(|u_{n+1}| + |u_n|): at small
    // steps the inertia term amplifies that by 2/Δt².
    magnitude_ += (2.0 / (dt_ * dt_)) * assembler_.mass_times(u_np1_.cwiseAbs() + start_.u.cwiseAbs()) + magnitude_n_;
    mask_.apply(magnitude_);
    floor_ = kRoundOff * magnitude_.norm();
    Eigen::VectorXd free_motion = du_;  // the prescribed dofs' residual is masked: it does no work
    mask_.apply(free_motion);
    motion_ = free_motion.norm();
    // The reactions of the prescribed dofs are external forces too: in a
    // displacement-driven step they are the load.
    double reactions = 0.0;
    for (int d : mask_.dofs()) reactions += g_[d] * g_[d];
    force_scale_ = std::max(start_scale_, std::sqrt(reactions));
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
    assembler_.internal_force_tangent(cells_n_, u_np1_, scheme_, f_int_, K_);
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
  // K_reduced_'s pattern changes only when the constraints' nodes do
  // (facet switches, another active set): then the mask is remade.
  if (elimination_->reduce_tangent(K_, g_, K_reduced_))  // (43), (58)
    reduced_mask_ = assembly::DirichletMask(K_reduced_, mask_.dofs());
  reduced_mask_.apply(K_reduced_, diagonal);
  return K_reduced_;
}

template <int D>
void StepProblem<D>::update(const Eigen::VectorXd& increment) {
  u_before_ = u_np1_;
  if (eliminating()) {
    solver::ScopedTimer timer(clock(&solver::Timings::elimination));
    elimination_->save(elimination_before_);
    elimination_->update(increment, u_np1_);  // (45), (60)–(64)
  } else {
    u_np1_ += increment;
  }
}

template <int D>
bool StepProblem<D>::revert() {
  if (u_before_.size() != u_np1_.size() || (eliminating() && !elimination_before_)) return false;
  u_np1_ = u_before_;
  if (eliminating()) elimination_->restore(*elimination_before_);
  return true;
}

template class StepProblem<2>;
template class StepProblem<3>;

}  // namespace conserve::time
