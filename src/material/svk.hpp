#pragma once
/// Saint Venant–Kirchhoff hyperelasticity (docs/theory.md, "Material"):
///   E = ½(FᵀF − 1),  S = λ tr(E) 1 + 2μ E,  ρ0Ψ = ½ E:ℂ:E,  P = F S.
/// In 2D the same formulas hold in plane strain (E_i3 = 0) with the 3D λ.
/// The free functions are the closed-form kernel's (fem/element.cpp); the
/// law object (material/svk_law.hpp) is SVK as a material::Law.
#include "core/types.hpp"

namespace conserve::material {

/// Lamé constants [Pa].
struct Lame {
  double lambda = 0.0;
  double mu = 0.0;

  /// From Young's modulus E [Pa] and Poisson's ratio ν (−1 < ν < 0.5).
  static Lame from_young_poisson(double young, double poisson) {
    return {young * poisson / ((1.0 + poisson) * (1.0 - 2.0 * poisson)), young / (2.0 * (1.0 + poisson))};
  }
};

/// Green–Lagrange strain E = ½(FᵀF − 1).
template <int D>
Mat<D> green_lagrange(const Mat<D>& F) {
  return 0.5 * (F.transpose().lazyProduct(F) - Mat<D>::Identity());
}

/// ℂ : A = λ tr(A) 1 + 2μ A — the second Piola–Kirchhoff stress of a strain
/// (S = ℂ:E) and also its variation (δS = ℂ:δE), since SVK is linear in E.
template <int D>
Mat<D> svk_stress(const Lame& lame, const Mat<D>& E) {
  Mat<D> S = (2.0 * lame.mu) * E;
  S.diagonal().array() += lame.lambda * E.trace();
  return S;
}

/// Stored energy per reference volume ρ0Ψ = ½ λ (tr E)² + μ E:E [J/m³].
template <int D>
double svk_energy_density(const Lame& lame, const Mat<D>& E) {
  const double tr = E.trace();
  return 0.5 * lame.lambda * tr * tr + lame.mu * E.squaredNorm();
}

}  // namespace conserve::material
