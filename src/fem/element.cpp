#include "fem/element.hpp"

namespace conserve::fem {
namespace {

/// The quantities both the force and the tangent need.
template <int D>
struct AlgorithmicState {
  Mat<D> F_mid;  ///< F_{n+½}
  Mat<D> G;      ///< the F that pairs with δF in δS: F_{n+1} (conserving) or F_{n+½}
  Mat<D> S;      ///< algorithmic second Piola–Kirchhoff stress
};

template <int D>
AlgorithmicState<D> algorithmic_state(const SimplexGeometry<D>& g, const material::Lame& lame,
                                      const StepPositions<D>& x, StressScheme scheme) {
  const Mat<D> F_n = deformation_gradient<D>(x.x_n, g);
  const Mat<D> F_np1 = deformation_gradient<D>(x.x_np1, g);
  const Mat<D> F_mid = 0.5 * (F_n + F_np1);
  if (scheme == StressScheme::midpoint) {
    return {F_mid, F_mid, material::svk_stress<D>(lame, material::green_lagrange<D>(F_mid))};
  }
  const Mat<D> E_alg = 0.5 * (material::green_lagrange<D>(F_n) + material::green_lagrange<D>(F_np1));
  return {F_mid, F_np1, material::svk_stress<D>(lame, E_alg)};
}

}  // namespace

template <int D>
NodeMatrix<D> internal_force(const SimplexGeometry<D>& g, const material::Lame& lame, const StepPositions<D>& x,
                             StressScheme scheme) {
  const AlgorithmicState<D> s = algorithmic_state<D>(g, lame, x, scheme);
  return g.volume * (s.F_mid * s.S * g.grad);
}

// Perturbing x_{n+1} at node B along e_k: δF_{n+1} = e_k a_Bᵀ (a = ∇N), and
// both schemes give δF_{n+½} = ½ δF_{n+1} and δS = ½ ℂ:sym(Gᵀ e_k a_Bᵀ).
// With SVK's ℂ this yields, for block (A, B), entry (i, k):
//   ½V [ δ_ik a_B·S a_A + λ (F a_A)_i (G a_B)_k + μ (F a_B)_i (G a_A)_k
//        + μ (a_A·a_B) (F Gᵀ)_ik ],     F = F_{n+½}.
template <int D>
void internal_force_tangent(const SimplexGeometry<D>& g, const material::Lame& lame, const StepPositions<D>& x,
                            StressScheme scheme, NodeMatrix<D>& f, ElementMatrix<D>& K) {
  const AlgorithmicState<D> s = algorithmic_state<D>(g, lame, x, scheme);
  const NodeMatrix<D> Fa = s.F_mid * g.grad;
  const NodeMatrix<D> Ga = s.G * g.grad;
  const Mat<D> FGt = s.F_mid * s.G.transpose();
  const Eigen::Matrix<double, D + 1, D + 1> aSa = g.grad.transpose() * s.S * g.grad;
  const Eigen::Matrix<double, D + 1, D + 1> aa = g.grad.transpose() * g.grad;
  const double h = 0.5 * g.volume;
  f = g.volume * (s.F_mid * s.S * g.grad);
  for (int B = 0; B < D + 1; ++B) {
    for (int A = 0; A < D + 1; ++A) {
      Mat<D> block = lame.lambda * Fa.col(A) * Ga.col(B).transpose() + lame.mu * Fa.col(B) * Ga.col(A).transpose() +
                     lame.mu * aa(A, B) * FGt;
      block.diagonal().array() += aSa(A, B);
      K.template block<D, D>(A * D, B * D) = h * block;
    }
  }
}

template <int D>
double strain_energy(const SimplexGeometry<D>& g, const material::Lame& lame, const NodeMatrix<D>& x) {
  const Mat<D> E = material::green_lagrange<D>(deformation_gradient<D>(x, g));
  return g.volume * material::svk_energy_density<D>(lame, E);
}

template <int D>
Mat3 cauchy_stress(const SimplexGeometry<D>& g, const material::Lame& lame, const NodeMatrix<D>& x) {
  const Mat<D> F = deformation_gradient<D>(x, g);
  const Mat<D> E = material::green_lagrange<D>(F);
  const double J = F.determinant();
  Mat3 sigma = Mat3::Zero();
  sigma.topLeftCorner<D, D>() = F * material::svk_stress<D>(lame, E) * F.transpose() / J;
  if constexpr (D == 2) sigma(2, 2) = lame.lambda * E.trace() / J;
  return sigma;
}

#define CONSERVE_INSTANTIATE(D)                                                                                       \
  template NodeMatrix<D> internal_force<D>(const SimplexGeometry<D>&, const material::Lame&, const StepPositions<D>&, \
                                           StressScheme);                                                             \
  template void internal_force_tangent<D>(const SimplexGeometry<D>&, const material::Lame&, const StepPositions<D>&,  \
                                          StressScheme, NodeMatrix<D>&, ElementMatrix<D>&);                           \
  template double strain_energy<D>(const SimplexGeometry<D>&, const material::Lame&, const NodeMatrix<D>&);           \
  template Mat3 cauchy_stress<D>(const SimplexGeometry<D>&, const material::Lame&, const NodeMatrix<D>&);
CONSERVE_INSTANTIATE(2)
CONSERVE_INSTANTIATE(3)
#undef CONSERVE_INSTANTIATE

}  // namespace conserve::fem
