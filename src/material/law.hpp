#pragma once
/// Hyperelastic point laws: the stored energy ρ0Ψ of the right Cauchy–Green
/// tensor C = FᵀF, its stress S = 2 ∂(ρ0Ψ)/∂C and tangent ℂ = 4 ∂²(ρ0Ψ)/∂C∂C
/// (so that δS = ℂ : δE with E = ½(C − 1)). Laws take 3 × 3 tensors; plane
/// strain (2D) embeds the in-plane C with C_33 = 1 (embed_plane_strain).
/// A law is one file with its LawInfo and one line in catalog.cpp.
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/types.hpp"
#include "material/svk.hpp"

namespace conserve::material {

/// A fourth-order tensor T as a 9 × 9 matrix on column-major vec(·):
/// vec(T : A) = T9 · vec(A), entry (i + 3j, k + 3l) = T_ijkl.
using Mat9 = Eigen::Matrix<double, 9, 9>;

/// The symmetric identity 𝕀_ijkl = ½(δ_ik δ_jl + δ_il δ_jk) built on a
/// symmetric A: ½(A_ik A_jl + A_il A_jk) (A = 1 gives 𝕀 itself).
Mat9 symmetric_product(const Mat3& A);
/// The dyad (A ⊗ B)_ijkl = A_ij B_kl.
Mat9 dyad(const Mat3& A, const Mat3& B);

/// ln(det(C + dC) / det C), accurate when dC is small: the change of the
/// determinant from det(A + B) = det A + tr(adj(A) B) + tr(A adj(B)) +
/// det B, then log1p (for energy_change; ln J_{n+1} − ln J_n is half of it).
double log_det_ratio(const Mat3& C, const Mat3& dC);

template <int D>
Mat3 embed_plane_strain(const Mat<D>& C) {
  if constexpr (D == 3) {
    return C;
  } else {
    Mat3 C3 = Mat3::Identity();
    C3.topLeftCorner<2, 2>() = C;
    return C3;
  }
}

class Law {
 public:
  virtual ~Law() = default;
  /// Stored energy per reference volume ρ0Ψ(C) [J/m³].
  [[nodiscard]] virtual double energy(const Mat3& C) const = 0;
  /// ρ0Ψ(C + ΔC) − ρ0Ψ(C) [J/m³]. The discrete gradient divides it by
  /// |ΔC|, so laws it serves compute it from ΔC with round-off of order
  /// ε·(their moduli)·|ΔC|, not as a difference of two energies (whose
  /// round-off, ε·(moduli)·|C|, does not shrink with the step). ΔC is an
  /// argument so that a caller can form it more exactly than C + ΔC holds
  /// it (fem/mean_dilatation.cpp).
  [[nodiscard]] virtual double energy_change(const Mat3& C, const Mat3& dC) const { return energy(C + dC) - energy(C); }
  /// S = 2 ∂(ρ0Ψ)/∂C [Pa], symmetric.
  [[nodiscard]] virtual Mat3 stress(const Mat3& C) const = 0;
  /// ℂ = 4 ∂²(ρ0Ψ)/∂C∂C [Pa], with minor and major symmetries.
  [[nodiscard]] virtual Mat9 tangent(const Mat3& C) const = 0;
  /// The Lamé constants of the law linearised at C = 1 [Pa]: the wave
  /// speeds, the stiffness scale and Newton's force scale come from them.
  [[nodiscard]] virtual Lame small_strain() const = 0;
  /// For Saint Venant–Kirchhoff (energy quadratic in E), its constants:
  /// the step then uses the Simo–Tarnow stress and its closed-form
  /// kernel (fem/element.hpp); nullptr for every other law.
  [[nodiscard]] virtual const Lame* svk() const { return nullptr; }
};

/// A parameter of a law, as `[body.material]` takes it.
struct LawParameter {
  std::string name;
  std::string unit;
  std::string doc;
  double min = -std::numeric_limits<double>::infinity();  ///< lower bound
  double max = std::numeric_limits<double>::infinity();   ///< upper bound (exclusive)
  bool min_inclusive = false;                             ///< the lower bound itself is allowed
};

/// A law's entry in the catalog: what the docs and the scenario parser
/// know of it, and how to make it from its parameters (each within its
/// bounds); `make` throws InputError for a combination it cannot take.
struct LawInfo {
  std::string doc;
  std::vector<LawParameter> parameters;
  std::function<std::shared_ptr<const Law>(const std::map<std::string, double>&)> make;
};

/// Every law by its `model` name: svk, neo_hookean, mooney_rivlin.
const std::map<std::string, LawInfo>& law_catalog();

/// The law `model` with `parameters`; throws InputError for an unknown
/// model or a combination of parameters it cannot take.
std::shared_ptr<const Law> make_law(const std::string& model, const std::map<std::string, double>& parameters);

}  // namespace conserve::material
