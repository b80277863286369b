#include "material/svk_law.hpp"

namespace conserve::material {

double Svk::energy(const Mat3& C) const { return svk_energy_density<3>(lame_, 0.5 * (C - Mat3::Identity())); }

// With ΔE = ½ΔC: λ/2 (2 tr E + tr ΔE) tr ΔE + μ (2E + ΔE):ΔE.
double Svk::energy_change(const Mat3& C, const Mat3& dC) const {
  const Mat3 E = 0.5 * (C - Mat3::Identity()), dE = 0.5 * dC;
  return 0.5 * lame_.lambda * (2.0 * E.trace() + dE.trace()) * dE.trace() +
         lame_.mu * (2.0 * E + dE).cwiseProduct(dE).sum();
}

Mat3 Svk::stress(const Mat3& C) const { return svk_stress<3>(lame_, 0.5 * (C - Mat3::Identity())); }

Mat9 Svk::tangent(const Mat3&) const {
  return lame_.lambda * dyad(Mat3::Identity(), Mat3::Identity()) + 2.0 * lame_.mu * symmetric_product(Mat3::Identity());
}

LawInfo svk_info() {
  return {.doc =
              "Saint Venant–Kirchhoff: ρ0Ψ = ½λ(tr E)² + μ E:E, λ and μ from `young` and `poisson`; energy "
              "quadratic in E, integrated with the Simo–Tarnow stress ½(S(E_n) + S(E_{n+1})). Softens in "
              "compression: strains beyond about 40 % turn cells inside out.",
          .parameters = {{.name = "young", .unit = "Pa", .doc = "Young's modulus E", .min = 0.0},
                         {.name = "poisson", .unit = "", .doc = "Poisson's ratio ν", .min = -1.0, .max = 0.5}},
          .make = [](const std::map<std::string, double>& p) -> std::shared_ptr<const Law> {
            return std::make_shared<Svk>(Lame::from_young_poisson(p.at("young"), p.at("poisson")));
          }};
}

}  // namespace conserve::material
