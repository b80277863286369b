#include "fem/mean_dilatation.hpp"

#include <cmath>
#include <limits>

#include "fem/discrete_gradient.hpp"

namespace conserve::fem {

double fluctuation_share(const material::Law& law, int dim) {
  const material::Lame lame = law.small_strain();
  const double bulk = lame.lambda + 2.0 * lame.mu / dim;
  return bulk > lame.mu ? std::sqrt(lame.mu / bulk) : 1.0;
}

namespace {

using material::Mat9;
using Vec9 = Eigen::Matrix<double, 9, 1>;

double contract(const Mat3& A, const Mat3& B) { return A.cwiseProduct(B).sum(); }

/// The cell's mean-dilatation quantities at one configuration.
template <int Q>
struct Bar {
  std::array<Mat3, Q> par, par_inv, C_bar, S_bar;  ///< C^∥, (C^∥)⁻¹ (in-plane in 2D), C̄_q, S(C̄_q)
  std::array<double, Q> J, alpha, P;
  double V0 = 0.0, J_bar = 0.0, P_bar = 0.0, d = 3.0;
  double beta = 0.0;   ///< the share of J_q kept, fluctuation_share(law, d)
  double gamma = 0.0;  ///< the exponent of α_q, (1 − β) 2/d

  /// `stresses`: also S̄_q, P_q and P̄ (not needed for C̄ alone).
  Bar(const material::Law& law, const DilatationCell<Q>& cell, bool stresses = true)
      : d(cell.dim), beta(fluctuation_share(law, cell.dim)), gamma((1.0 - beta) * 2.0 / d) {
    for (int q = 0; q < Q; ++q) {
      const Mat3& C = cell.C[static_cast<std::size_t>(q)];
      Mat3& par_q = par[static_cast<std::size_t>(q)];
      Mat3& inv_q = par_inv[static_cast<std::size_t>(q)];
      if (cell.dim == 3) {
        par_q = C;
        inv_q = C.inverse();
      } else {
        par_q.setZero(), inv_q.setZero();
        par_q.topLeftCorner<2, 2>() = C.topLeftCorner<2, 2>();
        inv_q.topLeftCorner<2, 2>() = C.topLeftCorner<2, 2>().inverse();
      }
      J[static_cast<std::size_t>(q)] = std::sqrt(C.determinant());
      V0 += cell.w[static_cast<std::size_t>(q)];
      J_bar += cell.w[static_cast<std::size_t>(q)] * J[static_cast<std::size_t>(q)];
    }
    J_bar /= V0;
    for (std::size_t q = 0; q < Q; ++q) {
      alpha[q] = std::pow(J_bar / J[q], gamma);
      C_bar[q] = alpha[q] * par[q];
      if (cell.dim == 2) C_bar[q](2, 2) = 1.0;
      if (!stresses) continue;
      S_bar[q] = law.stress(C_bar[q]);
      P[q] = alpha[q] * contract(S_bar[q], par[q]) / d;
      P_bar += cell.w[q] * P[q];
    }
    P_bar /= V0;
  }
};

}  // namespace

template <int Q>
double mean_dilatation_energy(const material::Law& law, const DilatationCell<Q>& cell) {
  const Bar<Q> b(law, cell);
  double W = 0.0;
  for (std::size_t q = 0; q < Q; ++q) W += cell.w[q] * law.energy(b.C_bar[q]);
  return W;
}

template <int Q>
std::array<Mat3, Q> mean_dilatation_stress(const material::Law& law, const DilatationCell<Q>& cell,
                                           std::array<Mat9, Q * Q>* dS) {
  const Bar<Q> b(law, cell);
  std::array<Mat3, Q> S;
  for (std::size_t q = 0; q < Q; ++q)
    S[q] = b.alpha[q] * b.S_bar[q] + (1.0 - b.beta) * (b.P_bar * b.J[q] / b.J_bar - b.P[q]) * b.par_inv[q];
  if (dS == nullptr) return S;
  // Directional derivatives along sym(e_k e_lᵀ) at one point p, by the chain
  // dJ_p = ½ J_p C_p^{∥−1}:δC, dJ̄ = w_p dJ_p / V_0, dα_q = γ α_q (dJ̄/J̄ − dJ_q/J_q),
  // dC̄_q = dα_q C_q^∥ + α_q δC_q, dS̄_q = ½ ℂ(C̄_q):dC̄_q (material/law.hpp's ℂ), then P, P̄, S.
  // ½ℂ:C^∥ and its contraction with C^∥ once per point; ½ℂ:δC along sym(e_k e_lᵀ) is ¼ of two
  // columns of ℂ. Both orders (k, l) give one column: computed for k ≤ l.
  std::array<Mat9, Q> tangent;
  std::array<Mat3, Q> T_par;
  std::array<double, Q> SP, TP;
  for (std::size_t q = 0; q < Q; ++q) {
    tangent[q] = law.tangent(b.C_bar[q]);
    const Vec9 v = 0.5 * tangent[q].lazyProduct(Eigen::Map<const Vec9>(b.par[q].data()));
    T_par[q] = Eigen::Map<const Mat3>(v.data());
    SP[q] = contract(b.S_bar[q], b.par[q]);
    TP[q] = contract(T_par[q], b.par[q]);
  }
  const int n = cell.dim;
  for (std::size_t p = 0; p < Q; ++p) {
    for (std::size_t q = 0; q < Q; ++q) (*dS)[q * Q + p].setZero();
    for (int k = 0; k < n; ++k)
      for (int l = k; l < n; ++l) {
        Mat3 dC = Mat3::Zero();
        dC(k, l) += 0.5, dC(l, k) += 0.5;
        const Vec9 column = 0.25 * (tangent[p].col(k + 3 * l) + tangent[p].col(l + 3 * k));
        const Mat3 T_dC = Eigen::Map<const Mat3>(column.data());  // ½ℂ_p:δC
        const double dJ_p = 0.5 * b.J[p] * contract(b.par_inv[p], dC);
        const double dJ_bar = cell.w[p] * dJ_p / b.V0;
        std::array<double, Q> dalpha, dP;
        std::array<Mat3, Q> dS_bar;
        double dP_bar = 0.0;
        for (std::size_t q = 0; q < Q; ++q) {
          const double dJ_q = q == p ? dJ_p : 0.0;
          dalpha[q] = b.gamma * b.alpha[q] * (dJ_bar / b.J_bar - dJ_q / b.J[q]);
          dS_bar[q] = dalpha[q] * T_par[q];
          dP[q] = dalpha[q] * (SP[q] + b.alpha[q] * TP[q]);
          if (q == p) {
            dS_bar[q] += b.alpha[q] * T_dC;
            dP[q] += b.alpha[q] * (b.alpha[q] * contract(T_dC, b.par[q]) + contract(b.S_bar[q], dC));
          }
          dP[q] /= b.d;
          dP_bar += cell.w[q] * dP[q];
        }
        dP_bar /= b.V0;
        for (std::size_t q = 0; q < Q; ++q) {
          const double dJ_q = q == p ? dJ_p : 0.0;
          const double pressure = (1.0 - b.beta) * (b.P_bar * b.J[q] / b.J_bar - b.P[q]);
          const double dpressure = (1.0 - b.beta) * (dP_bar * b.J[q] / b.J_bar + b.P_bar * dJ_q / b.J_bar -
                                                     b.P_bar * b.J[q] * dJ_bar / (b.J_bar * b.J_bar) - dP[q]);
          Mat3 d = dalpha[q] * b.S_bar[q] + b.alpha[q] * dS_bar[q] + dpressure * b.par_inv[q];
          if (q == p) d -= pressure * b.par_inv[q] * dC * b.par_inv[q];
          auto& block = (*dS)[q * Q + p];
          block.col(k + 3 * l) = Eigen::Map<const Vec9>(d.data());
          if (l != k) block.col(l + 3 * k) = block.col(k + 3 * l);
        }
      }
  }
  return S;
}

template <int Q>
std::array<Mat3, Q> mean_dilatation_discrete_gradient(const material::Law& law, const DilatationCell<Q>& start,
                                                      const DilatationCell<Q>& end, std::array<Mat9, Q * Q>* dS) {
  DilatationCell<Q> mid = start;
  for (std::size_t q = 0; q < Q; ++q) mid.C[q] = 0.5 * (start.C[q] + end.C[q]);
  std::array<Mat3, Q> S = mean_dilatation_stress<Q>(law, mid, dS);
  if (dS != nullptr)
    for (auto& block : *dS) block *= 0.5;  // C_mid moves by half of C_{n+1}
  const Bar<Q> b_n(law, start, false);
  std::array<Mat3, Q> dC;
  std::array<double, Q> dlog_J;  // ln J_{q,n+1} − ln J_{q,n}, from ΔC_q
  double dJ_bar = 0.0;
  for (std::size_t q = 0; q < Q; ++q) {
    dC[q] = end.C[q] - start.C[q];
    dlog_J[q] = 0.5 * material::log_det_ratio(start.C[q], dC[q]);
    dJ_bar += start.w[q] * b_n.J[q] * std::expm1(dlog_J[q]);
  }
  const double dlog_J_bar = std::log1p(dJ_bar / (b_n.V0 * b_n.J_bar));
  double r = 0.0, dCdC = 0.0, scale = 0.0;
  const material::Lame lame = law.small_strain();
  for (std::size_t q = 0; q < Q; ++q) {
    // ΔC̄_q = α_{n+1} ΔC_q + Δα_q C^∥_{q,n}, Δα_q = α_n expm1(γ Δln(J̄/J_q)): from ΔC, so that
    // r carries round-off ε M |ΔC| (as fem/discrete_gradient.hpp's), not ε M |C|.
    const double dalpha = b_n.alpha[q] * std::expm1(b_n.gamma * (dlog_J_bar - dlog_J[q]));
    const Mat3 dC_bar = (b_n.alpha[q] + dalpha) * dC[q] + dalpha * b_n.par[q];
    r += start.w[q] * (law.energy_change(b_n.C_bar[q], dC_bar) - 0.5 * contract(S[q], dC[q]));
    dCdC += start.w[q] * dC[q].squaredNorm();
    scale += start.w[q] * (S[q].norm() + (lame.lambda + 2.0 * lame.mu) * mid.C[q].norm());
  }
  const double noise = kRoundOffMultiple * std::numeric_limits<double>::epsilon() * scale * std::sqrt(dCdC / b_n.V0);
  if (!(dCdC > 0.0) || !(std::abs(r) > noise)) return S;  // the mid-point value
  const double k = 2.0 / dCdC;
  if (dS != nullptr) {
    const std::array<Mat3, Q> S_end = mean_dilatation_stress<Q>(law, end);
    static const Mat9 identity = material::symmetric_product(Mat3::Identity());
    for (std::size_t p = 0; p < Q; ++p) {
      // g_p, with (*dS) already ½ ∂S/∂C_p(C_mid): ¼ Σ_q w_q (∂S_q/∂C_p)ᵀ ΔC_q = ½ Σ_q w_q dS_qpᵀ ΔC_q.
      Vec9 g = Eigen::Map<const Vec9>(Mat3(0.5 * start.w[p] * (S_end[p] - S[p])).data());
      for (std::size_t q = 0; q < Q; ++q)
        g -= 0.5 * start.w[q] * (*dS)[q * Q + p].transpose().lazyProduct(Eigen::Map<const Vec9>(dC[q].data()));
      for (std::size_t q = 0; q < Q; ++q) {
        const Eigen::Map<const Vec9> dq(dC[q].data()), dp(dC[p].data());
        Mat9& block = (*dS)[q * Q + p];
        block += k * (dq * g.transpose()) - (4.0 * r * start.w[p] / (dCdC * dCdC)) * (dq * dp.transpose());
        if (q == p) block += k * r * identity;
      }
    }
  }
  for (std::size_t q = 0; q < Q; ++q) S[q] += k * r * dC[q];
  return S;
}

template double mean_dilatation_energy<3>(const material::Law&, const DilatationCell<3>&);
template double mean_dilatation_energy<4>(const material::Law&, const DilatationCell<4>&);
template std::array<Mat3, 3> mean_dilatation_stress<3>(const material::Law&, const DilatationCell<3>&,
                                                       std::array<Mat9, 9>*);
template std::array<Mat3, 4> mean_dilatation_stress<4>(const material::Law&, const DilatationCell<4>&,
                                                       std::array<Mat9, 16>*);
template std::array<Mat3, 3> mean_dilatation_discrete_gradient<3>(const material::Law&, const DilatationCell<3>&,
                                                                  const DilatationCell<3>&, std::array<Mat9, 9>*);
template std::array<Mat3, 4> mean_dilatation_discrete_gradient<4>(const material::Law&, const DilatationCell<4>&,
                                                                  const DilatationCell<4>&, std::array<Mat9, 16>*);

}  // namespace conserve::fem
