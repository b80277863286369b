#include "fem/element.hpp"

#include <algorithm>
#include <limits>

#include "fem/discrete_gradient.hpp"

namespace conserve::fem {
namespace {

/// The quantities both the force and the tangent need.
template <int D>
struct AlgorithmicState {
  Mat<D> F_mid;  ///< F_{n+½}
  Mat<D> G;      ///< the F that pairs with δF in δS: F_{n+1} (conserving) or F_{n+½}
  Mat<D> S;      ///< algorithmic second Piola–Kirchhoff stress
};

/// Positions of a cell's N nodes.
template <int D, int N>
using Nodes = Eigen::Matrix<double, D, N>;

/// SVK's state: the Simo–Tarnow stress, or the mid-point S(E(F_{n+½})).
template <int D, int N>
AlgorithmicState<D> svk_state(const PointGeometry<D, N>& g, const material::Lame& lame, const CellStart<D>& start,
                              const Nodes<D, N>& x_np1, StressScheme scheme) {
  const Mat<D> F_np1 = x_np1.lazyProduct(g.grad.transpose());
  const Mat<D> F_mid = 0.5 * (start.F + F_np1);
  if (scheme == StressScheme::midpoint) {
    return {F_mid, F_mid, material::svk_stress<D>(lame, material::green_lagrange<D>(F_mid))};
  }
  const Mat<D> E_alg = 0.5 * (material::green_lagrange<D>(start.F) + material::green_lagrange<D>(F_np1));
  return {F_mid, F_np1, material::svk_stress<D>(lame, E_alg)};
}

/// Any other law's state, with ∂S/∂C_G (C_G = GᵀG, the C the stress is
/// varied through): the discrete gradient (conserving, G = F_{n+1}), or
/// S(C(F_{n+½})) with ¼ℂ (midpoint, G = F_{n+½}, whose C varies by half).
template <int D>
struct LawState {
  AlgorithmicState<D> state;
  material::Mat9 dS;
};

template <int D, int N>
LawState<D> law_state(const PointGeometry<D, N>& g, const material::Law& law, const CellStart<D>& start,
                      const Nodes<D, N>& x_np1, StressScheme scheme, bool with_derivative) {
  const Mat<D> F_np1 = x_np1.lazyProduct(g.grad.transpose());
  const Mat<D> F_mid = 0.5 * (start.F + F_np1);
  LawState<D> s;
  s.state.F_mid = F_mid;
  if (scheme == StressScheme::midpoint) {
    const Mat3 C = material::embed_plane_strain<D>(Mat<D>(F_mid.transpose() * F_mid));
    s.state.G = F_mid;
    s.state.S = law.stress(C).template topLeftCorner<D, D>();
    if (with_derivative) s.dS = 0.25 * law.tangent(C);
    return s;
  }
  const AlgorithmicStress a =
      discrete_gradient(law, material::embed_plane_strain<D>(Mat<D>(start.F.transpose() * start.F)),
                        material::embed_plane_strain<D>(Mat<D>(F_np1.transpose() * F_np1)), with_derivative);
  s.state.G = F_np1;
  s.state.S = a.S.template topLeftCorner<D, D>();
  if (with_derivative) s.dS = a.dS;
  return s;
}

/// f_A = V F_{n+½} S ∇N_A; one expression for the force and the tangent,
/// so that both give the same bits.
template <int D, int N>
Nodes<D, N> force_of_state(const PointGeometry<D, N>& g, const AlgorithmicState<D>& s) {
  return (g.volume * s.F_mid.lazyProduct(s.S)).lazyProduct(g.grad);  // coefficient-wise, no temporaries
}

}  // namespace

template <int D>
CellStart<D> cell_start(const SimplexGeometry<D>& g, const NodeMatrix<D>& x_n) {
  return {deformation_gradient<D>(x_n, g)};
}

namespace {

/// The force at one point (the whole cell for a linear one).
template <int D, int N>
Nodes<D, N> point_force(const PointGeometry<D, N>& g, const material::Law& law, const CellStart<D>& start,
                        const Nodes<D, N>& x_np1, StressScheme scheme) {
  if (const material::Lame* lame = law.svk())
    return force_of_state<D, N>(g, svk_state<D, N>(g, *lame, start, x_np1, scheme));
  return force_of_state<D, N>(g, law_state<D, N>(g, law, start, x_np1, scheme, false).state);
}

}  // namespace

template <int D>
NodeMatrix<D> internal_force(const SimplexGeometry<D>& g, const material::Law& law, const CellStart<D>& start,
                             const NodeMatrix<D>& x_np1, StressScheme scheme) {
  return point_force<D, D + 1>(g, law, start, x_np1, scheme);
}

template <int D>
NodeMatrix<D> internal_force(const SimplexGeometry<D>& g, const material::Law& law, const StepPositions<D>& x,
                             StressScheme scheme) {
  return internal_force<D>(g, law, cell_start<D>(g, x.x_n), x.x_np1, scheme);
}

// Perturbing x_{n+1} at node B along e_k: δF_{n+1} = e_k a_Bᵀ (a = ∇N), and
// both schemes give δF_{n+½} = ½ δF_{n+1} and δS = ½ ℂ:sym(Gᵀ e_k a_Bᵀ).
// With SVK's ℂ this yields, for block (A, B), entry (i, k):
//   ½V [ δ_ik a_B·S a_A + λ (F a_A)_i (G a_B)_k + μ (F a_B)_i (G a_A)_k
//        + μ (a_A·a_B) (F Gᵀ)_ik ],     F = F_{n+½}.
// Written column (B, k) at a time: a column is a flat vector over the rows
// (A, i), and each term an elementwise product of per-cell vectors that
// repeat a factor over A or over i (vectorisable, no D × D blocks), with
// λ' = ½Vλ, μ' = ½Vμ folded in once per cell.
template <int D>
void internal_force_tangent(const SimplexGeometry<D>& g, const material::Law& law, const StepPositions<D>& x,
                            StressScheme scheme, NodeMatrix<D>& f, ElementMatrix<D>& K) {
  internal_force_tangent<D>(g, law, cell_start<D>(g, x.x_n), x.x_np1, scheme, f, K);
}

namespace {

template <int D, int N>
using CellMatrix = Eigen::Matrix<double, D * N, D * N>;

/// SVK's closed form (above).
template <int D, int N>
void svk_force_tangent(const PointGeometry<D, N>& g, const material::Lame& lame, const CellStart<D>& start,
                       const Nodes<D, N>& x_np1, StressScheme scheme, Nodes<D, N>& f, CellMatrix<D, N>& K) {
  constexpr int n = D * N;
  using Column = Eigen::Array<double, n, 1>;
  const AlgorithmicState<D> s = svk_state<D, N>(g, lame, start, x_np1, scheme);
  f = force_of_state<D, N>(g, s);
  const double h = 0.5 * g.volume;
  const Nodes<D, N> Fa = s.F_mid * g.grad;
  const Nodes<D, N> Ga = s.G * g.grad;
  const Mat<D> mu_FGt = (h * lame.mu) * (s.F_mid * s.G.transpose());
  const Eigen::Matrix<double, N, N> aa = g.grad.transpose() * g.grad;
  const Eigen::Matrix<double, N, N> aSa = g.grad.transpose() * (h * (s.S * g.grad));
  // Columns over the rows (A, i): λ'(F a_A)_i; per B, μ'(F a_B)_i and a_A·a_B;
  // per k, (G a_A)_k and μ'(F Gᵀ)_ik.
  const Column lambda_Fa = (h * lame.lambda) * Eigen::Map<const Column>(Fa.data());
  Column mu_Fa[N], aa_of[N], Ga_of[D], FGt_of[D];
  for (int A = 0; A < N; ++A)
    for (int i = 0; i < D; ++i) {
      for (int B = 0; B < N; ++B) mu_Fa[B][A * D + i] = (h * lame.mu) * Fa(i, B), aa_of[B][A * D + i] = aa(A, B);
      for (int k = 0; k < D; ++k) Ga_of[k][A * D + i] = Ga(k, A), FGt_of[k][A * D + i] = mu_FGt(i, k);
    }
  for (int B = 0; B < N; ++B)
    for (int k = 0; k < D; ++k) {
      Eigen::Map<Column> column(K.data() + (B * D + k) * n);
      column = Ga(k, B) * lambda_Fa + mu_Fa[B] * Ga_of[k] + FGt_of[k] * aa_of[B];
      for (int A = 0; A < N; ++A) column[A * D + k] += aSa(A, B);
    }
}

// Any law: perturbing node B along e_k, δF_{n+1} = e_k a_Bᵀ, δF_{n+½} =
// ½δF_{n+1}, δC_G = G ᵀe_k a_Bᵀ + a_B e_kᵀG (ΔC's variation through G, see
// law_state), δS = dS : δC_G, and
//   δf_A = V [ ½ e_k (a_B·S a_A) + F_{n+½} δS a_A ].
// dS maps symmetric to symmetric with symmetric columns (ℂ's minor
// symmetry; the discrete gradient's terms in ΔC, w and 1 keep it), so
// dS : δC_G = 2 dS : (G_k ⊗ a_B), G_k the k-th row of G: with
//   U_ij = V F_{n+½} mat(dS(:, i + 3j)) ∇N   (D × (D+1), over i, j < D),
// δf(B, k) = 2 Σ_ij G_ki a_Bj U_ij, fixed-size products only.
template <int D, int N>
void law_force_tangent(const PointGeometry<D, N>& g, const material::Law& law, const CellStart<D>& start,
                       const Nodes<D, N>& x_np1, StressScheme scheme, Nodes<D, N>& f, CellMatrix<D, N>& K) {
  const LawState<D> s = law_state<D, N>(g, law, start, x_np1, scheme, true);
  f = force_of_state<D, N>(g, s.state);
  const double V = g.volume;
  const Eigen::Matrix<double, N, N> aSa = g.grad.transpose() * (s.state.S * g.grad);
  const Mat<D> VF = V * s.state.F_mid;
  Nodes<D, N> U[D][D];
  for (int i = 0; i < D; ++i)
    for (int j = 0; j < D; ++j) {
      const Eigen::Map<const Mat3> column(s.dS.col(i + 3 * j).data());
      U[i][j].noalias() = (VF * column.template topLeftCorner<D, D>()) * g.grad;
    }
  for (int k = 0; k < D; ++k) {
    // T_j = 2 Σ_i G_ki U_ij: then δf(B, k) = Σ_j a_Bj T_j.
    Nodes<D, N> T[D];
    for (int j = 0; j < D; ++j) {
      T[j] = (2.0 * s.state.G(k, 0)) * U[0][j];
      for (int i = 1; i < D; ++i) T[j] += (2.0 * s.state.G(k, i)) * U[i][j];
    }
    for (int B = 0; B < N; ++B) {
      Nodes<D, N> df = g.grad(0, B) * T[0];
      for (int j = 1; j < D; ++j) df += g.grad(j, B) * T[j];
      for (int A = 0; A < N; ++A)
        for (int i = 0; i < D; ++i) K(A * D + i, B * D + k) = df(i, A) + (i == k ? 0.5 * V * aSa(A, B) : 0.0);
    }
  }
}

template <int D, int N>
void point_force_tangent(const PointGeometry<D, N>& g, const material::Law& law, const CellStart<D>& start,
                         const Nodes<D, N>& x_np1, StressScheme scheme, Nodes<D, N>& f, CellMatrix<D, N>& K) {
  if (const material::Lame* lame = law.svk())
    svk_force_tangent<D, N>(g, *lame, start, x_np1, scheme, f, K);
  else
    law_force_tangent<D, N>(g, law, start, x_np1, scheme, f, K);
}

/// W at one point from its F: V ρ0Ψ(E(F)).
template <int D>
double point_energy(double volume, const material::Law& law, const Mat<D>& F) {
  if (const material::Lame* lame = law.svk())
    return volume * material::svk_energy_density<D>(*lame, material::green_lagrange<D>(F));
  return volume * law.energy(material::embed_plane_strain<D>(Mat<D>(F.transpose() * F)));
}

/// σ at one point from its F.
template <int D>
Mat3 point_stress(const material::Law& law, const Mat<D>& F) {
  const double J = F.determinant();
  Mat3 sigma = Mat3::Zero();
  if (const material::Lame* lame = law.svk()) {
    const Mat<D> E = material::green_lagrange<D>(F);
    sigma.topLeftCorner<D, D>() = F * material::svk_stress<D>(*lame, E) * F.transpose() / J;
    if constexpr (D == 2) sigma(2, 2) = lame->lambda * E.trace() / J;
    return sigma;
  }
  const Mat3 S = law.stress(material::embed_plane_strain<D>(Mat<D>(F.transpose() * F)));
  sigma.topLeftCorner<D, D>() = F * S.topLeftCorner<D, D>() * F.transpose() / J;
  if constexpr (D == 2) sigma(2, 2) = S(2, 2) / J;  // F_zz = 1
  return sigma;
}

}  // namespace

template <int D>
void internal_force_tangent(const SimplexGeometry<D>& g, const material::Law& law, const CellStart<D>& start,
                            const NodeMatrix<D>& x_np1, StressScheme scheme, NodeMatrix<D>& f, ElementMatrix<D>& K) {
  point_force_tangent<D, D + 1>(g, law, start, x_np1, scheme, f, K);
}

template <int D>
double strain_energy(const SimplexGeometry<D>& g, const material::Law& law, const NodeMatrix<D>& x) {
  return point_energy<D>(g.volume, law, deformation_gradient<D>(x, g));
}

template <int D>
Mat3 cauchy_stress(const SimplexGeometry<D>& g, const material::Law& law, const NodeMatrix<D>& x) {
  return point_stress<D>(law, deformation_gradient<D>(x, g));
}

// Quadratic cells: the sums over the points of the force rule
// (fem/quadratic.hpp) of the same point kernels.

template <int D>
void cell_start(const QuadraticGeometry<D>& g, const QuadraticNodes<D>& x_n, CellStart<D>* start) {
  for (int q = 0; q < QuadraticGeometry<D>::kPoints; ++q)
    start[q] = {x_n.lazyProduct(g.at(q).grad.transpose())};
}

template <int D>
QuadraticNodes<D> internal_force(const QuadraticGeometry<D>& g, const material::Law& law, const CellStart<D>* start,
                                 const QuadraticNodes<D>& x_np1, StressScheme scheme) {
  constexpr int N = Quadratic<D>::kNodes;
  QuadraticNodes<D> f = point_force<D, N>(g.at(0), law, start[0], x_np1, scheme);
  for (int q = 1; q < QuadraticGeometry<D>::kPoints; ++q) f += point_force<D, N>(g.at(q), law, start[q], x_np1, scheme);
  return f;
}

template <int D>
void internal_force_tangent(const QuadraticGeometry<D>& g, const material::Law& law, const CellStart<D>* start,
                            const QuadraticNodes<D>& x_np1, StressScheme scheme, QuadraticNodes<D>& f,
                            QuadraticMatrix<D>& K) {
  constexpr int N = Quadratic<D>::kNodes;
  point_force_tangent<D, N>(g.at(0), law, start[0], x_np1, scheme, f, K);
  QuadraticNodes<D> fq;
  QuadraticMatrix<D> Kq;
  for (int q = 1; q < QuadraticGeometry<D>::kPoints; ++q) {
    point_force_tangent<D, N>(g.at(q), law, start[q], x_np1, scheme, fq, Kq);
    f += fq;
    K += Kq;
  }
}

template <int D>
double strain_energy(const QuadraticGeometry<D>& g, const material::Law& law, const QuadraticNodes<D>& x) {
  double W = 0.0;
  for (int q = 0; q < QuadraticGeometry<D>::kPoints; ++q) {
    const auto p = g.at(q);
    W += point_energy<D>(p.volume, law, Mat<D>(x.lazyProduct(p.grad.transpose())));
  }
  return W;
}

template <int D>
Mat3 cauchy_stress(const QuadraticGeometry<D>& g, const material::Law& law, const QuadraticNodes<D>& x) {
  Mat3 sigma = Mat3::Zero();
  for (int q = 0; q < QuadraticGeometry<D>::kPoints; ++q) {
    const auto p = g.at(q);
    sigma += p.volume * point_stress<D>(law, Mat<D>(x.lazyProduct(p.grad.transpose())));
  }
  return sigma / g.volume;
}

template <int D>
double min_det_F(const QuadraticGeometry<D>& g, const QuadraticNodes<D>& x) {
  double lowest = std::numeric_limits<double>::infinity();
  for (int q = 0; q < QuadraticGeometry<D>::kPoints; ++q)
    lowest = std::min(lowest, Mat<D>(x.lazyProduct(g.at(q).grad.transpose())).determinant());
  return lowest;
}

#define CONSERVE_INSTANTIATE(D)                                                                                       \
  template CellStart<D> cell_start<D>(const SimplexGeometry<D>&, const NodeMatrix<D>&);                              \
  template NodeMatrix<D> internal_force<D>(const SimplexGeometry<D>&, const material::Law&, const CellStart<D>&,    \
                                           const NodeMatrix<D>&, StressScheme);                                      \
  template void internal_force_tangent<D>(const SimplexGeometry<D>&, const material::Law&, const CellStart<D>&,     \
                                          const NodeMatrix<D>&, StressScheme, NodeMatrix<D>&, ElementMatrix<D>&);    \
  template NodeMatrix<D> internal_force<D>(const SimplexGeometry<D>&, const material::Law&, const StepPositions<D>&, \
                                           StressScheme);                                                             \
  template void internal_force_tangent<D>(const SimplexGeometry<D>&, const material::Law&, const StepPositions<D>&,  \
                                          StressScheme, NodeMatrix<D>&, ElementMatrix<D>&);                           \
  template double strain_energy<D>(const SimplexGeometry<D>&, const material::Law&, const NodeMatrix<D>&);           \
  template Mat3 cauchy_stress<D>(const SimplexGeometry<D>&, const material::Law&, const NodeMatrix<D>&);              \
  template void cell_start<D>(const QuadraticGeometry<D>&, const QuadraticNodes<D>&, CellStart<D>*);                  \
  template QuadraticNodes<D> internal_force<D>(const QuadraticGeometry<D>&, const material::Law&, const CellStart<D>*, \
                                               const QuadraticNodes<D>&, StressScheme);                               \
  template void internal_force_tangent<D>(const QuadraticGeometry<D>&, const material::Law&, const CellStart<D>*,     \
                                          const QuadraticNodes<D>&, StressScheme, QuadraticNodes<D>&,                  \
                                          QuadraticMatrix<D>&);                                                        \
  template double strain_energy<D>(const QuadraticGeometry<D>&, const material::Law&, const QuadraticNodes<D>&);     \
  template Mat3 cauchy_stress<D>(const QuadraticGeometry<D>&, const material::Law&, const QuadraticNodes<D>&);       \
  template double min_det_F<D>(const QuadraticGeometry<D>&, const QuadraticNodes<D>&);
CONSERVE_INSTANTIATE(2)
CONSERVE_INSTANTIATE(3)
#undef CONSERVE_INSTANTIATE

}  // namespace conserve::fem
