#pragma once
/// The penalty force of one slave node on one master facet over a step,
/// evaluated so that the mid-point scheme conserves energy and momentum
/// (Gonzalez 1996, J. Nonlinear Sci. 6:449, discrete gradients in
/// invariants; for penalty contact, Armero & Petocz 1998, CMAME 158:269).
///
/// The nodes y = (x_s, x_0, …, x_{D−1}) give the facet's edge vectors
/// A = (a_1, …, a_{D−1}), a_k = x_k − x_0, and b = x_s − x_0. Two kinds of
/// invariants describe the gap: the facet's metric G_a = AᵀA and
/// ĝ = g·|facet| (2D: b_x a_y − b_y a_x; 3D: b·(a_1 × a_2)), so that
///   Φ = ½ k ⟨−g⟩² = ½ k ⟨−ĝ⟩² / det G_a,  k = ε a_s,
/// a_s the slave node's share of its surface [m²]. With (∂̄Φ/∂ĝ, ∂̄Φ/∂G_a)
/// Gonzalez's discrete gradient of Φ in (ĝ, G_a) (their mid-point gradient
/// plus r Δπ/|Δπ|², r the energy it misses, |·| scaled by the facet size)
/// and the invariants' gradients at y_{n+½}, the force
///   f = ∂̄Φ/∂ĝ ∇ĝ(y_{n+½}) + ∂̄Φ/∂G_a : ∇G_a(y_{n+½})
/// does work Φ_{n+1} − Φ_n over the step: the energy including the
/// springs' is conserved. G_a is quadratic, so Δ G_a = ∇G_a(y_{n+½})·Δy
/// exactly; so is ĝ in 2D. In 3D ĝ is a triple product, trilinear:
/// Δĝ = ∇ĝ(y_{n+½})·Δy + ¼ ĝ(Δy), and the last term's work is done along
/// the non-rigid part d of the step:
/// ∂̄Φ/∂ĝ ¼ ĝ(Δy) d/|d|² (d = 0 with ĝ(Δy) = 0 for a rigid step). The
/// gradients of invariants at the mid-point and d have no resultant and no
/// moment about y_{n+½}: L and J are kept. On a fixed master the force on
/// the slave is along the normal. The mid-point force (the
/// negative control) is ∂Φ/∂y at y_{n+½}.
///
/// Stick adds a spring to the slave's anchor ξ₀ on the facet (its
/// projection when it was caught), in the facet's plane:
///   Φ_t = ½ k (ξ − ξ₀)ᵀ G_a (ξ − ξ₀),  ξ = G_a⁻¹ c,  c = Aᵀb,
/// a function of the quadratic invariants c and G_a (so the same
/// discrete gradient keeps energy, L and J); it stores nothing when the
/// slave is caught (ξ = ξ₀) and is let go, with what it stores, when the
/// slave is in front of its facet at a step's end (penalty.hpp).
#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <vector>

#include "core/types.hpp"

namespace conserve::contact::penalty {

/// Node positions of one slave–facet coupling: column 0 the slave, then
/// the facet's D nodes.
template <int D, class T>
using CouplingNodes = Eigen::Matrix<T, D, D + 1>;

/// The value of a scalar (an automatic-differentiation scalar's value).
inline double value_of(double x) { return x; }
template <class T>
double value_of(const T& x) {
  return x.value();
}
/// √x for either scalar.
template <class T>
T sqrt_of(const T& x) {
  using std::sqrt;
  return sqrt(x);
}

/// The relative vectors V = (A, b) of nodes y.
template <int D, class T>
Eigen::Matrix<T, D, D> relative_vectors(const CouplingNodes<D, T>& y) {
  Eigen::Matrix<T, D, D> V;
  for (int j = 0; j + 1 < D; ++j) V.col(j) = y.col(j + 2) - y.col(1);
  V.col(D - 1) = y.col(0) - y.col(1);
  return V;
}

/// ĝ of V = (A, b): g × the facet's length (2D) or twice its area (3D),
/// signed with the outward normal of contact/facet.hpp.
template <int D, class T>
T scaled_gap(const Eigen::Matrix<T, D, D>& V) {
  if constexpr (D == 2) {
    return V(0, 1) * V(1, 0) - V(1, 1) * V(0, 0);
  } else {
    return V.col(2).dot(V.col(0).cross(V.col(1)));
  }
}

/// ∂ĝ/∂V, column by column (ĝ is multilinear in the columns).
template <int D, class T>
Eigen::Matrix<T, D, D> scaled_gap_gradient(const Eigen::Matrix<T, D, D>& V) {
  Eigen::Matrix<T, D, D> d;
  if constexpr (D == 2) {
    d.col(0) << -V(1, 1), V(0, 1);
    d.col(1) << V(1, 0), -V(0, 0);
  } else {
    d.col(0) = V.col(1).cross(V.col(2));
    d.col(1) = V.col(2).cross(V.col(0));
    d.col(2) = V.col(0).cross(V.col(1));
  }
  return d;
}

/// det G_a and its cofactor matrix.
template <int D, class T>
T metric_determinant(const Eigen::Matrix<T, D - 1, D - 1>& Ga, Eigen::Matrix<T, D - 1, D - 1>& cofactor) {
  if constexpr (D == 2) {
    cofactor(0, 0) = T(1);
    return Ga(0, 0);
  } else {
    cofactor << Ga(1, 1), -Ga(1, 0), -Ga(0, 1), Ga(0, 0);
    return Ga(0, 0) * Ga(1, 1) - Ga(0, 1) * Ga(1, 0);
  }
}

/// The invariants (ĝ, G_a, c) of V = (A, b).
template <int D, class T>
struct Invariants {
  T gap;                                  ///< ĝ
  Eigen::Matrix<T, D - 1, D - 1> metric;  ///< G_a = AᵀA
  Eigen::Matrix<T, D - 1, 1> along;       ///< c = Aᵀb

  Invariants operator+(const Invariants& o) const { return {gap + o.gap, metric + o.metric, along + o.along}; }
  Invariants operator-(const Invariants& o) const { return {gap - o.gap, metric - o.metric, along - o.along}; }
  Invariants operator*(const T& s) const { return {gap * s, metric * s, along * s}; }
};

template <int D, class T>
Invariants<D, T> invariants(const Eigen::Matrix<T, D, D>& V) {
  const Eigen::Matrix<T, D, D - 1> A = V.template leftCols<D - 1>();
  return {scaled_gap<D, T>(V), A.transpose() * A, A.transpose() * V.col(D - 1)};
}

/// A stick spring's anchor ξ₀ on its facet (nothing: frictionless).
template <int D>
using Anchor = const Eigen::Matrix<double, D - 1, 1>*;

/// Φ(ĝ, G_a, c) = ½ k ⟨−ĝ⟩² / det G_a (+ Φ_t with an anchor) and, if
/// `d` is given, its derivatives by the invariants (in d's fields).
template <int D, class T, class A = double>
T potential(const Invariants<D, T>& p, double k, const Eigen::Matrix<A, D - 1, 1>* anchor = nullptr,
            Invariants<D, T>* d = nullptr) {
  using Metric = Eigen::Matrix<T, D - 1, D - 1>;
  Metric cof;
  const T det = metric_determinant<D, T>(p.metric, cof);
  T phi = p.gap < T(0) ? T(0.5 * k) * p.gap * p.gap / det : T(0);
  if (d) {
    d->gap = p.gap < T(0) ? T(k) * p.gap / det : T(0);
    d->metric = (-phi / det) * cof;
    d->along.setZero();
  }
  if (anchor) {
    const Metric inverse = cof.transpose() / det;
    const Eigen::Matrix<T, D - 1, 1> xi = inverse * p.along;
    const Eigen::Matrix<T, D - 1, 1> slip = xi - anchor->template cast<T>();
    phi += T(0.5 * k) * slip.dot(p.metric * slip);
    if (d) {
      d->along += T(k) * slip;
      const Eigen::Matrix<T, D - 1, 1> a0 = anchor->template cast<T>();
      d->metric += T(0.5 * k) * (a0 * a0.transpose() - xi * xi.transpose());
    }
  }
  return phi;
}

/// Φ of nodes y [J] (with the anchor: a stick spring's).
template <int D>
double penalty_energy(const CouplingNodes<D, double>& y, double k, Anchor<D> anchor = nullptr) {
  return potential<D, double>(invariants<D, double>(relative_vectors<D, double>(y)), k, anchor);
}

/// The stick part Φ_t alone of nodes y [J].
template <int D>
double spring_energy(const CouplingNodes<D, double>& y, double k, Anchor<D> anchor) {
  Invariants<D, double> p = invariants<D, double>(relative_vectors<D, double>(y));
  p.gap = 0.0;
  return potential<D, double>(p, k, anchor);
}

/// ξ of the slave's projection on the facet's plane, G_a⁻¹ Aᵀb.
template <int D>
Eigen::Matrix<double, D - 1, 1> projected_xi(const CouplingNodes<D, double>& y) {
  const Invariants<D, double> p = invariants<D, double>(relative_vectors<D, double>(y));
  return p.metric.ldlt().solve(p.along);
}

/// Nodes' positions of a step in which a slave's potential changes its
/// facet: the union of the slave's and both facets' nodes, D × M.
template <class T, int D>
using StepNodes = Eigen::Matrix<T, D, Eigen::Dynamic>;

/// The part of the nodes' step dx that is not a rigid motion about their
/// mid-point positions x_mid: dx less its projection on the translations
/// and the rotations about the centre (orthonormalised by Gram–Schmidt).
/// It has no resultant and no moment about x_mid.
template <int D, class T>
StepNodes<T, D> non_rigid(const StepNodes<T, D>& x_mid, const StepNodes<T, D>& dx) {
  const Eigen::Index M = x_mid.cols();
  const Eigen::Matrix<T, D, 1> centre = x_mid.rowwise().sum() / T(static_cast<double>(M));
  constexpr int kModes = D == 2 ? 3 : 6;
  std::vector<StepNodes<T, D>> modes;
  const double size = value_of(x_mid.squaredNorm()) + 1.0;
  for (int m = 0; m < kModes; ++m) {
    StepNodes<T, D> v = StepNodes<T, D>::Zero(D, M);
    for (Eigen::Index a = 0; a < M; ++a) {
      const Eigen::Matrix<T, D, 1> r = x_mid.col(a) - centre;
      if (m < D) {
        v(m, a) = T(1);
      } else if constexpr (D == 2) {
        v(0, a) = -r(1);
        v(1, a) = r(0);
      } else {
        Eigen::Matrix<T, 3, 1> axis = Eigen::Matrix<T, 3, 1>::Zero();
        axis(m - 3) = T(1);
        v.col(a) = axis.cross(r);
      }
    }
    for (const auto& u : modes) v -= u.cwiseProduct(v).sum() * u;
    const T norm2 = v.squaredNorm();
    // A rotation about the line of two nodes moves neither: no mode.
    if (value_of(norm2) > 1e-24 * size) modes.push_back(v / sqrt_of(norm2));
  }
  StepNodes<T, D> d = dx;
  for (const auto& u : modes) d -= u.cwiseProduct(dx).sum() * u;
  return d;
}

/// ∂Φ/∂y from Φ's derivatives by the invariants d, at relative vectors V,
/// with ∇̄ĝ = `gap_gradient`: ĝ's part, G_a = AᵀA's 2A ∂Φ/∂G_a and
/// c = Aᵀb's (b ∂Φ/∂c on A, A ∂Φ/∂c on b), then v_j's forces to the nodes.
template <int D, class T>
CouplingNodes<D, T> node_forces(const Invariants<D, T>& d, const Eigen::Matrix<T, D, D>& V,
                                const Eigen::Matrix<T, D, D>& gap_gradient) {
  Eigen::Matrix<T, D, D> F = d.gap * gap_gradient;  // ∂Φ/∂v_j, column j
  const auto A = V.template leftCols<D - 1>();
  F.template leftCols<D - 1>() += T(2) * A * d.metric + V.col(D - 1) * d.along.transpose();
  F.col(D - 1) += A * d.along;
  CouplingNodes<D, T> f;
  for (int j = 0; j + 1 < D; ++j) f.col(j + 2) = F.col(j);
  f.col(0) = F.col(D - 1);
  f.col(1) = -F.rowwise().sum();
  return f;
}

/// A Coulomb spring's step (penalty_force with a finite μ): the anchor it
/// ends with and the friction's work D ≥ 0 over the anchor's slip [J].
template <int D, class T>
struct CoulombStep {
  Eigen::Matrix<T, D - 1, 1> anchor;
  T dissipated = T(0);
  bool slips = false;
};

/// The Coulomb return map of a spring anchored at ξ₀ⁿ over the step with
/// mid-point invariants p_m: with ξ_m = G_m⁻¹ c_m and τ = ξ_m − ξ₀ⁿ, the
/// spring's mid-point stretch |ξ_m − ξ₀,m|_G (ξ₀,m = ½(ξ₀ⁿ + ξ₀ⁿ⁺¹),
/// |v|²_G = vᵀ G_m v) may not exceed `limit` = μ f_N / k, f_N the step's
/// normal force: inside, the anchor stays; outside it slips along τ by
/// λ = 2(|τ|_G − limit), which leaves the mid-point stretch at the limit:
/// |f_T| = μ f_N. `slip` gets λ · limit (the friction's work over k).
template <int D, class T>
Eigen::Matrix<T, D - 1, 1> coulomb_anchor(const Invariants<D, T>& p_m, const Eigen::Matrix<double, D - 1, 1>& a_n,
                                          const T& limit, bool& slips, T& slip) {
  Eigen::Matrix<T, D - 1, D - 1> cof;
  const T det = metric_determinant<D, T>(p_m.metric, cof);
  const Eigen::Matrix<T, D - 1, 1> tau = (cof.transpose() / det) * p_m.along - a_n.template cast<T>();
  const T stretch2 = tau.dot(p_m.metric * tau);
  slips = value_of(stretch2) > value_of(limit * limit);
  slip = T(0);
  if (!slips) return a_n.template cast<T>();
  const T stretch = sqrt_of(stretch2);
  const T lambda = T(2) * (stretch - limit);
  slip = lambda * limit;
  return a_n.template cast<T>() + tau * (lambda / stretch);
}

/// Gonzalez's correction of mid-point derivatives d of a potential by the
/// residual r = Φ₁ − Φₙ − (d·Δπ) over the step Δπ of the invariants, along
/// the invariants weighted by w (gap, metric, along): d + r w Δπ / |Δπ|²_w,
/// dropped while r is within `noise` (its round-off). False if Δπ = 0.
template <int D, class T>
bool correct(Invariants<D, T>& d, const Invariants<D, T>& dp, const T& r, double noise, double w_gap,
             double w_metric, double w_along) {
  T den = T(w_metric) * dp.metric.squaredNorm();
  if (w_gap > 0.0) den += T(w_gap) * dp.gap * dp.gap;
  if (w_along > 0.0) den += T(w_along) * dp.along.squaredNorm();
  if (!(value_of(den) > 0.0)) return false;
  if (!(std::abs(value_of(r)) > noise)) return true;
  if (w_gap > 0.0) d.gap += (r * T(w_gap) / den) * dp.gap;
  d.metric += (r * T(w_metric) / den) * dp.metric;
  if (w_along > 0.0) d.along += (r * T(w_along) / den) * dp.along;
  return true;
}

/// ∂Φ/∂y over the step y_n → y_np1 (columns as y) [N]: the discrete
/// gradient if `conserving`, else the mid-point gradient. T is double or
/// an automatic-differentiation scalar (the tangent).
///
/// Φ = Φ_N(ĝ, G_a) + Φ_t(G_a, c; ξ₀), each corrected along its own
/// invariants (the gap's residual of a step across ĝ = 0 put along c
/// would be a tangential force). With a finite μ the spring is a
/// Coulomb one (kind = "coulomb"; in the manner of Armero & Petőcz 1998,
/// CMAME 158:269, in these invariants): its anchor moves in the step by
/// the return map (coulomb_anchor) against the step's normal force, from
/// ξ₀ⁿ to ξ₀ⁿ⁺¹, and the discrete gradient of Φ_t splits
///   Φ_t(π₁, ξ₀ⁿ⁺¹) − Φ_t(πₙ, ξ₀ⁿ) = ∂̄Φ_t/∂π · Δπ + ∂Φ_t/∂ξ₀|_m · Δξ₀,
/// the correction on π alone: the force (from ∂̄Φ/∂π, as above: no
/// resultant, no moment) does the first term's work and
///   D = −∂Φ_t/∂ξ₀|_m · Δξ₀ = k λ · limit ≥ 0
/// is the friction's (`coulomb`), so that E_{n+1} + D = E_n.
template <int D, class T>
CouplingNodes<D, T> penalty_force(const CouplingNodes<D, double>& y_n, const CouplingNodes<D, T>& y_np1, double k,
                                  bool conserving, Anchor<D> anchor = nullptr,
                                  double mu = std::numeric_limits<double>::infinity(),
                                  CoulombStep<D, T>* coulomb = nullptr) {
  using Mat = Eigen::Matrix<T, D, D>;
  using XiT = Eigen::Matrix<T, D - 1, 1>;
  using Xi0 = Eigen::Matrix<double, D - 1, 1>;
  const Mat V_n = relative_vectors<D, double>(y_n).template cast<T>();
  const Mat V_1 = relative_vectors<D, T>(y_np1);
  const Mat V_mid = T(0.5) * (V_n + V_1);
  const Mat gap_gradient = scaled_gap_gradient<D, T>(V_mid);
  const Invariants<D, T> p_n = invariants<D, T>(V_n), p_1 = invariants<D, T>(V_1);
  // The derivatives are taken at the mean invariants (the discrete
  // gradient) or at y_{n+½}'s (the mid-point force).
  const Invariants<D, T> p_mid = conserving ? (p_n + p_1) * T(0.5) : invariants<D, T>(V_mid), dp = p_1 - p_n;
  const bool sliding = anchor && std::isfinite(mu);
  // |Δπ|² with each invariant scaled by the facet's size ℓ (ℓ² = tr G_a
  // at the start), so that none dominates by its unit.
  const double l2 = value_of(p_n.metric.trace());
  const double w_gap = 1.0 / std::pow(l2, D - 1), w_metric = 1.0 / (l2 * l2);
  const double eps16 = 16.0 * std::numeric_limits<double>::epsilon();

  // The gap's part.
  Invariants<D, T> d;
  if (!conserving) {
    potential<D, T>(p_mid, k, static_cast<const Xi0*>(nullptr), &d);
  } else {
    if (!anchor && !(p_n.gap < T(0)) && !(p_1.gap < T(0))) return CouplingNodes<D, T>::Zero();
    const T phi_n = potential<D, T>(p_n, k), phi_1 = potential<D, T>(p_1, k);
    potential<D, T>(p_mid, k, static_cast<const Xi0*>(nullptr), &d);
    const T r = phi_1 - phi_n - d.gap * dp.gap - d.metric.cwiseProduct(dp.metric).sum();
    // r's round-off (as in fem/discrete_gradient.hpp, the correction is
    // dropped within it).
    const double noise =
        eps16 * (std::abs(value_of(phi_n)) + std::abs(value_of(phi_1)) + std::abs(value_of(d.gap * p_mid.gap)) +
                 std::sqrt(value_of(d.metric.squaredNorm()) * value_of(p_mid.metric.squaredNorm())));
    correct<D, T>(d, dp, r, noise, w_gap, w_metric, 0.0);
  }

  // The spring's part.
  if (anchor) {
    XiT a_n = anchor->template cast<T>(), a_1 = a_n;
    bool slips = false;
    T slip(0);
    if (sliding) {
      // The step's normal force over k, as a gap: ⟨−∂̄Φ_N/∂ĝ⟩ √det G_m / k.
      Eigen::Matrix<T, D - 1, D - 1> cof;
      const T root = sqrt_of(metric_determinant<D, T>(p_mid.metric, cof));
      const T limit = d.gap < T(0) ? d.gap * (-mu / k) * root : T(0);
      a_1 = coulomb_anchor<D, T>(p_mid, *anchor, limit, slips, slip);
    }
    const XiT a_mid = T(0.5) * (a_n + a_1);
    // ∂Φ_t/∂ξ₀|_m · Δξ₀ = −k (ξ_m − ξ₀,m)ᵀ G_m Δξ₀ = −k λ · limit (the
    // return map makes ξ_m − ξ₀,m parallel to Δξ₀, at the limit's
    // length): in this form D ≥ 0 without round-off, which r takes.
    const T anchor_work = slip * -k;
    Invariants<D, T> s;
    const auto no_gap = [](Invariants<D, T> p) {
      p.gap = T(0);
      return p;
    };
    potential<D, T, T>(no_gap(p_mid), k, &a_mid, &s);
    T dissipated = -anchor_work;
    if (conserving) {
      const T phi_n = potential<D, T, T>(no_gap(p_n), k, &a_n), phi_1 = potential<D, T, T>(no_gap(p_1), k, &a_1);
      const T r = phi_1 - phi_n - s.metric.cwiseProduct(dp.metric).sum() - s.along.dot(dp.along) - anchor_work;
      const double noise =
          eps16 * (std::abs(value_of(phi_n)) + std::abs(value_of(phi_1)) +
                   std::sqrt(value_of(s.metric.squaredNorm()) * value_of(p_mid.metric.squaredNorm())) +
                   std::sqrt(value_of(s.along.squaredNorm()) * value_of(p_mid.along.squaredNorm())));
      // The slave still on its facet while the anchor slips toward it:
      // what r holds is the anchor's.
      if (!correct<D, T>(s, dp, r, noise, 0.0, w_metric, w_metric) && slips) dissipated -= r;
    }
    d.metric += s.metric;
    d.along = s.along;
    if (coulomb) {
      coulomb->anchor = a_1;
      coulomb->dissipated = dissipated;
      coulomb->slips = slips;
    }
  } else {
    d.along.setZero();
  }
  CouplingNodes<D, T> f = node_forces<D, T>(d, V_mid, gap_gradient);
  if constexpr (D == 3) {
    if (conserving) {
      // Δĝ = ∇ĝ(V_{n+½})·ΔV + ¼ ĝ(ΔV) (ĝ trilinear): the last term's work
      // is done along the step's non-rigid part, which has no moment.
      const T cubic = T(0.25) * scaled_gap<D, T>(Mat(V_1 - V_n));
      const StepNodes<T, D> y_1 = y_np1, y_0 = y_n.template cast<T>();
      const StepNodes<T, D> step = non_rigid<D, T>(StepNodes<T, D>(T(0.5) * (y_1 + y_0)), StepNodes<T, D>(y_1 - y_0));
      const T den = step.squaredNorm();
      if (value_of(den) > 0.0 && value_of(cubic) != 0.0) f += (d.gap * cubic / den) * step;
    }
  }
  return f;
}

/// ∂Φ/∂y at nodes y (Φ's plain gradient).
template <int D, class T>
CouplingNodes<D, T> penalty_gradient(const CouplingNodes<D, T>& y, double k, Anchor<D> anchor = nullptr) {
  const Eigen::Matrix<T, D, D> V = relative_vectors<D, T>(y);
  Invariants<D, T> d;
  potential<D, T>(invariants<D, T>(V), k, anchor, &d);
  return node_forces<D, T>(d, V, scaled_gap_gradient<D, T>(V));
}

/// Φ of nodes y (any scalar) [J].
template <int D, class T>
T penalty_potential(const CouplingNodes<D, T>& y, double k, Anchor<D> anchor = nullptr) {
  return potential<D, T>(invariants<D, T>(relative_vectors<D, T>(y)), k, anchor);
}

/// A discrete gradient over a step whose potential is Φ_n at the start
/// (one facet's, or 0 for a slave coupled in the step) and Φ_1 at the end
/// (another facet's): ∇Φ̄ (the end facet's gradient at the mid-point)
/// plus r d/|d|², r = Φ_1 − Φ_n − ∇Φ̄·Δx, d the part of Δx that is not a
/// rigid motion about x_{n+½} (Gonzalez's correction with the rigid modes
/// taken out). Its work is Φ_1 − Φ_n exactly; ∇Φ̄ (an invariant's
/// gradient) and d have no resultant and no moment about x_{n+½}, so L and
/// J are kept too. (A rigid step of the nodes is an infinitesimal rotation
/// about x_{n+½}, through the Cayley map: then d = 0 and r = 0.)
template <int D, class T>
StepNodes<T, D> switching_gradient(const StepNodes<double, D>& x_n, const StepNodes<T, D>& x_1, double phi_n,
                                   const T& phi_1, const StepNodes<T, D>& grad_mid) {
  const StepNodes<T, D> dx = x_1 - x_n.template cast<T>();
  const StepNodes<T, D> x_mid = T(0.5) * (x_1 + x_n.template cast<T>());
  const StepNodes<T, D> d = non_rigid<D, T>(x_mid, dx);
  const T r = phi_1 - T(phi_n) - grad_mid.cwiseProduct(dx).sum();
  const T den = d.squaredNorm();
  const double noise = 16.0 * std::numeric_limits<double>::epsilon() *
                       (std::abs(phi_n) + std::abs(value_of(phi_1)) +
                        std::sqrt(value_of(grad_mid.squaredNorm()) * value_of(dx.squaredNorm())));
  if (!(value_of(den) > 0.0) || !(std::abs(value_of(r)) > noise)) return grad_mid;
  return grad_mid + (r / den) * d;
}

/// The part of a master surface nearest to a slave: a facet's interior
/// (face), one of its edges (3D) or a vertex. Off the faces the potential
/// is ½ k d², d the distance to the edge or vertex, so that it is
/// continuous as the nearest part changes (penalty.hpp).
enum class FeatureKind { face, edge, vertex };

/// ½ k d² of the slave y_s to the segment x_a x_b (`edge`) or the point
/// x_a, and if `grad` is given its gradient by (y_s, x_a[, x_b]) (the
/// envelope theorem: the nearest point's parameter held) [J].
template <int D, class T>
T point_potential(const Eigen::Matrix<T, D, 1>& y_s, const Eigen::Matrix<T, D, 1>& x_a,
                  const Eigen::Matrix<T, D, 1>* x_b, double k, Eigen::Matrix<T, D, 3>* grad = nullptr) {
  // (Products with constants are written so that no scalar without
  // derivatives meets one with: Eigen's AutoDiff does not take it well.)
  Eigen::Matrix<T, D, 1> w = y_s - x_a;
  if (!x_b) {
    if (grad) {
      grad->col(0) = w * k;
      grad->col(1) = w * -k;
      grad->col(2) = w * 0.0;
    }
    return w.squaredNorm() * (0.5 * k);
  }
  const Eigen::Matrix<T, D, 1> e = *x_b - x_a;
  const T t = w.dot(e) / e.squaredNorm();
  w -= e * t;
  if (grad) {
    grad->col(0) = w * k;
    grad->col(2) = w * (t * -k);
    grad->col(1) = -(grad->col(0) + grad->col(2));
  }
  return w.squaredNorm() * (0.5 * k);
}

}  // namespace conserve::contact::penalty
