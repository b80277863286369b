#pragma once
/// Compressible Mooney–Rivlin law (material/law.hpp), with the isochoric
/// invariants Ī₁ = J^(−2/3) I₁, Ī₂ = J^(−4/3) I₂, I₂ = ½(I₁² − C:C):
///   ρ0Ψ = c₁₀ (Ī₁ − 3) + c₀₁ (Ī₂ − 3) + κ/2 (J − 1)²
///   S   = 2c₁₀ J^(−2/3) (1 − ⅓I₁C⁻¹) + 2c₀₁ J^(−4/3) (I₁1 − C − ⅔I₂C⁻¹)
///         + κ (J − 1) J C⁻¹
/// ℂ as derived in mooney_rivlin.cpp. Small strain: μ = 2(c₁₀ + c₀₁),
/// bulk modulus κ (λ = κ − ⅔μ).
#include "material/law.hpp"

namespace conserve::material {

struct MooneyRivlinConstants {
  double c10 = 0.0;   ///< [Pa]
  double c01 = 0.0;   ///< [Pa]
  double bulk = 0.0;  ///< κ [Pa]
};

class MooneyRivlin final : public Law {
 public:
  explicit MooneyRivlin(const MooneyRivlinConstants& k) : k_(k) {}
  [[nodiscard]] double energy(const Mat3& C) const override;
  [[nodiscard]] double energy_change(const Mat3& C_n, const Mat3& dC) const override;
  [[nodiscard]] Mat3 stress(const Mat3& C) const override;
  [[nodiscard]] Mat9 tangent(const Mat3& C) const override;
  [[nodiscard]] Lame small_strain() const override;

 private:
  MooneyRivlinConstants k_;
};

/// `model = "mooney_rivlin"`: parameters c10, c01, bulk [Pa].
LawInfo mooney_rivlin_info();

}  // namespace conserve::material
