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
                            StepTerms<D>& terms, const model::State& start, double dt, Eigen::VectorXd& u_np1,
                            SparseMatrix& K, contact::Coupling* coupling)
    : assembler_(assembler),
      mask_(mask),
      terms_(terms),
      start_(start),
      dt_(dt),
      u_np1_(u_np1),
      K_(K),
      coupling_(coupling) {
  take_scales();
}

template <int D>
StepProblem<D>::StepProblem(const assembly::Assembler<D>& assembler, const assembly::DirichletMask& mask,
                            fem::StressScheme scheme, const model::State& start, double dt, Eigen::VectorXd& u_np1,
                            SparseMatrix& K, contact::Coupling* coupling)
    : own_terms_(elastodynamic_terms(assembler, scheme)),
      assembler_(assembler),
      mask_(mask),
      terms_(own_terms_),
      start_(start),
      dt_(dt),
      u_np1_(u_np1),
      K_(K),
      coupling_(coupling) {
  for (const auto& term : terms_) term->begin(start, dt);
  take_scales();
}

template <int D>
void StepProblem<D>::take_scales() {
  for (const auto& term : terms_) {
    start_scale_ = std::max(start_scale_, term->start_force());
    energy_n_ += term->start_energy();
  }
  force_scale_ = start_scale_;
}

template <int D>
bool StepProblem<D>::abandon(double residual, double force_scale) {
  if (!check_ || checked_ || !(residual <= check_at_ * force_scale)) return false;
  checked_ = true;
  return check_(u_np1_);
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
    g_.setZero(u_np1_.size());
    magnitude_.setZero(u_np1_.size());
    assembled_ = assemble_with_residual_;
    assemble_with_residual_ = false;
    if (assembled_) {
      std::fill(K_.valuePtr(), K_.valuePtr() + K_.nonZeros(), 0.0);
      for (const auto& term : terms_) term->add_value_and_derivative(u_np1_, g_, magnitude_, K_);
    } else {
      for (const auto& term : terms_) term->add_value(u_np1_, g_, magnitude_);
    }
    mask_.apply(magnitude_);
    floor_ = kRoundOff * magnitude_.norm();
    du_ = u_np1_ - start_.u;
    Eigen::VectorXd free_motion = du_;  // the prescribed dofs' residual is masked: it does no work
    mask_.apply(free_motion);
    motion_ = free_motion.norm();
  }
  const int free = static_cast<int>(g_.size() - static_cast<Eigen::Index>(mask_.dofs().size()));
  equations_ = (coupled() ? coupling_->equations(free) : free) + (bodies_ ? bodies_->unknowns() : 0);
  if (coupled()) {
    solver::ScopedTimer timer(clock(&solver::Timings::elimination));
    coupling_->residual(u_np1_, g_, magnitude_, r);
    mask_.apply(magnitude_);
    floor_ = kRoundOff * magnitude_.norm();
  } else {
    r = g_;
  }
  // The reactions of the prescribed dofs are external forces too: in a
  // displacement-driven step they are the load, and a tool pressing a body
  // at rest is the only force of the step. They are the system's residual
  // there, where a constraint method has passed its contact forces on (a
  // rigid master's share N^T g_s of its slaves' forces (41), (56)).
  reaction_.setZero(g_.size());
  for (int d : mask_.dofs()) reaction_[d] = r[d];
  force_scale_ = std::max(start_scale_, reaction_.norm());
  Eigen::VectorXd bodies;
  if (bodies_) {
    bodies_->residual(u_np1_, r, bodies);
    floor_ = std::hypot(floor_, kRoundOff * bodies_->magnitude().norm());
  }
  mask_.apply(r);
  if (bodies_) {
    const Eigen::Index n = r.size();
    r.conservativeResize(n + bodies.size());
    r.tail(bodies.size()) = bodies;
  }
}

template <int D>
const SparseMatrix& StepProblem<D>::tangent() {
  if (observer_) observer_(u_np1_);
  if (!assembled_) {
    solver::ScopedTimer timer(clock(&solver::Timings::assembly));
    std::fill(K_.valuePtr(), K_.valuePtr() + K_.nonZeros(), 0.0);
    for (const auto& term : terms_) term->add_derivative(u_np1_, K_);
  }
  assembled_ = false;
  // Prescribed rows get the inertia's mean diagonal: of the order of the
  // others, whatever the stiffness.
  const double diagonal = 2.0 / (dt_ * dt_) * assembler_.mean_dof_mass();
  SparseMatrix* system = &K_;
  if (coupled()) {
    solver::ScopedTimer timer(clock(&solver::Timings::elimination));
    // K_reduced_'s pattern changes only when the coupling's does (an
    // elimination's constraints' nodes, a penalty's pairs): then the mask
    // is remade.
    if (coupling_->tangent(u_np1_, K_, g_, K_reduced_))
      reduced_mask_ = assembly::DirichletMask(K_reduced_, mask_.dofs(), mask_.owned());
    system = &K_reduced_;
  }
  const SparseMatrix unmasked = bodies_ ? *system : SparseMatrix();  // the bodies read its held rows and columns
  (coupled() ? reduced_mask_ : mask_).apply(*system, diagonal);
  if (!bodies_) return *system;
  bodies_->tangent(unmasked, *system, K_bodies_);
  return K_bodies_;
}

template <int D>
void StepProblem<D>::update(const Eigen::VectorXd& increment) {
  assembled_ = false;
  u_before_ = u_np1_;
  // The free bodies move their nodes (what follows them, a slave, moves
  // with those nodes' increments), then are placed exactly.
  Eigen::VectorXd system;
  if (bodies_) {
    const Eigen::Index n = increment.size() - bodies_->unknowns();
    system = increment.head(n);
    bodies_->save();
    bodies_->update(increment.tail(bodies_->unknowns()), system);
  }
  const Eigen::VectorXd& step = bodies_ ? system : increment;
  if (coupled()) {
    solver::ScopedTimer timer(clock(&solver::Timings::elimination));
    coupling_->save();
    coupling_->update(step, u_np1_);
  } else {
    u_np1_ += step;
  }
  if (bodies_) bodies_->place(u_np1_);
}

template <int D>
bool StepProblem<D>::revert() {
  if (u_before_.size() != u_np1_.size()) return false;
  if (coupled() && !coupling_->restore()) return false;
  assembled_ = false;
  if (bodies_) bodies_->restore();
  u_np1_ = u_before_;
  return true;
}

template class StepProblem<2>;
template class StepProblem<3>;

}  // namespace conserve::time
