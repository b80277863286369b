#pragma once
/// Compressible neo-Hookean law (material/law.hpp), J = √det C:
///   ρ0Ψ = μ/2 (tr C − 3) − μ ln J + λ/2 (ln J)²
///   S   = μ (1 − C⁻¹) + λ ln J C⁻¹
///   ℂ   = λ C⁻¹⊗C⁻¹ + 2(μ − λ ln J) 𝕀_{C⁻¹}
/// (Bonet & Wood, Nonlinear continuum mechanics for FE analysis, §6.4.3).
/// Its energy grows without bound as J → 0: cells resist inversion.
#include "material/law.hpp"

namespace conserve::material {

class NeoHookean final : public Law {
 public:
  explicit NeoHookean(const Lame& lame) : lame_(lame) {}
  [[nodiscard]] double energy(const Mat3& C) const override;
  [[nodiscard]] double energy_change(const Mat3& C_n, const Mat3& dC) const override;
  [[nodiscard]] Mat3 stress(const Mat3& C) const override;
  [[nodiscard]] Mat9 tangent(const Mat3& C) const override;
  [[nodiscard]] Lame small_strain() const override { return lame_; }

 private:
  Lame lame_;
};

/// `model = "neo_hookean"`: parameters young [Pa], poisson (λ, μ as for SVK).
LawInfo neo_hookean_info();

}  // namespace conserve::material
