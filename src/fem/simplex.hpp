#pragma once
/// Linear simplices (3-node triangle, 4-node tetrahedron): constant
/// shape-function gradients, measure and mass.
#include <Eigen/LU>

#include "core/types.hpp"

namespace conserve::fem {

/// Node count of the linear simplex in D dimensions.
template <int D>
inline constexpr int kNodes = D + 1;

/// D × (D+1): one column per node (coordinates, displacements or gradients).
template <int D>
using NodeMatrix = Eigen::Matrix<double, D, D + 1>;

/// (D(D+1))² element matrix; dof (A, i) has index A·D + i.
template <int D>
using ElementMatrix = Eigen::Matrix<double, D*(D + 1), D*(D + 1)>;

/// Reference geometry at one quadrature point of a cell with N nodes: the
/// whole linear simplex (N = D+1, one point), or one point of a quadratic
/// one (fem/quadratic.hpp).
template <int D, int N>
struct PointGeometry {
  Eigen::Matrix<double, D, N> grad;  ///< column A = ∇_X N_A [1/m]
  double volume = 0.0;               ///< the point's weight × det J: reference volume [m³] (2D: area × thickness)
};

/// Reference geometry of one linear cell.
template <int D>
using SimplexGeometry = PointGeometry<D, D + 1>;

/// Signed measure (length/area/volume) of the simplex with nodes X:
/// det[X_1 − X_0, …, X_D − X_0] / D!. Positive for the positive orientation.
template <int D>
double signed_measure(const NodeMatrix<D>& X) {
  Mat<D> J;
  for (int a = 0; a < D; ++a) J.col(a) = X.col(a + 1) - X.col(0);
  return J.determinant() / (D == 2 ? 2.0 : 6.0);
}

/// Gradients and volume of a cell with reference nodes X; `thickness` [m]
/// multiplies the area in 2D (ignored in 3D). The caller checks the sign
/// with signed_measure first: a non-positive cell has no valid geometry.
template <int D>
SimplexGeometry<D> simplex_geometry(const NodeMatrix<D>& X, double thickness) {
  Mat<D> J;
  for (int a = 0; a < D; ++a) J.col(a) = X.col(a + 1) - X.col(0);
  const Mat<D> Jinv_t = J.inverse().transpose();
  SimplexGeometry<D> g;
  // ∇N_a = J⁻ᵀ ∇_ξ N_a with ∇_ξ N_0 = −(1,…,1), ∇_ξ N_a = e_{a−1}.
  g.grad.col(0) = -Jinv_t.rowwise().sum();
  g.grad.template rightCols<D>() = Jinv_t;
  g.volume = signed_measure<D>(X) * (D == 2 ? thickness : 1.0);
  return g;
}

/// Deformation gradient F = Σ_A x_A ⊗ ∇N_A for nodal positions x.
template <int D>
Mat<D> deformation_gradient(const NodeMatrix<D>& x, const SimplexGeometry<D>& g) {
  return x.lazyProduct(g.grad.transpose());  // coefficient-wise: no temporary, no aliasing check
}

/// Consistent mass M_AB = ρ V (1 + δ_AB) / ((D+1)(D+2)), or the lumped
/// (row-sum) mass ρ V/(D+1) δ_AB [kg]. Both have the total ρV.
template <int D>
Eigen::Matrix<double, D + 1, D + 1> element_mass(double density, double volume, bool lumped) {
  using M = Eigen::Matrix<double, D + 1, D + 1>;
  if (lumped) return M::Identity() * (density * volume / (D + 1));
  const double c = density * volume / ((D + 1) * (D + 2));
  return c * (M::Ones() + M::Identity());
}

}  // namespace conserve::fem
