#pragma once
/// The algorithmic stress of a step for laws whose energy is not quadratic
/// in E: Gonzalez's discrete gradient (Gonzalez 2000, CMAME 190:1763, (4.5);
/// docs/theory.md, "Materials: the discrete gradient"). With C_mid =
/// ½(C_n + C_{n+1}), ΔC = C_{n+1} − C_n and S = 2∂(ρ0Ψ)/∂C,
///   S_algo = S(C_mid) + 2 r ΔC / (ΔC:ΔC),
///   r = ρ0Ψ(C_{n+1}) − ρ0Ψ(C_n) − ½ S(C_mid):ΔC,
/// so that ½ S_algo:ΔC = ρ0Ψ(C_{n+1}) − ρ0Ψ(C_n) exactly: with f_A =
/// V F_{n+½} S_algo ∇N_A the internal force's work over the step is the
/// change of stored energy, and S_algo symmetric keeps L and J.
#include "material/law.hpp"

namespace conserve::fem {

/// r is computed from ΔC (material::Law::energy_change), so its round-off
/// is about ε (|S(C_mid)| + M |C_mid|) |ΔC|, M the law's small-strain
/// P-wave modulus λ + 2μ: the correction 2r ΔC/(ΔC:ΔC) then carries
/// round-off of order ε M |C|, that of the stress itself, however small
/// the step. The correction is dropped (S_algo = S(C_mid), the mid-point
/// value) when ΔC = 0 or |r| is within kRoundOffMultiple times that
/// round-off: the mid-point stress then misses the step's energy by no
/// more than the round-off r is known to. Since r = O(|ΔC|³) this is a
/// threshold on |ΔC| relative to C, about 1e-7 in the tests.
inline constexpr double kRoundOffMultiple = 16.0;

struct AlgorithmicStress {
  Mat3 S;                   ///< S_algo [Pa]
  material::Mat9 dS;        ///< ∂S_algo/∂C_{n+1}: vec(δS) = dS · vec(δC_{n+1}) [Pa] (if asked for)
  bool mid_point = false;  ///< the fallback S(C_mid) was taken
};

/// S_algo of a step C_n → C_{n+1} (3 × 3, plane strain embedded) and, if
/// `with_derivative`, its derivative with respect to C_{n+1}:
///   ¼ℂ(C_mid) + (2/ΔC:ΔC) [ΔC ⊗ w + r 𝕀 − 2r ΔC⊗ΔC / (ΔC:ΔC)],
///   w = ½(S(C_{n+1}) − S(C_mid)) − ⅛ ℂ(C_mid):ΔC
/// (¼ℂ(C_mid) alone for the fallback).
AlgorithmicStress discrete_gradient(const material::Law& law, const Mat3& C_n, const Mat3& C_np1,
                                    bool with_derivative);

}  // namespace conserve::fem
