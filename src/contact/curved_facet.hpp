#pragma once
/// Geometry of a quadratic master facet (a 3-node line in 2D, a 6-node
/// triangle in 3D; Gmsh's node order) and the closest-point projection of
/// a slave point on it, paper (27)–(29) with the second derivatives of
/// Appendix 1 (87)–(94): x(ξ) = Σ N_b(ξ) x_b, τ_α = x,_α, and ξ̄ solves
/// r(ξ) = τ(ξ)ᵀ (x_s − x(ξ)) = 0 by Newton with
///   H_αβ = τ_α·τ_β − (x_s − x)·x,_αβ,   x,_αβ = Σ N_b,αβ x_b,
/// the Hessian of ½|x_s − x(ξ)|². H is the matrix of Appendix 1's δξ̄ =
/// H⁻¹ [τᵀ(δx_s − Σ N_b δx_b) + (x_s − x̄)·Σ N_b,α δx_b].
#include <array>
#include <cmath>
#include <algorithm>
#include <limits>
#include <tuple>

#include "contact/facet.hpp"
#include "fem/lagrange.hpp"

namespace conserve::contact {

template <int D>
struct CurvedFacet {
  using Shape = fem::Lagrange<D - 1, 2>;
  static constexpr int kNodes = Shape::kNodes;  ///< 3 (2D) or 6 (3D)
  using Nodes = Eigen::Matrix<double, D, kNodes>;

  /// x(ξ).
  static Vec<D> point(const Nodes& x, const Xi<D>& xi) { return x * Shape::shape(xi); }
  /// τ_α = ∂x/∂ξ_α as columns.
  static Tangents<D> tangents(const Nodes& x, const Xi<D>& xi) { return x * Shape::dshape(xi).transpose(); }
  /// x,_αβ (constant on a quadratic facet), index α(D−1)+β.
  static std::array<Vec<D>, (D - 1) * (D - 1)> second_derivatives(const Nodes& x) {
    std::array<Vec<D>, (D - 1) * (D - 1)> out;
    const auto H = Shape::d2shape(Xi<D>::Zero());
    for (int a = 0; a < D - 1; ++a)
      for (int b = 0; b < D - 1; ++b) {
        Vec<D> v = Vec<D>::Zero();
        for (int n = 0; n < kNodes; ++n) v += H[static_cast<std::size_t>(n)](a, b) * x.col(n);
        out[static_cast<std::size_t>(a * (D - 1) + b)] = v;
      }
    return out;
  }
  /// Outward unit normal at ξ: (τ_ξ × τ_η)/|·| in 3D, (τ_y, −τ_x)/|τ| in 2D.
  static Vec<D> normal(const Nodes& x, const Xi<D>& xi) {
    const Tangents<D> t = tangents(x, xi);
    if constexpr (D == 3) {
      return t.col(0).cross(t.col(1)).normalized();
    } else {
      return Vec<2>(t(1, 0), -t(0, 0)).normalized();
    }
  }
  /// H(ξ) = τᵀτ − (x_s − x(ξ))·x,_αβ.
  static Mat<D - 1> hessian(const Vec<D>& x_s, const Nodes& x, const Xi<D>& xi) {
    const Tangents<D> t = tangents(x, xi);
    const Vec<D> d = x_s - point(x, xi);
    const auto xx = second_derivatives(x);
    Mat<D - 1> H = t.transpose() * t;
    for (int a = 0; a < D - 1; ++a)
      for (int b = 0; b < D - 1; ++b) H(a, b) -= d.dot(xx[static_cast<std::size_t>(a * (D - 1) + b)]);
    return H;
  }
  /// The linear facet through the vertices (the first D nodes).
  static FacetNodes<D> chord(const Nodes& x) { return x.template leftCols<D>(); }

  /// A box holding the whole curved facet: that of its Bézier control
  /// points, the vertices and 2 x_m − (x_a + x_b)/2 for the middle x_m of
  /// edge (a, b) (a quadratic Bézier patch lies in their convex hull).
  static std::pair<Vec<D>, Vec<D>> box(const Nodes& x) {
    Vec<D> lo = x.col(0), hi = x.col(0);
    for (int n = 1; n < kNodes; ++n) {
      Vec<D> c = x.col(n);
      if (n >= D) {
        const auto [a, b] = Shape::edges()[static_cast<std::size_t>(n - D)];
        c = 2.0 * x.col(n) - 0.5 * (x.col(a) + x.col(b));
      }
      lo = lo.cwiseMin(c), hi = hi.cwiseMax(c);
    }
    return {lo, hi};
  }
};

/// The outcome of a curved projection: the projection and how it was found.
template <int D>
struct CurvedProjection {
  Projection<D> projection;  ///< ξ̄ (not clamped to the facet), x̄, n(ξ̄), τ(ξ̄), g_N = (x_s − x̄)·n
  int iterations = 0;
  bool converged = false;  ///< |r| at the round-off of the positions, or a step below ξ's (else the last iterate)
};

/// Closest-point projection of x_s on the quadratic facet's surface, from
/// the chord's projection: Newton on r(ξ) = 0 with the Hessian H, a step
/// limited to 0.5 in ξ and halved until ½|x_s − x(ξ)|² does not grow (a
/// Gauss–Newton step H = τᵀτ where H is not positive definite: beyond the
/// focal distance, where the nearest point is not unique).
template <int D>
CurvedProjection<D> project_curved(const Vec<D>& x_s, const typename CurvedFacet<D>::Nodes& x, int max_iterations = 30) {
  using F = CurvedFacet<D>;
  CurvedProjection<D> out;
  Xi<D> xi = project<D>(x_s, F::chord(x)).xi;
  // r's round-off: |τ| times that of x_s − x(ξ), positions of this size.
  const double position = x_s.norm() + x.colwise().norm().maxCoeff();
  const auto distance2 = [&](const Xi<D>& z) { return (x_s - F::point(x, z)).squaredNorm(); };
  for (int it = 0; it < max_iterations; ++it) {
    const Tangents<D> t = F::tangents(x, xi);
    const Xi<D> r = t.transpose() * (x_s - F::point(x, xi));
    Eigen::LLT<Mat<D - 1>> llt(F::hessian(x_s, x, xi));
    if (llt.info() != Eigen::Success) llt.compute(t.transpose() * t);
    Xi<D> step = llt.solve(r);
    if (r.norm() <= 1e-14 * position * t.norm()) {  // converging: one more step takes ξ to its round-off
      xi += step;
      out.converged = true;
      break;
    }
    if (step.norm() > 0.5) step *= 0.5 / step.norm();
    // Halved while ½|x_s − x|² grows by more than its round-off (near the
    // minimum it is flat to round-off and only r tells).
    const double f0 = distance2(xi);
    const double noise = 4.0 * std::numeric_limits<double>::epsilon() * position * (std::sqrt(f0) + position);
    double s = 1.0;
    while (s > 1e-6 && distance2(xi + s * step) > f0 + noise) s *= 0.5;
    xi += s * step;
    out.iterations = it + 1;
    if (s * step.norm() <= 1e-15 * (1.0 + xi.norm())) {  // a step below ξ's round-off
      out.converged = true;
      break;
    }
  }
  Projection<D>& p = out.projection;
  p.xi = xi;
  p.point = F::point(x, xi);
  p.tangents = F::tangents(x, xi);
  p.normal = F::normal(x, xi);
  p.gap = (x_s - p.point).dot(p.normal);
  return out;
}

/// The point of the closed quadratic facet nearest to x_s, given x_s's
/// projection p on its surface (project_curved): p itself when inside,
/// else the nearest point of its border: a vertex (2D) or, in 3D, the
/// best of each 3-node edge curve (Newton on its parameter t ∈ [0, 1],
/// clamped, from the chord's clamped projection; its ends compared too).
/// Returns its ξ (inside the facet), the distance [m] and the point.
template <int D>
std::tuple<Xi<D>, double, Vec<D>> closest_point_on_curved(const Vec<D>& x_s, const typename CurvedFacet<D>::Nodes& x,
                                                         const Projection<D>& p) {
  using F = CurvedFacet<D>;
  if (p.inside()) return {p.xi, (x_s - p.point).norm(), p.point};
  std::tuple<Xi<D>, double, Vec<D>> best{Xi<D>::Zero(), std::numeric_limits<double>::infinity(), Vec<D>::Zero()};
  const auto offer = [&](const Xi<D>& xi) {
    const Vec<D> y = F::point(x, xi);
    const double d = (x_s - y).norm();
    if (d < std::get<1>(best)) best = {xi, d, y};
  };
  if constexpr (D == 2) {
    offer(Xi<2>::Zero());
    offer(Xi<2>::Ones());
  } else {
    using Line = fem::Lagrange<1, 2>;
    using Tri = typename F::Shape;
    int m = 3;
    for (const auto& [a, b] : Tri::edges()) {
      Eigen::Matrix<double, 3, 3> e;  // the edge's line3: ends a, b, middle m
      e << x.col(a), x.col(b), x.col(m++);
      const Vec<3> chord = e.col(1) - e.col(0);
      Vec<1> t(std::clamp((x_s - e.col(0)).dot(chord) / chord.squaredNorm(), 0.0, 1.0));
      const Vec<3> dtt = 4.0 * (e.col(0) + e.col(1)) - 8.0 * e.col(2);  // x'' (constant on a line3)
      for (int it = 0; it < 20; ++it) {
        const Vec<3> d = x_s - e * Line::shape(t);
        const Vec<3> dt = e * Line::dshape(t).transpose();
        const double r = dt.dot(d);
        double h = dt.squaredNorm() - d.dot(dtt);
        if (h <= 0.0) h = dt.squaredNorm();
        const double next = std::clamp(t(0) + r / h, 0.0, 1.0);
        const double moved = std::abs(next - t(0));
        t(0) = next;
        if (moved <= 1e-15) break;
      }
      const Xi<3> ta = Tri::node(a), tb = Tri::node(b);
      offer(Xi<3>(ta + t(0) * (tb - ta)));
      offer(Xi<3>(ta));
      offer(Xi<3>(tb));
    }
  }
  return best;
}

}  // namespace conserve::contact
