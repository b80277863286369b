#include "material/mooney_rivlin.hpp"

#include <fmt/format.h>

#include <cmath>

#include "core/error.hpp"

namespace conserve::material {
namespace {

/// The invariants of C the law is written in.
struct Invariants {
  double I1, I2, J;
  Mat3 C_inv;
};

Invariants invariants(const Mat3& C) {
  const double I1 = C.trace();
  return {I1, 0.5 * (I1 * I1 - C.squaredNorm()), std::sqrt(C.determinant()), C.inverse()};
}

}  // namespace

double MooneyRivlin::energy(const Mat3& C) const {
  const Invariants v = invariants(C);
  return k_.c10 * (std::pow(v.J, -2.0 / 3.0) * v.I1 - 3.0) + k_.c01 * (std::pow(v.J, -4.0 / 3.0) * v.I2 - 3.0) +
         0.5 * k_.bulk * (v.J - 1.0) * (v.J - 1.0);
}

// Each term's change from ΔC and d = ln J_{n+1} − ln J_n without
// subtracting energies: J^a_{n+1} − J^a_n = J^a_n expm1(a d),
// ΔI₁ = tr ΔC, ΔI₂ = ½(ΔI₁ (I₁ + I₁') − ΔC:(C + C')).
double MooneyRivlin::energy_change(const Mat3& C_n, const Mat3& dC) const {
  const Invariants v = invariants(C_n);
  const double d = 0.5 * log_det_ratio(C_n, dC);
  const double dI1 = dC.trace(), I1_np1 = v.I1 + dI1;
  const double dI2 = 0.5 * (dI1 * (v.I1 + I1_np1) - dC.cwiseProduct(2.0 * C_n + dC).sum());
  const double a_n = std::pow(v.J, -2.0 / 3.0), b_n = std::pow(v.J, -4.0 / 3.0);
  const double da = a_n * std::expm1(-2.0 * d / 3.0), db = b_n * std::expm1(-4.0 * d / 3.0);
  const double dJ = v.J * std::expm1(d);
  return k_.c10 * ((a_n + da) * dI1 + v.I1 * da) + k_.c01 * ((b_n + db) * dI2 + v.I2 * db) +
         0.5 * k_.bulk * dJ * (2.0 * v.J + dJ - 2.0);
}

Mat3 MooneyRivlin::stress(const Mat3& C) const {
  const Invariants v = invariants(C);
  const Mat3 I = Mat3::Identity();
  return (2.0 * k_.c10 * std::pow(v.J, -2.0 / 3.0)) * (I - (v.I1 / 3.0) * v.C_inv) +
         (2.0 * k_.c01 * std::pow(v.J, -4.0 / 3.0)) * (v.I1 * I - C - (2.0 * v.I2 / 3.0) * v.C_inv) +
         (k_.bulk * (v.J - 1.0) * v.J) * v.C_inv;
}

// ℂ = 2 ∂S/∂C, from ∂C⁻¹/∂C = −𝕀_{C⁻¹}, ∂J^a/∂C = (a/2) J^a C⁻¹,
// ∂I₁/∂C = 1, ∂I₂/∂C = I₁1 − C, term by term:
//   4c₁₀ J^(−2/3) [ −⅓(1⊗C⁻¹ + C⁻¹⊗1) + ⅑I₁ C⁻¹⊗C⁻¹ + ⅓I₁ 𝕀_{C⁻¹} ]
//   4c₀₁ J^(−4/3) [ 1⊗1 − 𝕀 − ⅔I₁(1⊗C⁻¹ + C⁻¹⊗1) + ⅔(C⊗C⁻¹ + C⁻¹⊗C)
//                   + (4/9)I₂ C⁻¹⊗C⁻¹ + ⅔I₂ 𝕀_{C⁻¹} ]
//   κ [ (2J² − J) C⁻¹⊗C⁻¹ − 2(J² − J) 𝕀_{C⁻¹} ]
Mat9 MooneyRivlin::tangent(const Mat3& C) const {
  const Invariants v = invariants(C);
  const Mat3 I = Mat3::Identity();
  const Mat9 ici = dyad(I, v.C_inv) + dyad(v.C_inv, I), cc = dyad(v.C_inv, v.C_inv), sym = symmetric_product(v.C_inv);
  const Mat9 first = -ici / 3.0 + (v.I1 / 9.0) * cc + (v.I1 / 3.0) * sym;
  const Mat9 second = dyad(I, I) - symmetric_product(I) - (2.0 * v.I1 / 3.0) * ici +
                      (2.0 / 3.0) * (dyad(C, v.C_inv) + dyad(v.C_inv, C)) + (4.0 * v.I2 / 9.0) * cc +
                      (2.0 * v.I2 / 3.0) * sym;
  const double J2 = v.J * v.J;
  return (4.0 * k_.c10 * std::pow(v.J, -2.0 / 3.0)) * first + (4.0 * k_.c01 * std::pow(v.J, -4.0 / 3.0)) * second +
         k_.bulk * ((2.0 * J2 - v.J) * cc - 2.0 * (J2 - v.J) * sym);
}

Lame MooneyRivlin::small_strain() const {
  const double mu = 2.0 * (k_.c10 + k_.c01);
  return {k_.bulk - 2.0 * mu / 3.0, mu};
}

LawInfo mooney_rivlin_info() {
  return {.doc =
              "compressible Mooney–Rivlin: ρ0Ψ = c₁₀ (Ī₁ − 3) + c₀₁ (Ī₂ − 3) + κ/2 (J − 1)², with Ī₁ = "
              "J^(−2/3) I₁, Ī₂ = J^(−4/3) I₂; small-strain shear modulus μ = 2(c₁₀ + c₀₁), bulk modulus κ; "
              "integrated with Gonzalez's discrete gradient.",
          .parameters = {{.name = "c10", .unit = "Pa", .doc = "c₁₀ (c₁₀ + c₀₁ > 0)", .min = 0.0, .min_inclusive = true},
                         {.name = "c01", .unit = "Pa", .doc = "c₀₁", .min = 0.0, .min_inclusive = true},
                         {.name = "bulk", .unit = "Pa", .doc = "bulk modulus κ", .min = 0.0}},
          .make = [](const std::map<std::string, double>& p) -> std::shared_ptr<const Law> {
            const MooneyRivlinConstants k{p.at("c10"), p.at("c01"), p.at("bulk")};
            if (!(k.c10 + k.c01 > 0.0))
              throw InputError(
                  fmt::format("c10 + c01 = {} gives no shear stiffness (expected c10 + c01 > 0)", k.c10 + k.c01));
            return std::make_shared<MooneyRivlin>(k);
          }};
}

}  // namespace conserve::material
