#pragma once
/// Quadratic simplices (6-node triangle, 10-node tetrahedron, Gmsh's node
/// order, fem/lagrange.hpp), possibly curved: the reference map's inverse
/// Jacobian and weight at each quadrature point, and the mass.
///
/// Rules (fem/quadrature.hpp): the internal force and the stored energy use
/// the degree-2 rule (3 points on a triangle, 4 on a tetrahedron; exact for
/// the small-strain stiffness of a straight-sided cell). The conserving
/// step's energy and momenta are exact at each point separately (the
/// discrete gradient acts pointwise, Σ_A ∇N_A = 0 and S is symmetric at every
/// point), so they hold for this rule as for any. The consistent mass
/// ∫ρ N_A N_B uses the degree-4 (6-point) / degree-5 (14-point) rule, exact
/// for straight-sided cells.
#include <algorithm>
#include <array>

#include "fem/lagrange.hpp"
#include "fem/quadrature.hpp"
#include "fem/simplex.hpp"

namespace conserve::fem {

template <int D>
struct Quadratic {
  using Shape = Lagrange<D, 2>;
  static constexpr int kNodes = Shape::kNodes;                 ///< 6 or 10
  static constexpr int kPoints = rule_points<D, 2>();          ///< force and energy: 3 or 4
  static constexpr int kMassPoints = rule_points<D, D == 2 ? 4 : 5>();  ///< mass: 6 or 14
  using Nodes = Eigen::Matrix<double, D, kNodes>;
  using Matrix = Eigen::Matrix<double, D * kNodes, D * kNodes>;
  using Point = PointGeometry<D, kNodes>;

  /// The force rule and ∂N/∂ξ at its points (computed once).
  static const Quadrature<D, kPoints>& rule() {
    static const auto q = quadrature<D, 2>();
    return q;
  }
  static const std::array<typename Shape::Gradients, kPoints>& reference_gradients() {
    static const auto g = [] {
      std::array<typename Shape::Gradients, kPoints> out;
      for (int q = 0; q < kPoints; ++q) out[q] = Shape::dshape(rule().points[q]);
      return out;
    }();
    return g;
  }
};

template <int D>
using QuadraticNodes = typename Quadratic<D>::Nodes;
template <int D>
using QuadraticMatrix = typename Quadratic<D>::Matrix;

/// Reference geometry of one quadratic cell: J⁻ᵀ and w det J (× thickness
/// in 2D) at each point of the force rule, ∇N = J⁻ᵀ ∇_ξN there.
template <int D>
struct QuadraticGeometry {
  static constexpr int kPoints = Quadratic<D>::kPoints;
  std::array<Mat<D>, kPoints> jinv_t;
  std::array<double, kPoints> weight;
  double volume = 0.0;  ///< Σ weight [m³] (2D: area × thickness)

  /// The geometry at point q: ∇N and its weight.
  [[nodiscard]] typename Quadratic<D>::Point at(int q) const {
    return {jinv_t[q] * Quadratic<D>::reference_gradients()[q], weight[q]};
  }
};

/// J = ∂x/∂ξ = Σ_a X_a ⊗ ∂N_a/∂ξ of the quadratic map at ξ.
template <int D>
Mat<D> quadratic_jacobian(const QuadraticNodes<D>& X, const Vec<D>& xi) {
  return X * Quadratic<D>::Shape::dshape(xi).transpose();
}

/// The smallest det J over the cell's nodes and force-rule points [m^D]:
/// a positive orientation needs it positive (a midside node pushed across
/// its edge folds the map locally however positive the vertex simplex is).
template <int D>
double min_jacobian(const QuadraticNodes<D>& X) {
  using Shape = typename Quadratic<D>::Shape;
  double lowest = quadratic_jacobian<D>(X, Shape::node(0)).determinant();
  for (int a = 1; a < Shape::kNodes; ++a) lowest = std::min(lowest, quadratic_jacobian<D>(X, Shape::node(a)).determinant());
  for (const auto& xi : Quadratic<D>::rule().points) lowest = std::min(lowest, quadratic_jacobian<D>(X, xi).determinant());
  return lowest;
}

/// The geometry of a cell with reference nodes X; the caller checks
/// min_jacobian first.
template <int D>
QuadraticGeometry<D> quadratic_geometry(const QuadraticNodes<D>& X, double thickness) {
  QuadraticGeometry<D> g;
  const auto& rule = Quadratic<D>::rule();
  for (int q = 0; q < Quadratic<D>::kPoints; ++q) {
    const Mat<D> J = quadratic_jacobian<D>(X, rule.points[q]);
    g.jinv_t[q] = J.inverse().transpose();
    g.weight[q] = rule.weights[q] * J.determinant() * (D == 2 ? thickness : 1.0);
    g.volume += g.weight[q];
  }
  return g;
}

/// The consistent mass M_AB = ∫ρ N_A N_B dV [kg] by the mass rule, or the
/// lumped one: a row sum is negative at a 10-node tetrahedron's vertices
/// (zero at a 6-node triangle's), so it is the diagonal scaled to the total
/// mass (Hinton, Rock & Zienkiewicz 1976), positive at every node.
/// `density` [kg/m³] × thickness in 2D.
template <int D>
Eigen::Matrix<double, Quadratic<D>::kNodes, Quadratic<D>::kNodes> quadratic_mass(const QuadraticNodes<D>& X,
                                                                                  double density, bool lumped) {
  using Shape = typename Quadratic<D>::Shape;
  constexpr int n = Shape::kNodes;
  const auto rule = quadrature<D, D == 2 ? 4 : 5>();
  Eigen::Matrix<double, n, n> M = Eigen::Matrix<double, n, n>::Zero();
  for (int q = 0; q < rule.kPoints; ++q) {
    const auto N = Shape::shape(rule.points[q]);
    M += (density * rule.weights[q] * quadratic_jacobian<D>(X, rule.points[q]).determinant()) * (N * N.transpose());
  }
  if (!lumped) return M;
  const auto diagonal = M.diagonal();
  return Eigen::Matrix<double, n, n>((diagonal * (M.sum() / diagonal.sum())).asDiagonal());
}

}  // namespace conserve::fem
