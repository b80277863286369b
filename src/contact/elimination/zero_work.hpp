#pragma once
/// Contact forces that do no work over a step while the slave keeps its
/// gap (docs/theory.md, "No slave behind its master"). A slave in contact
/// holds its gap γ at the END of every step exactly (position level, so it
/// never ends behind its master); the contact force is given a direction
/// ā that is orthogonal to the step's actual motion of the constraint's
/// nodes, so its work, and hence the energy error, vanish exactly; ā sums
/// to zero and has no moment about the mid-point configuration, so linear
/// and angular momentum are conserved as in the paper's §5.
///
/// Frictionless (replaces the paper's mid-point condition (48)): with the
/// slave s and the nodes b of the mid-point facet, a = (n, −N_b n) is the
/// gradient of the gap at the mid-point configuration (the paper's force
/// direction, (55)–(56)); w = PΔx is the part of the nodes' displacement
/// that is not a rigid motion about the mid-point positions; then
///   ā = a + β w,  β = −(a·Δx)/(w·w),   so ā·Δx = 0.
/// a·Δx is what the paper's (48) sets to zero: ā = a whenever (48) holds.
///
/// Stick: the slave is the point x_s = F(x_m) = N(ξ̄) x_m + γ n(x_m) of its
/// facet's frame; the master receives −Aᵀ f, with A a secant of F
/// (stick_test) such that A Δx_m = Δx_s (no work), Σ_b A_b = 1 (linear
/// momentum) and A maps the facet's rigid motions about the mid-point to
/// the slave's (angular momentum); with γ = 0, F is linear and
/// A = N(ξ̄) ⊗ 1, the paper's (41).
///
/// Every function is templated on the scalar so that the reduced tangent's
/// variation terms are obtained by automatic differentiation
/// (unsupported/Eigen/AutoDiff).
#include <Eigen/Dense>
#include <array>
#include <atomic>
#include <cmath>
#include <stdexcept>
#include <type_traits>

#include "contact/curved_facet.hpp"
#include "contact/facet.hpp"

namespace conserve::contact::zero_work {

template <int D, class S>
using V = Eigen::Matrix<S, D, 1>;
/// Positions of a constraint's nodes: column 0 the slave, 1…NF the
/// facet's (NF = D for a linear facet; 3 (2D) or 6 (3D) for a quadratic
/// one, CurvedFacet).
template <int D, class S, int NF = D>
using Nodes = Eigen::Matrix<S, D, NF + 1>;
/// Positions of a facet's NF nodes.
template <int D, class S, int NF = D>
using Facet = Eigen::Matrix<S, D, NF>;
/// ∂(one point)/∂(a facet's node positions): D × D·NF, column b·D + i.
template <int D, class S, int NF = D>
using FacetJacobian = Eigen::Matrix<S, D, D * NF>;

/// Round-off level of the work a·Δx (or of the stick defect R): relative to
/// the displacements (the sum's own round-off) and absolute, relative to
/// the positions (the displacements of slaves placed on their constraint
/// carry the round-off of the positions). Below it the value is noise,
/// which the correction, divided by the small w·w, would amplify into the
/// force direction (and Newton's residual). The correction is therefore
/// weighted by s = t²/(1 + t²), t = |a·Δx| / noise: s ≈ 1 for real work,
/// s ≈ 0 for noise; the work it leaves out, (1 − s) a·Δx, is below the
/// noise: noise = |a| (kRoundOff |Δx| + kPositionRoundOff |x|).
inline constexpr double kRoundOff = 1e-13;
inline constexpr double kPositionRoundOff = 1e-15;
/// How far above its round-off a facet's non-rigid motion must be for the
/// stick map's correction along it to act in full (stick_test).
inline constexpr double kRigidFloor = 1e3;

/// The weight s of the correction for a work (defect) whose square is
/// `value2` and whose round-off level is `noise`.
template <class S>
S correction_weight(const S& value2, const S& noise) {
  if (!(noise > 0.0)) return S(0.0);
  const S t2 = value2 / (noise * noise);
  return t2 / (S(1.0) + t2);
}

/// The value of a scalar (an automatic-differentiation one's without its
/// derivatives).
template <class S>
double value_of(const S& s) {
  if constexpr (std::is_arithmetic_v<S>)
    return s;
  else
    return s.value();
}

/// Unnormalised outward normal: τ_ξ × τ_η (3D) or (τ_y, −τ_x) (2D).
template <int D, class S>
V<D, S> raw_normal(const Facet<D, S>& x) {
  if constexpr (D == 3) {
    return (x.col(1) - x.col(0)).cross(x.col(2) - x.col(0));
  } else {
    const V<2, S> t = x.col(1) - x.col(0);
    return V<2, S>(t(1), -t(0));
  }
}

/// N_0 = 1 − Σξ, N_k = ξ_k.
template <int D, class S>
V<D, S> shape(const Eigen::Matrix<S, D - 1, 1>& xi) {
  V<D, S> N;
  N(0) = S(1.0) - xi.sum();
  N.template tail<D - 1>() = xi;
  return N;
}

/// The closest-point projection of a point p on a facet: ξ, the facet's
/// unit normal and tangents at ξ, the gap (p − x(ξ))·n and the NF shape
/// values N_b(ξ).
template <int D, class S, int NF = D>
struct Plane {
  Eigen::Matrix<S, D - 1, 1> xi;
  V<D, S> normal;
  Eigen::Matrix<S, D, D - 1> tangents;
  S gap;
  Eigen::Matrix<S, NF, 1> shape;
};

/// On a linear facet's plane (line): ξ = (τᵀτ)⁻¹ τᵀ(p − x_0).
template <int D, class S>
Plane<D, S> project_on_plane(const V<D, S>& p, const Facet<D, S>& x) {
  Plane<D, S> out;
  out.tangents = x.template rightCols<D - 1>().colwise() - x.col(0);
  out.normal = raw_normal<D, S>(x).normalized();
  const Eigen::Matrix<S, D - 1, D - 1> G = out.tangents.transpose() * out.tangents;
  out.xi = G.inverse() * (out.tangents.transpose() * (p - x.col(0)));
  out.gap = (p - x.col(0)).dot(out.normal);
  out.shape = shape<D, S>(out.xi);
  return out;
}

/// On a quadratic facet (paper (27)–(29) on a curved master): ξ̄ of the
/// guarded Newton in double (project_curved), then one Newton step in S
/// from it, ξ = ξ̄ + H⁻¹ r with r = τᵀ(p − x(ξ̄)) (zero to round-off) and
/// H = τᵀτ − (p − x)·x,_αβ, so that ξ's derivatives are Appendix 1's
/// δξ̄ = H⁻¹ [τᵀ(δp − Σ N_b δx_b) + (p − x̄)·Σ N_b,α δx_b], (87)–(94),
/// while its value is ξ̄'s. x(ξ), τ(ξ) and N(ξ) are exact quadratic
/// (linear) expansions about ξ̄. `curvature` false leaves out H's
/// curvature term: a negative control for tests only.
template <int D, class S, int NF>
Plane<D, S, NF> project_on_curved(const V<D, S>& p, const Facet<D, S, NF>& x, bool curvature = true) {
  using Shape = typename CurvedFacet<D>::Shape;
  static_assert(NF == CurvedFacet<D>::kNodes);
  using Xs = Eigen::Matrix<S, D - 1, 1>;
  typename CurvedFacet<D>::Nodes xv;
  Vec<D> pv;
  for (int i = 0; i < D; ++i) {
    pv(i) = value_of(p(i));
    for (int b = 0; b < NF; ++b) xv(i, b) = value_of(x(i, b));
  }
  const Xi<D> xi0 = project_curved<D>(pv, xv).projection.xi;
  const auto N0 = Shape::shape(xi0);
  const auto dN0 = Shape::dshape(xi0);
  const auto d2N = Shape::d2shape(xi0);
  const V<D, S> x0 = x * N0.template cast<S>();
  const Eigen::Matrix<S, D, D - 1> tau0 = x * dN0.transpose().template cast<S>();
  std::array<V<D, S>, (D - 1) * (D - 1)> xx;  // x,_αβ
  for (int a = 0; a < D - 1; ++a)
    for (int b = 0; b < D - 1; ++b) {
      V<D, S> v = V<D, S>::Zero();
      for (int n = 0; n < NF; ++n) v += S(d2N[static_cast<std::size_t>(n)](a, b)) * x.col(n);
      xx[static_cast<std::size_t>(a * (D - 1) + b)] = v;
    }
  const V<D, S> d0 = p - x0;
  Eigen::Matrix<S, D - 1, D - 1> H = tau0.transpose() * tau0;
  if (curvature)
    for (int a = 0; a < D - 1; ++a)
      for (int b = 0; b < D - 1; ++b) H(a, b) -= d0.dot(xx[static_cast<std::size_t>(a * (D - 1) + b)]);
  const Xs step = H.inverse() * (tau0.transpose() * d0);
  Plane<D, S, NF> out;
  out.xi = xi0.template cast<S>() + step;
  out.tangents = tau0;
  V<D, S> point = x0 + tau0 * step;
  for (int a = 0; a < D - 1; ++a)
    for (int b = 0; b < D - 1; ++b) {
      const V<D, S>& v = xx[static_cast<std::size_t>(a * (D - 1) + b)];
      out.tangents.col(a) += v * step(b);
      point += S(0.5) * step(a) * step(b) * v;
    }
  if constexpr (D == 3) {
    out.normal = out.tangents.col(0).cross(out.tangents.col(1)).normalized();
  } else {
    out.normal = V<2, S>(out.tangents(1, 0), -out.tangents(0, 0)).normalized();
  }
  out.gap = (p - point).dot(out.normal);
  out.shape = N0.template cast<S>() + dN0.transpose().template cast<S>() * step;
  for (int n = 0; n < NF; ++n) out.shape(n) += S(0.5) * step.dot(d2N[static_cast<std::size_t>(n)].template cast<S>() * step);
  return out;
}

/// Whether project_on_facet keeps Appendix 1's curvature term on quadratic
/// facets: always, except in the tests' negative control (which shows the
/// reduced tangent wrong without it).
inline std::atomic<bool> appendix_one_terms{true};

/// project_on_plane (NF = D) or project_on_curved.
template <int D, class S, int NF>
Plane<D, S, NF> project_on_facet(const V<D, S>& p, const Facet<D, S, NF>& x) {
  if constexpr (NF == D)
    return project_on_plane<D, S>(p, x);
  else
    return project_on_curved<D, S, NF>(p, x, appendix_one_terms.load(std::memory_order_relaxed));
}

/// Θ: the rotation of the least-squares rigid motion of a displacement δx
/// of the points y (columns), about their centroid, as a linear map of δx:
/// θ = Θ δx (column a·D + i for point a's dof i), one row in 2D, three in
/// 3D; θ = I⁻¹ Σ_a (y_a − c) × δx_a, I the points' inertia about c. It is
/// zero for a translation and ω for the rotation δx = ω × y.
template <int D, int K, class S>
Eigen::Matrix<S, D == 3 ? 3 : 1, D * K> rotation_fit(const Eigen::Matrix<S, D, K>& y) {
  const V<D, S> c = y.rowwise().mean();
  const Eigen::Matrix<S, D, K> r = y.colwise() - c;
  Eigen::Matrix<S, D == 3 ? 3 : 1, D * K> theta;
  if constexpr (D == 3) {
    Eigen::Matrix<S, 3, 3> inertia = Eigen::Matrix<S, 3, 3>::Zero();
    for (int a = 0; a < K; ++a)
      inertia += r.col(a).squaredNorm() * Eigen::Matrix<S, 3, 3>::Identity() - r.col(a) * r.col(a).transpose();
    const Eigen::Matrix<S, 3, 3> inverse = inertia.inverse();
    for (int a = 0; a < K; ++a) {
      Eigen::Matrix<S, 3, 3> cross;  // [r_a]×
      cross << S(0.0), -r(2, a), r(1, a), r(2, a), S(0.0), -r(0, a), -r(1, a), r(0, a), S(0.0);
      theta.template middleCols<3>(3 * a) = inverse * cross;
    }
  } else {
    const S inertia = r.squaredNorm();
    for (int a = 0; a < K; ++a) {
      theta(0, 2 * a) = -r(1, a) / inertia;
      theta(0, 2 * a + 1) = r(0, a) / inertia;
    }
  }
  return theta;
}

/// w = P Δx: Δx minus its least-squares rigid motion t + ω × (y − c) about
/// the centroid c of the positions y (columns are nodes). Σ w = 0 and
/// Σ (y − c) × w = 0: w carries neither force nor moment.
template <int D, int K, class S>
Eigen::Matrix<S, D, K> non_rigid_part(const Eigen::Matrix<S, D, K>& y, const Eigen::Matrix<S, D, K>& dx) {
  const V<D, S> c = y.rowwise().mean();
  const V<D, S> t = dx.rowwise().mean();
  Eigen::Matrix<S, D, K> r = y.colwise() - c, w = dx.colwise() - t;
  if constexpr (D == 3) {
    Eigen::Matrix<S, 3, 3> inertia = Eigen::Matrix<S, 3, 3>::Zero();
    V<3, S> moment = V<3, S>::Zero();
    for (int a = 0; a < K; ++a) {
      inertia += r.col(a).squaredNorm() * Eigen::Matrix<S, 3, 3>::Identity() - r.col(a) * r.col(a).transpose();
      moment += r.col(a).cross(w.col(a));
    }
    const V<3, S> omega = inertia.inverse() * moment;
    for (int a = 0; a < K; ++a) w.col(a) -= omega.cross(r.col(a));
  } else {
    S inertia(0.0), moment(0.0);
    for (int a = 0; a < K; ++a) {
      inertia += r.col(a).squaredNorm();
      moment += r(0, a) * w(1, a) - r(1, a) * w(0, a);
    }
    const S omega = moment / inertia;
    for (int a = 0; a < K; ++a) w.col(a) -= omega * V<2, S>(-r(1, a), r(0, a));
  }
  return w;
}

/// Frictionless: the zero-work force direction ā on (slave, facet nodes)
/// for the step that ends at positions x with displacements dx = x − x_n
/// (given separately: from displacement differences they are exact, from
/// position differences they would lose ε|x| to cancellation, which the
/// small denominator w·w would amplify), with the facet's mid-point
/// projection `mid` (ξ_{n+½}, n_{n+½}, τ_{n+½}).
/// With `zero_work` false the paper's gradient a itself (a pushed-out
/// slave, Constraint::push).
template <int D, class S, int NF = D>
Nodes<D, S, NF> frictionless_direction(const Nodes<D, S, NF>& x, const Nodes<D, S, NF>& dx, Plane<D, S, NF>& mid,
                                       bool zero_work = true) {
  const Nodes<D, S, NF> y = x - S(0.5) * dx;
  mid = project_on_facet<D, S, NF>(y.col(0), y.template rightCols<NF>());
  const Eigen::Matrix<S, NF, 1>& N = mid.shape;
  Nodes<D, S, NF> a;
  a.col(0) = mid.normal;
  for (int b = 0; b < NF; ++b) a.col(b + 1) = -N(b) * mid.normal;
  if (!zero_work) return a;
  const Nodes<D, S, NF> w = non_rigid_part<D, NF + 1, S>(y, dx);
  const S ww = w.squaredNorm();
  if (!(ww > 0.0)) return a;  // a rigid motion: a·Δx = 0 already
  const S work = a.cwiseProduct(dx).sum();
  const S noise = a.norm() * (S(kRoundOff) * dx.norm() + S(kPositionRoundOff) * x.norm());
  const S weight = correction_weight<S>(work * work, noise);
  return a - (weight * work / ww) * w;
}

/// Coulomb friction on a slipping slave (docs/theory.md, "Coulomb
/// friction"). The discrete slip of the step that ends at x with
/// displacements dx, at the mid-point configuration y = x − dx/2,
///   Δs = B Δx = P [Δx_s − Σ_b N_b Δx_b + γ ∇(n·Δx)],
/// with P = 1 − n nᵀ, N_b at the slave's mid-point projection ξ_{n+½}, γ
/// its mid-point gap and ∇(n·Δx) the in-plane gradient of the facet nodes'
/// normal displacements, vanishes for every rigid motion about y (Δx =
/// Ω y + c, Ω skew: the mid-point rule's discrete rigid motions), so it is
/// objective. The friction force on the constraint's nodes is μ f_N φ with
///   φ = −Bᵀ t,  t = Δs / √(|Δs|² + ε²):
/// φ_s = −t, φ_b = N_b t − γ c_b n (c = M⁻¹ τᵀ t on nodes 1…D−1, c_0 = −Σ c,
/// M = τᵀτ). Σ φ = 0 and Σ y × φ = 0 (B annihilates rigid motions), so L
/// and J are kept, and φ·Δx = −|Δs|²/√(|Δs|² + ε²) ≤ 0: its work is the
/// step's dissipation, with the sign of f_N. ε regularizes the direction
/// at zero slip (the slave then sticks, ActiveSet). `slip` gets |Δs|.
template <int D, class S>
Nodes<D, S> friction_direction(const Nodes<D, S>& x, const Nodes<D, S>& dx, double slip_scale, double& slip) {
  const Nodes<D, S> y = x - S(0.5) * dx;
  const Plane<D, S> mid = project_on_plane<D, S>(y.col(0), y.template rightCols<D>());
  const V<D, S> N = shape<D, S>(mid.xi);
  const V<D, S>& n = mid.normal;
  V<D, S> relative = dx.col(0);
  for (int b = 0; b < D; ++b) relative -= N(b) * dx.col(b + 1);
  Eigen::Matrix<S, D - 1, 1> h;  // normal displacements of facet nodes 1…D−1 relative to node 0
  for (int k = 1; k < D; ++k) h(k - 1) = n.dot(dx.col(k + 1) - dx.col(1));
  const Eigen::Matrix<S, D - 1, D - 1> metric_inverse = (mid.tangents.transpose() * mid.tangents).inverse();
  const V<D, S> gradient = mid.tangents * (metric_inverse * h);
  const V<D, S> ds = relative - n * n.dot(relative) + mid.gap * gradient;
  slip = std::sqrt(value_of(ds.squaredNorm()));
  const V<D, S> t = ds / sqrt(ds.squaredNorm() + S(slip_scale * slip_scale));
  const Eigen::Matrix<S, D - 1, 1> c = metric_inverse * (mid.tangents.transpose() * t);
  Nodes<D, S> phi;
  phi.col(0) = -t;
  for (int b = 0; b < D; ++b) {
    const S cb = b == 0 ? S(-c.sum()) : S(c(b - 1));
    phi.col(b + 1) = N(b) * t - (mid.gap * cb) * n;
  }
  return phi;
}

/// Slave parts of a frictionless constraint's test columns (the reduced
/// residual is r = Wᵀ g): for master dof (b, i) of the mid-point facet,
/// column b·D + i of `master`; for slip j, column j of `slip`. Chosen so
/// that Wᵀg = 0 holds exactly when the residual on (slave, facet nodes) is
/// parallel to ā; with ā = a they are the paper's N_b e_i and τ_j (56).
template <int D, class S, int NF = D>
struct TestColumns {
  FacetJacobian<D, S, NF> master;
  Eigen::Matrix<S, D, D - 1> slip;
  /// â·n_{n+½}, â = ā_s/|ā_s|: 1 when ā = a (the paper's force); near 0
  /// when the zero-work correction has turned the slave's force tangential.
  S cosine;
};

/// With friction μ > 0 (a slipping slave of a Coulomb pair) the columns
/// are those of the same equations on g − μ f_N φ (friction_direction,
/// f_N = n·g_s, n = n_{n+½}): each column w becomes w − μ (φ_s·w + φ_w) n,
/// φ_w the entry of φ at the column's own dof (0 for a slip). Wᵀg = 0 then
/// holds exactly when g = λ ā + μ f_N φ: the zero-work force and a
/// friction force of magnitude μ f_N against the slip (linear facets only).
template <int D, class S, int NF = D>
TestColumns<D, S, NF> frictionless_test(const Nodes<D, S, NF>& x, const Nodes<D, S, NF>& dx, bool zero_work = true,
                                        double friction = 0.0, double slip_scale = 0.0) {
  Plane<D, S, NF> mid;
  const Nodes<D, S, NF> abar = frictionless_direction<D, S, NF>(x, dx, mid, zero_work);
  const V<D, S> as = abar.col(0);
  const S as2 = as.squaredNorm();

  const Eigen::Matrix<S, NF, 1>& N = mid.shape;
  TestColumns<D, S, NF> t;
  for (int b = 0; b < NF; ++b)
    for (int i = 0; i < D; ++i) {
      V<D, S> c = V<D, S>::Zero();
      c(i) = N(b);
      t.master.col(b * D + i) = c - ((N(b) * as(i) + abar(i, b + 1)) / as2) * as;
    }
  // The slip rows: the tangents turned by the rotation R that takes n to
  // â = ā_s/|ā_s| in their plane, R = 1 + K + K²/(1 + n·â), K = â nᵀ − n âᵀ.
  // They span â's orthogonal complement whatever the angle, so Wᵀg = 0
  // makes g_s ∥ ā_s (no work). Projecting the tangents on that complement
  // instead loses a rank when ā_s turns tangential (a push-out with little
  // other non-rigid motion: ā_s·n → 0), and the force then does work
  // (docs/validation.md, §6.2). With ā = a, R = 1: the paper's τ (56).
  const V<D, S> ahat = as / sqrt(as2);
  const Eigen::Matrix<S, D, D> K = ahat * mid.normal.transpose() - mid.normal * ahat.transpose();
  const Eigen::Matrix<S, D, D> R =
      Eigen::Matrix<S, D, D>::Identity() + K + (K * K) / (S(1.0) + mid.normal.dot(ahat));
  t.slip = R * mid.tangents;
  t.cosine = mid.normal.dot(ahat);
  if constexpr (NF != D) {
    if (friction > 0.0) throw std::logic_error("zero_work: Coulomb friction on a quadratic facet");
  } else if (friction > 0.0) {
    double slip = 0.0;
    const Nodes<D, S> phi = friction_direction<D, S>(x, dx, slip_scale, slip);
    const S mu(friction);
    for (int b = 0; b < D; ++b)
      for (int i = 0; i < D; ++i) {
        auto w = t.master.col(b * D + i);
        w -= (mu * (phi.col(0).dot(w) + phi(i, b + 1))) * mid.normal;
      }
    for (int j = 0; j < D - 1; ++j) {
      auto w = t.slip.col(j);
      w -= (mu * phi.col(0).dot(w)) * mid.normal;
    }
  }
  return t;
}

/// Two frictionless constraints on one slave (a node on two slave
/// surfaces, such as the rim where a ring's side meets the plane it stands
/// on, or a slave in the notch between two facets): positions of column 0
/// the slave, 1…NF the nodes of facet 1, NF+1…2NF those of facet 2 (both
/// linear or both curved).
template <int D, class S, int NF = D>
using PairNodes = Eigen::Matrix<S, D, 2 * NF + 1>;

/// The slave parts of the two constraints' test columns. Each constraint k
/// has its own zero-work direction ā_k (frictionless_direction on the slave
/// and facet k); the slave's residual is split into the forces
/// f = (AᵀA)⁻¹ Aᵀ g_s along A = [ā_1,s ā_2,s] (least squares: exact when
/// g_s lies in their span), and facet k's node b receives −f_k ā_k,b: the
/// column of its dof i is −ā_k(i, b) B_k, B = A (AᵀA)⁻¹. What is left of
/// the slave's residual, its part along ā_1,s × ā_2,s, is the slip
/// equation (3D; in 2D the slave has no slip). Wᵀg = 0 then holds exactly
/// when g on the slave and both facets is f_1 ā_1 + f_2 ā_2: each force
/// does no work over the step and has neither resultant nor moment, so E,
/// L and J are kept as for one constraint. With ā_k = a_k these are the
/// transpose of the trial map N_k(b) C_k n_kᵀ, C = [n_1 n_2] G⁻¹ (the
/// paper's W = T).
template <int D, class S, int NF = D>
struct PairTestColumns {
  Eigen::Matrix<S, D, 2 * D * NF> master;  ///< column (k·NF + b)·D + i: facet k's node b, dof i
  V<D, S> slip;                            ///< 3D: the slip equation's direction; 2D: zero
};

template <int D, class S, int NF = D>
PairTestColumns<D, S, NF> pair_frictionless_test(const PairNodes<D, S, NF>& x, const PairNodes<D, S, NF>& dx) {
  std::array<Nodes<D, S, NF>, 2> abar;
  Eigen::Matrix<S, D, 2> A;
  for (int k = 0; k < 2; ++k) {
    Nodes<D, S, NF> xk, dxk;
    xk.col(0) = x.col(0);
    dxk.col(0) = dx.col(0);
    xk.template rightCols<NF>() = x.template middleCols<NF>(1 + k * NF);
    dxk.template rightCols<NF>() = dx.template middleCols<NF>(1 + k * NF);
    Plane<D, S, NF> mid;
    abar[k] = frictionless_direction<D, S, NF>(xk, dxk, mid);
    A.col(k) = abar[k].col(0);
  }
  const Eigen::Matrix<S, 2, 2> AtA = A.transpose() * A;
  const Eigen::Matrix<S, D, 2> B = A * AtA.inverse();
  PairTestColumns<D, S, NF> t;
  for (int k = 0; k < 2; ++k)
    for (int b = 0; b < NF; ++b)
      for (int i = 0; i < D; ++i) t.master.col((k * NF + b) * D + i) = -abar[k](i, b + 1) * B.col(k);
  if constexpr (D == 3) {
    t.slip = A.col(0).cross(A.col(1)).normalized();
  } else {
    t.slip.setZero();
  }
  return t;
}

/// Stick: the slave's position F(x_m) = N(ξ̄) x_m + γ n(x_m).
template <int D, class S>
V<D, S> stick_position(const Facet<D, S>& xm, const Xi<D>& xi, double gamma) {
  const V<D, S> N = shape<D, S>(xi.template cast<S>());
  return xm * N + S(gamma) * raw_normal<D, S>(xm).normalized();
}

/// ∂F/∂x_m = N_b 1 + γ ∂n/∂x_b, with δn = (1 − n nᵀ) δc/|c| for the raw
/// normal c (3D: ∂c/∂x_1 = −[τ_η]×, ∂c/∂x_2 = [τ_ξ]×, ∂c/∂x_0 = −the sum).
template <int D, class S>
FacetJacobian<D, S> stick_jacobian(const Facet<D, S>& xm, const Xi<D>& xi, double gamma) {
  const V<D, S> N = shape<D, S>(xi.template cast<S>());
  const V<D, S> c = raw_normal<D, S>(xm);
  const S length = c.norm();
  const V<D, S> n = c / length;
  const Eigen::Matrix<S, D, D> projector =
      (Eigen::Matrix<S, D, D>::Identity() - n * n.transpose()) * (S(gamma) / length);
  std::array<Eigen::Matrix<S, D, D>, D> dc;  // ∂c/∂x_b
  if constexpr (D == 3) {
    auto cross_matrix = [](const V<3, S>& v) {
      Eigen::Matrix<S, 3, 3> m;
      m << S(0.0), -v(2), v(1), v(2), S(0.0), -v(0), -v(1), v(0), S(0.0);
      return m;
    };
    dc[1] = -cross_matrix(xm.col(2) - xm.col(0));
    dc[2] = cross_matrix(xm.col(1) - xm.col(0));
  } else {
    dc[1] << S(0.0), S(1.0), S(-1.0), S(0.0);
  }
  dc[0] = -dc[1];
  if constexpr (D == 3) dc[0] -= dc[2];
  FacetJacobian<D, S> J;
  for (int b = 0; b < D; ++b)
    J.template block<D, D>(0, b * D) = N(b) * Eigen::Matrix<S, D, D>::Identity() + projector * dc[b];
  return J;
}

/// Stick: the secant test matrix A (D × D²) of the step that ends at
/// master positions xm with displacements dxm (exact, as for
/// frictionless_direction), the slave going to F(xm); `offset` is
/// x_s,n − F(x_m,n), the slave's start off its frozen point (round-off).
/// The master rows of the reduced residual are g_m + Aᵀ g_s. With y the
/// mid-point positions, d = y_s − F(y_m) and Θ the facet's rotation_fit,
///   A₀ = ∂F/∂x_m(y_m) − [d]× Θ   (2D: (−d_y, d_x) Θ),
/// maps every rigid motion c + ω × y_m of the facet to c + ω × y_s (F is
/// frame-indifferent, so ∂F (ω × y_m) = ω × F(y_m)); the slave's force
/// then has no resultant and no moment about y with the master's: L and J
/// are kept whatever γ. The zero-work correction acts along the facet's
/// non-rigid motion w = P Δx_m only, which no rigid motion has:
///   A = A₀ + R wᵀ/|w|²,  R = Δx_s − A₀ Δx_m,   so A Δx_m = Δx_s.
/// With γ = 0 and no offset, d = 0, R = 0 and A = N(ξ̄) ⊗ 1: the paper's (41).
template <int D, class S>
FacetJacobian<D, S> stick_test(const Facet<D, S>& xm, const Facet<D, S>& dxm, const Facet<D, double>& xm_n,
                               const Vec<D>& offset, const Xi<D>& xi, double gamma) {
  const Facet<D, S> ym = xm - S(0.5) * dxm;
  FacetJacobian<D, S> A = stick_jacobian<D, S>(ym, xi, gamma);
  const V<D, S> N = shape<D, S>(xi.template cast<S>());
  // Δx_s = F(x_m) − x_s,n = N Δx_m + γ (n(x_m) − n(x_m,n)) − offset, free of cancellation.
  const V<D, S> n_end = raw_normal<D, S>(xm).normalized();
  const V<D, S> dn = n_end - raw_normal<D, double>(xm_n).normalized().template cast<S>();
  const V<D, S> dxs = dxm * N + S(gamma) * dn - offset.template cast<S>();
  // d = y_s − F(y_m) = (N Δx_m − Δx_s)/2 + γ (n(x_m) − n(y_m)), free of cancellation too.
  const V<D, S> d = S(0.5) * (dxm * N - dxs) + S(gamma) * (n_end - raw_normal<D, S>(ym).normalized());
  const auto theta = rotation_fit<D, D, S>(ym);
  if constexpr (D == 3) {
    Eigen::Matrix<S, 3, 3> cross;  // [d]×
    cross << S(0.0), -d(2), d(1), d(2), S(0.0), -d(0), -d(1), d(0), S(0.0);
    A -= cross * theta;
  } else {
    A += V<2, S>(-d(1), d(0)) * theta;
  }
  const Facet<D, S> w = non_rigid_part<D, D, S>(ym, dxm);
  const S ww = w.squaredNorm();
  if (!(ww > 0.0)) return A;  // a rigid motion: A₀ reproduces it
  const V<D, S> R = dxs - A * dxm.reshaped();
  const S noise =
      S(kRoundOff) * (dxs.norm() + A.norm() * dxm.norm()) + S(kPositionRoundOff) * (S(1.0) + A.norm()) * xm.norm();
  const S weight = correction_weight<S>(R.squaredNorm(), noise);
  // A rigid facet (a rigid body's) has w at round-off, where R wᵀ/|w|²
  // would be noise over noise: w·w is floored at (kRigidFloor ν)², ν the
  // round-off of w, which leaves (1 − |w|²/(|w|² + (kRigidFloor ν)²)) R of
  // work, R being at round-off there too.
  const double dxm_size = std::sqrt(value_of(dxm.squaredNorm())), xm_size = std::sqrt(value_of(xm.squaredNorm()));
  const double w_noise = kRigidFloor * (kRoundOff * dxm_size + kPositionRoundOff * xm_size);
  return A + (weight / (ww + S(w_noise * w_noise))) * R * w.reshaped().transpose();
}

}  // namespace conserve::contact::zero_work
