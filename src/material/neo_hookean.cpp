#include "material/neo_hookean.hpp"

#include <cmath>

namespace conserve::material {

double NeoHookean::energy(const Mat3& C) const {
  const double log_J = 0.5 * std::log(C.determinant());
  return 0.5 * lame_.mu * (C.trace() - 3.0) - lame_.mu * log_J + 0.5 * lame_.lambda * log_J * log_J;
}

// With d = ln J_{n+1} − ln J_n: μ/2 tr ΔC − μ d + λ/2 d (ln J_{n+1} + ln J_n).
double NeoHookean::energy_change(const Mat3& C_n, const Mat3& dC) const {
  const double d = 0.5 * log_det_ratio(C_n, dC);
  const double log_J_n = 0.5 * std::log(C_n.determinant());
  return 0.5 * lame_.mu * dC.trace() - lame_.mu * d + 0.5 * lame_.lambda * d * (2.0 * log_J_n + d);
}

Mat3 NeoHookean::stress(const Mat3& C) const {
  const Mat3 C_inv = C.inverse();
  const double log_J = 0.5 * std::log(C.determinant());
  return lame_.mu * (Mat3::Identity() - C_inv) + (lame_.lambda * log_J) * C_inv;
}

Mat9 NeoHookean::tangent(const Mat3& C) const {
  const Mat3 C_inv = C.inverse();
  const double log_J = 0.5 * std::log(C.determinant());
  return lame_.lambda * dyad(C_inv, C_inv) + 2.0 * (lame_.mu - lame_.lambda * log_J) * symmetric_product(C_inv);
}

LawInfo neo_hookean_info() {
  return {.doc =
              "compressible neo-Hookean: ρ0Ψ = μ/2 (I₁ − 3) − μ ln J + λ/2 (ln J)², λ and μ from `young` and "
              "`poisson` as for svk (the same small-strain response); integrated with Gonzalez's discrete "
              "gradient. Its energy grows without bound as J → 0.",
          .parameters =
              {{.name = "young", .unit = "Pa", .doc = "Young's modulus E at small strain", .min = 0.0},
               {.name = "poisson", .unit = "", .doc = "Poisson's ratio ν at small strain", .min = -1.0, .max = 0.5}},
          .make = [](const std::map<std::string, double>& p) -> std::shared_ptr<const Law> {
            return std::make_shared<NeoHookean>(Lame::from_young_poisson(p.at("young"), p.at("poisson")));
          }};
}

}  // namespace conserve::material
