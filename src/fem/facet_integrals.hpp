#pragma once
/// Integrals over a boundary facet of order P (line2/line3 in 2D, tri3/tri6
/// in 3D; Gmsh node order) for surface loads: each node's share of the
/// outward area vector, s_a = ∫ N_a n da = ∫ N_a x_ξ × x_η dξ (3D) or
/// t ∫ N_a (y_ξ, −x_ξ) dξ (2D, t the thickness), its derivative, and each
/// node's share of the facet's measure ∫ N_a dA. The integrands are
/// polynomials of degree 4 (3D P2) and 3 (2D P2), integrated exactly by
/// the 6-point and 2-point rules, so on a closed surface Σ_a s_a = ∮ n da = 0
/// and Σ_a x_a × s_a = ∮ x × n da = 0 hold to round-off for either order. On
/// a P1 facet every share is A/D (the closed form).
#include <array>
#include <cmath>

#include "fem/lagrange.hpp"
#include "fem/quadrature.hpp"

namespace conserve::fem {

template <int D, int P>
struct FacetIntegrals {
  static_assert(D == 2 || D == 3);
  using Shape = Lagrange<D - 1, P>;
  static constexpr int kNodes = Shape::kNodes;
  using Nodes = Eigen::Matrix<double, D, kNodes>;
  /// (a, b) → ∂s_a/∂x_b, at a * kNodes + b.
  using Derivatives = std::array<Mat<D>, kNodes * kNodes>;

  /// n da / dξ at ξ: x_ξ × x_η (3D) or t (y_ξ, −x_ξ) (2D).
  static Vec<D> area_density(const Nodes& x, const typename Shape::Gradients& dN, double thickness) {
    const Eigen::Matrix<double, D, D - 1> t = x * dN.transpose();
    if constexpr (D == 2) {
      return thickness * Vec<2>(t(1, 0), -t(0, 0));
    } else {
      return t.col(0).cross(t.col(1));
    }
  }

  /// Column a = s_a, node a's share of the outward area vector [m²].
  static Nodes area_shares(const Nodes& x, double thickness) {
    Nodes s;
    if constexpr (P == 1) {
      const Vec<D> a = x.col(1) - x.col(0);
      Vec<D> area;
      if constexpr (D == 2) {
        area = thickness * Vec<2>(a.y(), -a.x());
      } else {
        area = 0.5 * a.cross(Vec<3>(x.col(2) - x.col(0)));
      }
      s.colwise() = area / D;
    } else {
      s.setZero();
      static const auto rule = quadrature<D - 1, D == 2 ? 3 : 4>();
      for (int q = 0; q < rule.kPoints; ++q) {
        const auto& xi = rule.points[static_cast<std::size_t>(q)];
        const Vec<D> c = rule.weights[static_cast<std::size_t>(q)] * area_density(x, Shape::dshape(xi), thickness);
        s += c * Shape::shape(xi).transpose();
      }
    }
    return s;
  }

  /// ∂s_a/∂x_b = ∫ N_a ∂c/∂x_b dξ with ∂c/∂x_b = N_b,η [x_ξ]× − N_b,ξ [x_η]×
  /// (3D; [v]× w = v × w) or t N_b,ξ [[0, 1], [−1, 0]] (2D).
  static Derivatives area_share_derivatives(const Nodes& x, double thickness) {
    Derivatives d;
    for (auto& m : d) m.setZero();
    const auto cross_matrix = [](const Vec<3>& v) {
      Mat<3> m;
      m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
      return m;
    };
    static const auto rule = quadrature<D - 1, D == 2 ? 3 : 4>();
    for (int q = 0; q < rule.kPoints; ++q) {
      const auto& xi = rule.points[static_cast<std::size_t>(q)];
      const double w = rule.weights[static_cast<std::size_t>(q)];
      const auto N = Shape::shape(xi);
      const auto dN = Shape::dshape(xi);
      const Eigen::Matrix<double, D, D - 1> t = x * dN.transpose();
      for (int b = 0; b < kNodes; ++b) {
        Mat<D> dc;
        if constexpr (D == 2) {
          dc << 0.0, 1.0, -1.0, 0.0;
          dc *= thickness * dN(0, b);
        } else {
          dc = dN(1, b) * cross_matrix(t.col(0)) - dN(0, b) * cross_matrix(t.col(1));
        }
        for (int a = 0; a < kNodes; ++a) d[static_cast<std::size_t>(a * kNodes + b)] += w * N(a) * dc;
      }
    }
    return d;
  }

  /// Node a's share of the facet's measure ∫ N_a dA [m²] (2D: × thickness).
  /// On a straight or flat P2 facet: 0 at the vertices, 1/3 at the midsides
  /// (tri6); 1/6, 1/6, 2/3 (line3). |x_ξ × x_η| of a curved facet is not a
  /// polynomial: the rule of degree 4 (3D) or 5 (2D) integrates it.
  static Eigen::Matrix<double, kNodes, 1> measure_shares(const Nodes& x, double thickness) {
    if constexpr (P == 1) {
      return Eigen::Matrix<double, kNodes, 1>::Constant(area_shares(x, thickness).col(0).norm());
    } else {
      Eigen::Matrix<double, kNodes, 1> m = Eigen::Matrix<double, kNodes, 1>::Zero();
      static const auto rule = quadrature<D - 1, D == 2 ? 5 : 4>();
      for (int q = 0; q < rule.kPoints; ++q) {
        const auto& xi = rule.points[static_cast<std::size_t>(q)];
        m += rule.weights[static_cast<std::size_t>(q)] * area_density(x, Shape::dshape(xi), thickness).norm() *
             Shape::shape(xi);
      }
      return m;
    }
  }
};

}  // namespace conserve::fem
