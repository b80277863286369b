#pragma once
/// The velocity update of persistent contact (docs/theory.md, "Persistent
/// contact"). The mid-point rule's end velocity V* = (2/Δt)Δu − V_n (19)
/// reverses, step after step, any relative velocity a slave brought into
/// its constraint: the constraint holds the slave's gap (stick: its point)
/// at the end of every step, so Δg = 0 and ġ_{n+1} = −ġ_n. That parity
/// mode makes the contact force alternate in sign and the node chatter
/// (released and re-activated within a few steps). This update removes it
/// and gives its energy back, after each converged step:
///
///  1. persistency: impulses P_c along each active constraint's gradient
///     a_c (frictionless: the gap rate, a = (n, −N_b n); stick: the rate
///     of x_s − F(x_m), a = (1, −∂F/∂x_m), zero_work.hpp) set the relative
///     velocity of every active slave to zero, A V_p = 0, with the lumped
///     masses: V_p = V* + M_L⁻¹ Aᵀμ,  (A M_L⁻¹ Aᵀ) μ = −A V*. The impulses
///     have no resultant and no moment (frictionless: x_s − x̄ ∥ n; stick:
///     x_s = F(x_m), F frame-indifferent), so L and J are kept; with a
///     consistent M the rigid part of M(V_p − V*) is removed as well.
///  2. energy: the kinetic energy the impulses took, K* − K_p, is given
///     back by the smallest change of V_p in the kinetic (M-) norm that
///     keeps A V = 0, L and J: V = V_p + t w, w = V_p minus its M-orthogonal
///     projection on the rigid motions of the system (on V_p with the
///     prescribed dofs zeroed if there are any, since a fixed support
///     takes momentum), t the root of K(V_p + t w) = K* nearest 0.
///
/// The energy, L and J of the step are therefore those of V* exactly;
/// what changes is where the kinetic energy sits: not in the reversal of
/// the slaves' relative velocity, but in the motion of the bodies.
#include <Eigen/SparseCore>
#include <vector>

#include "contact/constraint.hpp"
#include "contact/method.hpp"
#include "model/model.hpp"

namespace conserve::contact {

/// What a velocity update after the step did.
struct VelocityUpdate {
  bool applied = false;       ///< false: V* kept (nothing to remove, or the update failed)
  double removed = 0.0;       ///< largest relative velocity of an active slave removed [m/s]
  double energy_moved = 0.0;  ///< K* − K_p, the kinetic energy given back [J]
  /// Why the update failed and V* was kept although the slaves moved
  /// relative to their facets (nullptr: it did not fail).
  const char* failure = nullptr;
};

/// A persistency impulse on a slave and the weights of its master's nodes.
template <int D>
struct SlaveImpulse {
  Vec<D> impulse = Vec<D>::Zero();  ///< on the slave [N s]
  FacetWeights<D> weights = FacetWeights<D>::Zero(D);  ///< N_b at the point of the facet it acts against
};

template <int D>
class PersistentVelocity {
 public:
  /// `mass` is the nodes' mass matrix M_AB (the assembler's node_mass(),
  /// consistent or lumped; the dofs' is M_AB ⊗ I_D) or a dofs' mass
  /// matrix; `model` gives the prescribed dofs; both must outlive the object.
  PersistentVelocity(const model::Model<D>& model, const SparseMatrix& mass);

  /// Updates the end-of-step velocities `v` for the active constraints at
  /// end positions `x` (see the file comment). Constraints on a free rigid
  /// body's facets keep the mid-point velocity (19): the update holds the
  /// body's nodes as supports.
  /// `impulses` (if given) receives per constraint the persistency
  /// impulse on its slave, Σ μ a_slave [N s] (zero if not applied), and
  /// the weights N_b with which its master's nodes took the opposite:
  /// what a prescribed master takes.
  VelocityUpdate apply(const std::vector<Constraint<D>>& constraints, const std::vector<ContactPair<D>>& pairs,
                       const Positions<D>& x, Eigen::VectorXd& v,
                       std::vector<SlaveImpulse<D>>* impulses = nullptr) const;

  /// Takes `energy` [J] out of the kinetic energy of `v` (gives it back if
  /// negative) by the step-2 change V = V + t w of the file comment
  /// without constraints: w is V with the prescribed dofs zeroed, minus its
  /// projection on the rigid motions (Rᵀ M w = 0), so L and J are kept and
  /// only the bodies' deformation velocity is scaled. False, `v`
  /// unchanged, if that motion cannot take it (|t| > 1/4).
  bool restore_energy(const Positions<D>& x, double energy, Eigen::VectorXd& v) const;

 private:
  /// Per dof: 1 / the lumped mass, 0 on prescribed and massless dofs.
  [[nodiscard]] Eigen::VectorXd free_inverse_mass() const;
  /// Rigid velocity fields at positions x, one per column: translations,
  /// then rotations about the centroid.
  [[nodiscard]] Eigen::MatrixXd rigid_modes(const Positions<D>& x) const;

  /// M x and M X (column by column).
  [[nodiscard]] Eigen::VectorXd times_mass(const Eigen::VectorXd& x) const;
  [[nodiscard]] Eigen::MatrixXd times_mass(const Eigen::MatrixXd& x) const;

  const model::Model<D>& model_;
  /// M_AB (nodes × nodes: M = M_AB ⊗ I_D, the assembler's) or the dofs' M.
  const SparseMatrix& mass_;
  bool nodal_;  ///< mass_ is M_AB
  Eigen::VectorXd lumped_;      ///< per dof: the row sum of M (the lumped mass)
  std::vector<char> prescribed_;  ///< per dof: held (prescribed, or a free rigid body's)
  std::vector<char> free_body_;   ///< per node: a free rigid body's
};

}  // namespace conserve::contact
