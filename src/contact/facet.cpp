#include "contact/facet.hpp"

#include <algorithm>
#include <limits>

namespace conserve::contact {
namespace {

/// δτ and δd = δ(x_s − x_0) for a unit perturbation of entry `col` of y.
template <int D>
void unit_variation(int col, Tangents<D>& dtau, Vec<D>& dd) {
  const int node = col / D, i = col % D;  // node 0: slave; 1…D: master nodes 0…D−1
  dtau.setZero();
  dd.setZero();
  if (node == 0) {
    dd(i) = 1.0;
  } else if (node == 1) {
    dd(i) = -1.0;
    dtau.row(i).setConstant(-1.0);
  } else {
    dtau(i, node - 2) = 1.0;
  }
}

/// The unnormalised normal c (τ_ξ × τ_η, or (τ_y, −τ_x)) of tangents τ.
template <int D>
Vec<D> raw_normal(const Tangents<D>& tau) {
  if constexpr (D == 3) {
    return tau.col(0).cross(tau.col(1));
  } else {
    return Vec<2>(tau(1, 0), -tau(0, 0));
  }
}

}  // namespace

template <int D>
Vec<D> facet_normal(const FacetNodes<D>& x) {
  return raw_normal<D>(facet_tangents<D>(x)).normalized();
}

template <int D>
FacetFrame<D> facet_frame(const FacetNodes<D>& x) {
  FacetFrame<D> f;
  f.origin = x.col(0);
  f.tangents = facet_tangents<D>(x);
  f.normal = facet_normal<D>(x);
  const Mat<D - 1> G = f.tangents.transpose() * f.tangents;  // metric
  f.inverse_metric = G.inverse();
  return f;
}

template <int D>
Projection<D> project(const Vec<D>& x_s, const FacetFrame<D>& f) {
  Projection<D> p;
  p.tangents = f.tangents;
  p.normal = f.normal;
  p.xi = f.inverse_metric * (f.tangents.transpose() * (x_s - f.origin));
  p.point = f.origin + f.tangents * p.xi;
  p.gap = (x_s - p.point).dot(p.normal);
  return p;
}

template <int D>
Projection<D> project(const Vec<D>& x_s, const FacetNodes<D>& x) {
  return project<D>(x_s, facet_frame<D>(x));
}

template <int D>
std::pair<Xi<D>, double> closest_point_on_facet(const Vec<D>& x_s, const FacetNodes<D>& x) {
  return closest_point_on_facet<D>(x_s, x, project<D>(x_s, x));
}

template <int D>
std::pair<Xi<D>, double> closest_point_on_facet(const Vec<D>& x_s, const FacetNodes<D>& x, const Projection<D>& p) {
  if (p.inside()) return {p.xi, (x_s - p.point).norm()};
  // The nearest point lies on the border: the best point of each edge.
  std::pair<Xi<D>, double> best{Xi<D>::Zero(), std::numeric_limits<double>::infinity()};
  for (int a = 0; a < D; ++a) {
    const int b = (a + 1) % D;
    const Vec<D> e = x.col(b) - x.col(a);
    const double t = std::clamp((x_s - x.col(a)).dot(e) / e.squaredNorm(), 0.0, 1.0);
    const double dist = (x_s - (x.col(a) + t * e)).norm();
    if (dist < best.second) {
      Vec<D> bary = Vec<D>::Zero();  // barycentric (N_0, …, N_{D−1})
      bary(a) = 1.0 - t;
      bary(b) += t;
      best = {bary.template tail<D - 1>(), dist};
    }
  }
  return best;
}

// δg = n·δx_s − Σ_k N_k(ξ̄) n·δx_k: x_s − x̄ = g n, and n·δτ_j = −τ_j·δn.
template <int D>
PairGradient<D> gap_gradient(const Vec<D>& x_s, const FacetNodes<D>& x) {
  const Projection<D> p = project<D>(x_s, x);
  const Vec<D> N = facet_shape<D>(p.xi);
  PairGradient<D> g;
  g.template head<D>() = p.normal.transpose();
  for (int k = 0; k < D; ++k) g.template segment<D>(D * (k + 1)) = -N(k) * p.normal.transpose();
  return g;
}

// ξ̄ = G⁻¹ τᵀ d with d = x_s − x_0, G = τᵀτ:
// δξ̄ = G⁻¹ (δτᵀ d + τᵀ δd − (δτᵀ τ + τᵀ δτ) ξ̄).
template <int D>
Eigen::Matrix<double, D - 1, kPairDofs<D>> xi_gradient(const Vec<D>& x_s, const FacetNodes<D>& x) {
  const Projection<D> p = project<D>(x_s, x);
  const Mat<D - 1> G_inv = (p.tangents.transpose() * p.tangents).inverse();
  const Vec<D> d = x_s - x.col(0);
  Eigen::Matrix<double, D - 1, kPairDofs<D>> J;
  Tangents<D> dtau;
  Vec<D> dd;
  for (int col = 0; col < kPairDofs<D>; ++col) {
    unit_variation<D>(col, dtau, dd);
    const Mat<D - 1> dG = dtau.transpose() * p.tangents + p.tangents.transpose() * dtau;
    J.col(col) = G_inv * (dtau.transpose() * d + p.tangents.transpose() * dd - dG * p.xi);
  }
  return J;
}

// n = c/|c|: δn = (1 − n nᵀ) δc / |c|, with c linear in τ.
template <int D>
Eigen::Matrix<double, D, kPairDofs<D>> normal_gradient(const FacetNodes<D>& x) {
  const Tangents<D> tau = facet_tangents<D>(x);
  const Vec<D> c = raw_normal<D>(tau);
  const Vec<D> n = c.normalized();
  const Mat<D> projector = (Mat<D>::Identity() - n * n.transpose()) / c.norm();
  Eigen::Matrix<double, D, kPairDofs<D>> J;
  Tangents<D> dtau;
  Vec<D> dd;
  for (int col = 0; col < kPairDofs<D>; ++col) {
    unit_variation<D>(col, dtau, dd);
    Vec<D> dc;
    if constexpr (D == 3) {
      dc = dtau.col(0).cross(tau.col(1)) + tau.col(0).cross(dtau.col(1));
    } else {
      dc = raw_normal<D>(dtau);
    }
    J.col(col) = projector * dc;
  }
  return J;
}

template <int D>
Eigen::Matrix<double, D*(D - 1), kPairDofs<D>> tangents_gradient() {
  Eigen::Matrix<double, D*(D - 1), kPairDofs<D>> J;
  Tangents<D> dtau;
  Vec<D> dd;
  for (int col = 0; col < kPairDofs<D>; ++col) {
    unit_variation<D>(col, dtau, dd);
    J.col(col) = dtau.reshaped();
  }
  return J;
}

#define CONSERVE_INSTANTIATE(D)                                                                            \
  template Vec<D> facet_normal<D>(const FacetNodes<D>&);                                                   \
  template Projection<D> project<D>(const Vec<D>&, const FacetNodes<D>&);                                  \
  template FacetFrame<D> facet_frame<D>(const FacetNodes<D>&);                                             \
  template Projection<D> project<D>(const Vec<D>&, const FacetFrame<D>&);                                  \
  template std::pair<Xi<D>, double> closest_point_on_facet<D>(const Vec<D>&, const FacetNodes<D>&);        \
  template std::pair<Xi<D>, double> closest_point_on_facet<D>(const Vec<D>&, const FacetNodes<D>&,         \
                                                              const Projection<D>&);                       \
  template PairGradient<D> gap_gradient<D>(const Vec<D>&, const FacetNodes<D>&);                           \
  template Eigen::Matrix<double, D - 1, kPairDofs<D>> xi_gradient<D>(const Vec<D>&, const FacetNodes<D>&); \
  template Eigen::Matrix<double, D, kPairDofs<D>> normal_gradient<D>(const FacetNodes<D>&);                \
  template Eigen::Matrix<double, D*(D - 1), kPairDofs<D>> tangents_gradient<D>();
CONSERVE_INSTANTIATE(2)
CONSERVE_INSTANTIATE(3)
#undef CONSERVE_INSTANTIATE

}  // namespace conserve::contact
