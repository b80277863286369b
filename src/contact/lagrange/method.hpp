#pragma once
/// Lagrange multipliers (`[[contact]] method = "lagrange"`): the very
/// constraints elimination holds, held by the same pieces
/// (contact/elimination/held_method.hpp), imposed instead by one multiplier per constrained direction
/// as extra unknowns, so that the two methods solve the same discrete
/// problem. For one solve, with the elimination's maps Δu = T q (trial)
/// and r = Wᵀ g (test) at the iterate,
///   g(u) + B λ = 0,   β c(u) = 0,
/// B's columns spanning the forces Wᵀ leaves out (Wᵀ B = 0: at a slave a
/// direction ν its test slips miss, at its facets' nodes −W_aᵀ ν, from
/// each constraint's own coefficients: a facet node that is itself a slave
/// (a chain) takes the force and passes it on through its own multiplier,
/// where elimination composes the maps), c the slave's distance from
/// where the constraint holds (elimination's enforce()) along the
/// directions μ its trial slips miss, and β =
/// (2/Δt²) × the mean nodal mass, so that both rows are forces. Newton
/// solves for (u, λ) with [[K + ∂(Bλ)/∂u, B], [β C, 0]], C = ∂c/∂u from
/// T, B's own variation by automatic differentiation of the zero-work
/// kernels (Elimination::force_variation; how a Coulomb slave's force
/// direction turns with its slip is in it), left out only for a slave
/// holding two constraints, in cycles and beyond one link of a chain. At a
/// solution Wᵀ g = 0 and c = 0, elimination's equations: the trajectories
/// agree to the solvers' tolerance. The number of equations is the free
/// unknowns plus one per frictionless and D per stick constraint.
#include "contact/elimination/held_method.hpp"

namespace conserve::contact {

template <int D>
class LagrangeMethod final : public HeldMethod<D> {
 public:
  LagrangeMethod(const model::Model<D>& model, const SparseMatrix& mass, std::vector<ContactPair<D>> pairs,
                 const ImpactLocation& location, bool persistent);
  [[nodiscard]] std::string_view name() const override { return "lagrange"; }
  [[nodiscard]] std::unique_ptr<Coupling> coupling(const Eigen::VectorXd& u_n, const Eigen::VectorXd& u_np1) override;

 private:
  double mean_mass_ = 0.0;  ///< mean of the dofs' mass matrix's diagonal [kg]
};

}  // namespace conserve::contact
