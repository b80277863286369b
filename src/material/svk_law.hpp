#pragma once
/// Saint Venant–Kirchhoff as a point law (material/law.hpp): ρ0Ψ = ½λ(tr E)²
/// + μ E:E, S = λ tr(E) 1 + 2μE, ℂ = λ 1⊗1 + 2μ𝕀, E = ½(C − 1). Its energy
/// is quadratic in E, so the step uses the Simo–Tarnow stress (exact).
#include "material/law.hpp"

namespace conserve::material {

class Svk final : public Law {
 public:
  explicit Svk(const Lame& lame) : lame_(lame) {}
  [[nodiscard]] double energy(const Mat3& C) const override;
  [[nodiscard]] double energy_change(const Mat3& C, const Mat3& dC) const override;
  [[nodiscard]] Mat3 stress(const Mat3& C) const override;
  [[nodiscard]] Mat9 tangent(const Mat3& C) const override;
  [[nodiscard]] Lame small_strain() const override { return lame_; }
  [[nodiscard]] const Lame* svk() const override { return &lame_; }

 private:
  Lame lame_;
};

/// `model = "svk"`: parameters young [Pa], poisson.
LawInfo svk_info();

}  // namespace conserve::material
