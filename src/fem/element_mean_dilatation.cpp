// The mean-dilatation kernels of quadratic cells (fem/element.hpp).
#include "fem/element.hpp"
#include "fem/mean_dilatation.hpp"

namespace conserve::fem {
namespace {

using material::Mat9;
using Vec9 = Eigen::Matrix<double, 9, 1>;

template <int D>
constexpr int kPoints = QuadraticGeometry<D>::kPoints;

template <int D>
Mat3 right_cauchy_green(const Mat<D>& F) {
  return material::embed_plane_strain<D>(Mat<D>(F.transpose() * F));
}

/// The cell at positions x: C_q and the weights.
template <int D>
DilatationCell<kPoints<D>> cell_at(const QuadraticGeometry<D>& g, const QuadraticNodes<D>& x) {
  DilatationCell<kPoints<D>> c;
  c.dim = D;
  for (int q = 0; q < kPoints<D>; ++q) {
    const auto p = g.at(q);
    c.C[static_cast<std::size_t>(q)] = right_cauchy_green<D>(Mat<D>(x.lazyProduct(p.grad.transpose())));
    c.w[static_cast<std::size_t>(q)] = p.volume;
  }
  return c;
}

/// The step's stresses, the F's they pair with, and, if asked, the blocks
/// ∂S_q/∂C_{G,p} (C_G = G_pᵀG_p: G = F_{n+1} conserving, F_{n+½} midpoint,
/// whose C varies by half).
template <int D>
struct Step {
  static constexpr int Q = kPoints<D>;
  std::array<Mat<D>, Q> F_mid, G;
  std::array<Mat3, Q> S;
  std::array<Mat9, Q * Q> dS;
};

template <int D>
Step<D> step(const QuadraticGeometry<D>& g, const material::Law& law, const CellStart<D>* start,
             const QuadraticNodes<D>& x_np1, StressScheme scheme, bool with_derivative) {
  constexpr int Q = kPoints<D>;
  Step<D> s;
  DilatationCell<Q> n, np1, mid;
  n.dim = np1.dim = mid.dim = D;
  for (int q = 0; q < Q; ++q) {
    const auto p = g.at(q);
    const auto k = static_cast<std::size_t>(q);
    const Mat<D> F_np1 = x_np1.lazyProduct(p.grad.transpose());
    s.F_mid[k] = 0.5 * (start[q].F + F_np1);
    s.G[k] = scheme == StressScheme::conserving ? F_np1 : s.F_mid[k];
    n.C[k] = right_cauchy_green<D>(start[q].F);
    np1.C[k] = right_cauchy_green<D>(F_np1);
    mid.C[k] = right_cauchy_green<D>(s.F_mid[k]);
    n.w[k] = np1.w[k] = mid.w[k] = p.volume;
  }
  auto* dS = with_derivative ? &s.dS : nullptr;
  if (scheme == StressScheme::conserving) {
    s.S = mean_dilatation_discrete_gradient<Q>(law, n, np1, dS);
  } else {
    s.S = mean_dilatation_stress<Q>(law, mid, dS);
    if (dS != nullptr)
      for (auto& block : *dS) block *= 0.5;
  }
  return s;
}

template <int D>
QuadraticNodes<D> force_of(const QuadraticGeometry<D>& g, const Step<D>& s) {
  QuadraticNodes<D> f = QuadraticNodes<D>::Zero();
  for (int q = 0; q < kPoints<D>; ++q) {
    const auto p = g.at(q);
    const auto k = static_cast<std::size_t>(q);
    f += (p.volume * s.F_mid[k] * s.S[k].template topLeftCorner<D, D>()) * p.grad;
  }
  return f;
}

}  // namespace

template <int D>
QuadraticNodes<D> internal_force_mean_dilatation(const QuadraticGeometry<D>& g, const material::Law& law,
                                                 const CellStart<D>* start, const QuadraticNodes<D>& x_np1,
                                                 StressScheme scheme) {
  return force_of<D>(g, step<D>(g, law, start, x_np1, scheme, false));
}

// Node B along e_k: δF_{n+1,p} = e_k a_pBᵀ, δF_{n+½,p} = ½ δF_{n+1,p}, δC_{G,p} =
// G_pᵀ e_k a_pBᵀ + a_pB e_kᵀ G_p, δS_q = Σ_p dS_qp : δC_{G,p}, and
//   δf_A = Σ_q w_q [½ e_k (a_qB · S_q a_qA) + F_{n+½,q} δS_q a_qA].
template <int D>
void internal_force_tangent_mean_dilatation(const QuadraticGeometry<D>& g, const material::Law& law,
                                            const CellStart<D>* start, const QuadraticNodes<D>& x_np1,
                                            StressScheme scheme, QuadraticNodes<D>& f, QuadraticMatrix<D>& K) {
  constexpr int Q = kPoints<D>;
  constexpr int N = Quadratic<D>::kNodes;
  const Step<D> s = step<D>(g, law, start, x_np1, scheme, true);
  f = force_of<D>(g, s);
  K.setZero();
  std::array<typename Quadratic<D>::Point, Q> points;
  for (int q = 0; q < Q; ++q) points[static_cast<std::size_t>(q)] = g.at(q);
  for (int B = 0; B < N; ++B)
    for (int k = 0; k < D; ++k) {
      std::array<Vec9, Q> dC;
      for (std::size_t p = 0; p < Q; ++p) {
        Mat3 m = Mat3::Zero();
        const Vec<D> a = points[p].grad.col(B);
        const Vec<D> Gk = s.G[p].row(k).transpose();
        m.template topLeftCorner<D, D>() = Gk * a.transpose() + a * Gk.transpose();
        dC[p] = Eigen::Map<const Vec9>(m.data());
      }
      QuadraticNodes<D> df = QuadraticNodes<D>::Zero();
      for (std::size_t q = 0; q < Q; ++q) {
        Vec9 dS = Vec9::Zero();
        for (std::size_t p = 0; p < Q; ++p) dS += s.dS[q * Q + p].lazyProduct(dC[p]);
        const Mat<D> dSq = Eigen::Map<const Mat3>(dS.data()).template topLeftCorner<D, D>();
        const auto& grad = points[q].grad;
        const double w = points[q].volume;
        df += (w * s.F_mid[q] * dSq) * grad;
        const Eigen::Matrix<double, 1, N> aSa =
            (0.5 * w) * (grad.col(B).transpose() * s.S[q].template topLeftCorner<D, D>()) * grad;
        df.row(k) += aSa;
      }
      K.col(B * D + k) = df.reshaped();
    }
}

template <int D>
double strain_energy_mean_dilatation(const QuadraticGeometry<D>& g, const material::Law& law,
                                     const QuadraticNodes<D>& x) {
  return mean_dilatation_energy<kPoints<D>>(law, cell_at<D>(g, x));
}

template <int D>
Mat3 cauchy_stress_mean_dilatation(const QuadraticGeometry<D>& g, const material::Law& law,
                                   const QuadraticNodes<D>& x) {
  const auto cell = cell_at<D>(g, x);
  const auto S = mean_dilatation_stress<kPoints<D>>(law, cell);
  Mat3 sigma = Mat3::Zero();
  for (int q = 0; q < kPoints<D>; ++q) {
    const auto p = g.at(q);
    const auto k = static_cast<std::size_t>(q);
    Mat3 F = Mat3::Identity();
    F.template topLeftCorner<D, D>() = x.lazyProduct(p.grad.transpose());
    sigma += p.volume * (F * S[k] * F.transpose()) / F.determinant();
  }
  return sigma / g.volume;
}

#define CONSERVE_INSTANTIATE(D)                                                                                        \
  template QuadraticNodes<D> internal_force_mean_dilatation<D>(                                                        \
      const QuadraticGeometry<D>&, const material::Law&, const CellStart<D>*, const QuadraticNodes<D>&, StressScheme); \
  template void internal_force_tangent_mean_dilatation<D>(const QuadraticGeometry<D>&, const material::Law&,           \
                                                          const CellStart<D>*, const QuadraticNodes<D>&, StressScheme, \
                                                          QuadraticNodes<D>&, QuadraticMatrix<D>&);                    \
  template double strain_energy_mean_dilatation<D>(const QuadraticGeometry<D>&, const material::Law&,                  \
                                                   const QuadraticNodes<D>&);                                          \
  template Mat3 cauchy_stress_mean_dilatation<D>(const QuadraticGeometry<D>&, const material::Law&,                    \
                                                 const QuadraticNodes<D>&);
CONSERVE_INSTANTIATE(2)
CONSERVE_INSTANTIATE(3)
#undef CONSERVE_INSTANTIATE

}  // namespace conserve::fem
