#pragma once
/// Geometry of one linear master facet (a 2-node segment in 2D, a 3-node
/// triangle in 3D) and the closest-point projection of a slave point on it
/// (paper (27)–(29); docs/theory.md, "Contact geometry (27)–(29)"). Free
/// functions in derivative families: value, `_gradient` (with respect to y =
/// (x_s, x_0, …, x_{D−1}), D(D+1) entries, slave first).
#include <vector>

#include "core/types.hpp"

namespace conserve::contact {

/// Facet node positions, one column per node: D × D.
template <int D>
using FacetNodes = Eigen::Matrix<double, D, D>;
/// Isoparametric coordinates on the facet: ξ (2D) or (ξ, η) (3D).
template <int D>
using Xi = Eigen::Matrix<double, D - 1, 1>;
/// Covariant basis (τ_ξ[, τ_η]) as columns: D × (D−1).
template <int D>
using Tangents = Eigen::Matrix<double, D, D - 1>;
/// Number of entries of y = (x_s, x_0, …, x_{D−1}).
template <int D>
inline constexpr int kPairDofs = D * (D + 1);
template <int D>
using PairGradient = Eigen::Matrix<double, 1, kPairDofs<D>>;

/// Shape functions N_0 = 1 − Σ ξ_k, N_k = ξ_k (k = 1…D−1): D values.
template <int D>
Vec<D> facet_shape(const Xi<D>& xi) {
  Vec<D> N;
  N(0) = 1.0 - xi.sum();
  N.template tail<D - 1>() = xi;
  return N;
}

/// τ_k = ∂x/∂ξ_k = x_k − x_0 (constant on a linear facet).
template <int D>
Tangents<D> facet_tangents(const FacetNodes<D>& x) {
  return x.template rightCols<D - 1>().colwise() - x.col(0);
}

/// Outward unit normal: (τ_ξ × τ_η)/|·| in 3D, (τ_y, −τ_x)/|τ| in 2D (the
/// orientation of mesh::boundary_facets).
template <int D>
Vec<D> facet_normal(const FacetNodes<D>& x);

/// The closest-point projection of a slave point on a facet's plane (line).
template <int D>
struct Projection {
  Xi<D> xi = Xi<D>::Zero();    ///< ξ̄: x̄ = Σ N_i(ξ̄) x_i; not clamped to the facet
  Vec<D> point = Vec<D>::Zero();  ///< x̄, the projected point
  Vec<D> normal = Vec<D>::Zero(); ///< n, outward unit normal of the master
  Tangents<D> tangents = Tangents<D>::Zero();  ///< τ_ξ[, τ_η]
  double gap = 0.0;               ///< g_N = (x_s − x̄)·n; < 0 is penetration [m]

  /// ξ̄ lies in the closed facet, enlarged by `tol` in isoparametric units.
  [[nodiscard]] bool inside(double tol = 0.0) const {
    return xi.minCoeff() >= -tol && xi.sum() <= 1.0 + tol;
  }
};

/// Projection of x_s on the plane (line) through the facet: solves
/// τᵀ(x_s − x(ξ)) = 0 exactly (linear facets: a (D−1)×(D−1) metric system).
/// This is the closest point of the facet whenever inside() holds.
template <int D>
Projection<D> project(const Vec<D>& x_s, const FacetNodes<D>& x);

/// What project() needs of a facet besides the slave: its first node, τ,
/// n and the inverse metric (τᵀτ)⁻¹. Kept per facet while the nodes do
/// not move, it makes a projection a few dot products.
template <int D>
struct FacetFrame {
  Vec<D> origin = Vec<D>::Zero();
  Tangents<D> tangents = Tangents<D>::Zero();
  Vec<D> normal = Vec<D>::Zero();
  Mat<D - 1> inverse_metric = Mat<D - 1>::Zero();
};
template <int D>
FacetFrame<D> facet_frame(const FacetNodes<D>& x);
/// project() on a frame: the same numbers, bit for bit.
template <int D>
Projection<D> project(const Vec<D>& x_s, const FacetFrame<D>& frame);

/// The frames of a surface's facets at the positions of one search, each
/// made on its first use.
template <int D>
class FacetFrames {
 public:
  /// Forgets them all (the nodes moved): `facets` facets.
  void reset(int facets) {
    ready_.assign(static_cast<std::size_t>(facets), 0);
    frames_.resize(static_cast<std::size_t>(facets));
  }
  /// Facet f's frame, from its nodes x if not made since reset().
  const FacetFrame<D>& get(int f, const FacetNodes<D>& x) {
    const auto k = static_cast<std::size_t>(f);
    if (!ready_[k]) frames_[k] = facet_frame<D>(x), ready_[k] = 1;
    return frames_[k];
  }

 private:
  std::vector<FacetFrame<D>> frames_;
  std::vector<char> ready_;
};

/// The point of the closed facet nearest to x_s (clamped to its edges and
/// vertices): its ξ (inside the facet) and the distance [m].
template <int D>
std::pair<Xi<D>, double> closest_point_on_facet(const Vec<D>& x_s, const FacetNodes<D>& x);
/// The same, given x_s's projection p on the facet.
template <int D>
std::pair<Xi<D>, double> closest_point_on_facet(const Vec<D>& x_s, const FacetNodes<D>& x, const Projection<D>& p);

/// ∂g_N/∂y.
template <int D>
PairGradient<D> gap_gradient(const Vec<D>& x_s, const FacetNodes<D>& x);
/// ∂ξ̄/∂y: (D−1) × D(D+1).
template <int D>
Eigen::Matrix<double, D - 1, kPairDofs<D>> xi_gradient(const Vec<D>& x_s, const FacetNodes<D>& x);
/// ∂n/∂y: D × D(D+1) (the slave columns are zero).
template <int D>
Eigen::Matrix<double, D, kPairDofs<D>> normal_gradient(const FacetNodes<D>& x);
/// ∂τ/∂y with τ flattened column by column: D(D−1) × D(D+1) (constant).
template <int D>
Eigen::Matrix<double, D*(D - 1), kPairDofs<D>> tangents_gradient();

}  // namespace conserve::contact
