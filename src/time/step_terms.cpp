#include "time/step_terms.hpp"

#include "time/surface_loads.hpp"

#include <cmath>

namespace conserve::time {

template <int D>
void Inertia<D>::begin(const model::State& start, double dt) {
  u_n_ = start.u;
  c_ = 2.0 / (dt * dt);
  momentum_ = (2.0 / dt) * assembler_.mass_times(start.v);
  momentum_magnitude_ = (2.0 / dt) * assembler_.mass_times(start.v.cwiseAbs()) + c_ * assembler_.mass_times(u_n_.cwiseAbs());
  kinetic_ = 0.25 * dt * start.v.dot(momentum_);
}

template <int D>
void Inertia<D>::add_value(const Eigen::VectorXd& u_np1, Eigen::VectorXd& g, Eigen::VectorXd& magnitude) {
  g += c_ * assembler_.mass_times(u_np1 - u_n_) - momentum_;
  // Δu = u_{n+1} − u_n is exact only to ε(|u_{n+1}| + |u_n|): at small
  // steps the factor 2/Δt² amplifies that.
  magnitude += c_ * assembler_.mass_times(u_np1.cwiseAbs()) + momentum_magnitude_;
}

template <int D>
void Inertia<D>::add_derivative(const Eigen::VectorXd&, SparseMatrix& K) {
  assembler_.add_mass(c_, K);
}

template <int D>
void InternalForce<D>::begin(const model::State& start, double) {
  // The state's measures (usually kept from the check of the step that
  // ended there); the midpoint scheme's force at rest differs from the
  // conserving one's in round-off only, but is its own.
  const auto& m = assembler_.measures(start.u);
  cells_n_ = m.cells;
  stored_ = m.strain_energy;
  start_force_ = m.force_norm;
  if (scheme_ != fem::StressScheme::conserving) {
    Eigen::VectorXd f_n;
    assembler_.internal_force(*cells_n_, start.u, scheme_, f_n);
    start_force_ = f_n.norm();
  }
}

template <int D>
void InternalForce<D>::add_value(const Eigen::VectorXd& u_np1, Eigen::VectorXd& g, Eigen::VectorXd& magnitude) {
  assembler_.add_internal_force(*cells_n_, u_np1, scheme_, g, &magnitude);
  add_round_off(u_np1, magnitude);
}

template <int D>
void InternalForce<D>::add_round_off(const Eigen::VectorXd& u_np1, Eigen::VectorXd& magnitude) const {
  // The round-off of E at small strains, and that of u itself (ε|u|).
  magnitude += assembler_.stiffness_scale() + assembler_.displacement_stiffness().cwiseProduct(u_np1.cwiseAbs());
}

template <int D>
void InternalForce<D>::add_value_and_derivative(const Eigen::VectorXd& u_np1, Eigen::VectorXd& g,
                                                Eigen::VectorXd& magnitude, SparseMatrix& K) {
  assembler_.add_internal_force_and_derivative(*cells_n_, u_np1, scheme_, g, magnitude, K);
  add_round_off(u_np1, magnitude);
}

template <int D>
void InternalForce<D>::add_derivative(const Eigen::VectorXd& u_np1, SparseMatrix& K) {
  assembler_.add_internal_force_derivative(*cells_n_, u_np1, scheme_, K);
}

template <int D>
void BodyForce<D>::begin(const model::State& start, double) {
  work_ = std::abs(assembler_.gravity_force().dot(start.u));
}

template <int D>
void BodyForce<D>::add_value(const Eigen::VectorXd&, Eigen::VectorXd& g, Eigen::VectorXd& magnitude) {
  g -= assembler_.gravity_force();
  magnitude += assembler_.gravity_force().cwiseAbs();
}

template <int D>
StepTerms<D> elastodynamic_terms(const assembly::Assembler<D>& assembler, fem::StressScheme scheme) {
  StepTerms<D> terms;
  terms.push_back(std::make_unique<Inertia<D>>(assembler));
  terms.push_back(std::make_unique<InternalForce<D>>(assembler, scheme));
  const auto& model = assembler.model();
  if (model.gravity_curve < 0) terms.push_back(std::make_unique<BodyForce<D>>(assembler));
  if (model.gravity_curve >= 0 || !model.loads.empty()) terms.push_back(std::make_unique<SurfaceLoads<D>>(assembler));
  return terms;
}

template class Inertia<2>;
template class Inertia<3>;
template class InternalForce<2>;
template class InternalForce<3>;
template class BodyForce<2>;
template class BodyForce<3>;
template StepTerms<2> elastodynamic_terms<2>(const assembly::Assembler<2>&, fem::StressScheme);
template StepTerms<3> elastodynamic_terms<3>(const assembly::Assembler<3>&, fem::StressScheme);

}  // namespace conserve::time
