#pragma once
/// Lagrange shape functions on the reference simplex {ξ ≥ 0, Σξ ≤ 1} of
/// dimension K (1 line, 2 triangle, 3 tetrahedron), order 1 or 2, with
/// their first and second derivatives (the N_ξ, N_ξξ of the paper's
/// Appendix 1, (87)–(94)), in Gmsh's node order: vertices first, then one
/// node per edge at its middle, edges in the order of Lagrange::kEdges.
#include <array>

#include "core/types.hpp"

namespace conserve::fem {

/// Nodes of the order-P simplex of dimension K.
constexpr int lagrange_nodes(int K, int P) { return P == 1 ? K + 1 : (K + 1) * (K + 2) / 2; }

template <int K, int P>
struct Lagrange {
  static_assert(K >= 1 && K <= 3 && (P == 1 || P == 2));
  static constexpr int kDim = K;
  static constexpr int kOrder = P;
  static constexpr int kNodes = lagrange_nodes(K, P);
  static constexpr int kVertices = K + 1;
  using Point = Vec<K>;
  using Values = Eigen::Matrix<double, kNodes, 1>;
  using Gradients = Eigen::Matrix<double, K, kNodes>;  ///< column a = ∂N_a/∂ξ
  using Hessians = std::array<Mat<K>, kNodes>;         ///< ∂²N_a/∂ξ∂ξ

  /// The edge (pair of vertices) of each midside node kVertices + e (Gmsh:
  /// line3 (0,1); tri6 (0,1) (1,2) (2,0); tet10 (0,1) (1,2) (2,0) (3,0)
  /// (3,2) (3,1)).
  static constexpr auto edges() {
    if constexpr (K == 1) return std::array<std::array<int, 2>, 1>{{{0, 1}}};
    if constexpr (K == 2) return std::array<std::array<int, 2>, 3>{{{0, 1}, {1, 2}, {2, 0}}};
    if constexpr (K == 3) return std::array<std::array<int, 2>, 6>{{{0, 1}, {1, 2}, {2, 0}, {3, 0}, {3, 2}, {3, 1}}};
  }

  /// Barycentric coordinates λ = (1 − Σξ, ξ_1, …, ξ_K).
  static Eigen::Matrix<double, K + 1, 1> barycentric(const Point& xi) {
    Eigen::Matrix<double, K + 1, 1> l;
    l(0) = 1.0 - xi.sum();
    l.template tail<K>() = xi;
    return l;
  }

  /// N_a(ξ): λ_a (order 1); λ_a(2λ_a − 1) at vertices and 4 λ_a λ_b at the
  /// middle of edge (a, b) (order 2).
  static Values shape(const Point& xi) {
    const auto l = barycentric(xi);
    Values N;
    if constexpr (P == 1) {
      N = l;
    } else {
      for (int a = 0; a <= K; ++a) N(a) = l(a) * (2.0 * l(a) - 1.0);
      int e = K + 1;
      for (const auto& [a, b] : edges()) N(e++) = 4.0 * l(a) * l(b);
    }
    return N;
  }

  /// ∂N_a/∂ξ, from ∂λ_0/∂ξ = −1, ∂λ_a/∂ξ = e_a.
  static Gradients dshape(const Point& xi) {
    const auto l = barycentric(xi);
    const auto dl = [](int a) -> Point { return a == 0 ? Point(-Point::Ones()) : Point(Point::Unit(a - 1)); };
    Gradients G;
    if constexpr (P == 1) {
      for (int a = 0; a <= K; ++a) G.col(a) = dl(a);
    } else {
      for (int a = 0; a <= K; ++a) G.col(a) = (4.0 * l(a) - 1.0) * dl(a);
      int e = K + 1;
      for (const auto& [a, b] : edges()) G.col(e++) = 4.0 * (l(b) * dl(a) + l(a) * dl(b));
    }
    return G;
  }

  /// ∂²N_a/∂ξ∂ξ: zero for order 1; constant for order 2.
  static Hessians d2shape(const Point& /*xi*/) {
    Hessians H;
    for (auto& h : H) h.setZero();
    if constexpr (P == 2) {
      const auto dl = [](int a) -> Point { return a == 0 ? Point(-Point::Ones()) : Point(Point::Unit(a - 1)); };
      for (int a = 0; a <= K; ++a) H[a] = 4.0 * dl(a) * dl(a).transpose();
      int e = K + 1;
      for (const auto& [a, b] : edges()) {
        H[e++] = 4.0 * (dl(a) * dl(b).transpose() + dl(b) * dl(a).transpose());
      }
    }
    return H;
  }

  /// Reference coordinates of node a.
  static Point node(int a) {
    const auto vertex = [](int v) -> Point { return v == 0 ? Point(Point::Zero()) : Point(Point::Unit(v - 1)); };
    if (a <= K) return vertex(a);
    const auto edge = edges()[static_cast<std::size_t>(a - K - 1)];
    return 0.5 * (vertex(edge[0]) + vertex(edge[1]));
  }
};

}  // namespace conserve::fem
