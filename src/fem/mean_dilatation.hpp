#pragma once
/// A cell's stored energy with a mean dilatation (the near-incompressibility
/// option for quadratic cells, issue 57): at its Q quadrature points, with
/// reference weights w_q (Σ w_q = V_0),
///   J̄ = Σ_q w_q J_q / V_0,   C̄_q = α_q C_q^∥ + C^⊥,   α_q = (J̄/J_q)^γ,   γ = (1 − β) 2/d,
///   W = Σ_q w_q ρ0Ψ(C̄_q),
/// the F-bar of de Souza Neto et al. 1996 with each point's J replaced by
/// J̄^{1−β} J_q^β (d = 3; plane strain d = 2 and C^∥ the in-plane block,
/// C^⊥ = e_3 ⊗ e_3, so the out-of-plane stretch stays 1). β = 0 is the
/// pure mean (P2/P0), which leaves each cell's quadratic conformal motions
/// (dev ε = 0, a zero-mean linear dilatation) without stiffness; linearised,
/// the volumetric energy is κ/2 [V_0 θ̄² + β² Σ_q w_q (θ_q − θ̄)²], and
/// β = √(μ/κ) (fluctuation_share) gives the fluctuation the bulk modulus μ:
/// no locking (μ does not grow as ν → ½) and no soft modes.
/// W is a function of the points' C_q alone:
///   S_q = (2/w_q) ∂W/∂C_q = α_q S̄_q + (1 − β)(P̄ J_q/J̄ − P_q) C_q^{∥−1},
///   S̄_q = S(C̄_q),  P_q = α_q S̄_q:C_q^∥ / d,  P̄ = Σ_p w_p P_p / V_0
/// (for a law split into isochoric and volumetric parts, as Mooney–Rivlin
/// is, and one J at every point, S_q is the law's stress). A Gonzalez
/// discrete gradient in the joint space (C_1 … C_Q), with the inner product
/// Σ_q w_q A_q:B_q, then keeps the energy of the step exactly and, each
/// S_q symmetric, the momenta.
#include <array>

#include "material/law.hpp"

namespace conserve::fem {

template <int Q>
struct DilatationCell {
  std::array<Mat3, Q> C;    ///< C_q (3 × 3; plane strain embedded, C_33 = 1)
  std::array<double, Q> w;  ///< reference weights w_q = ŵ_q det J_q [m³]
  int dim = 3;              ///< 3, or 2 (plane strain)
};

/// β = min(1, √(μ/κ)), κ = λ + 2μ/d, of the law's small-strain constants.
double fluctuation_share(const material::Law& law, int dim);

/// W [J] (per unit thickness in 2D).
template <int Q>
double mean_dilatation_energy(const material::Law& law, const DilatationCell<Q>& cell);

/// S_q and, if `dS`, the blocks ∂vec S_q/∂vec C_p at (q, p) → q·Q + p
/// (column-major vec, on the symmetric δC_p: a 9 × 9 block each).
template <int Q>
std::array<Mat3, Q> mean_dilatation_stress(const material::Law& law, const DilatationCell<Q>& cell,
                                           std::array<material::Mat9, Q * Q>* dS = nullptr);

/// The joint discrete gradient of a step C_{q,n} → C_{q,n+1} (same
/// weights): S_q^algo = S_q(C_mid) + 2 r ΔC_q / Σ_p w_p ΔC_p:ΔC_p, r = W_{n+1}
/// − W_n − ½ Σ_q w_q S_q(C_mid):ΔC_q, so ½ Σ_q w_q S_q^algo:ΔC_q = W_{n+1} −
/// W_n. The correction is dropped (the mid-point value) when it is within
/// round-off, as fem/discrete_gradient.hpp does for one point.
/// If `dS`, also ∂vec S_q^algo/∂vec C_{p,n+1} at q·Q + p:
///   ½ ∂S_q/∂C_p(C_mid) + k [ΔC_q ⊗ g_p + r δ_qp 𝕀] − (4 r w_p / D²) ΔC_q ⊗ ΔC_p,
///   k = 2/D, D = Σ w ΔC:ΔC, g_p = ½ w_p (S_p(C_{n+1}) − S_p(C_mid)) − ¼ Σ_q w_q (∂S_q/∂C_p)ᵀ:ΔC_q
/// (the single point's of fem/discrete_gradient.hpp, in the joint space).
template <int Q>
std::array<Mat3, Q> mean_dilatation_discrete_gradient(const material::Law& law, const DilatationCell<Q>& start,
                                                      const DilatationCell<Q>& end,
                                                      std::array<material::Mat9, Q * Q>* dS = nullptr);

}  // namespace conserve::fem
