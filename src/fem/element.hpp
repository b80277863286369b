#pragma once
/// Element kernels of the energy–momentum conserving mid-point step
/// (paper (18)–(26); Simo & Tarnow 1992; docs/theory.md, "The conserving
/// step (18)–(26)").
///
/// For a step from positions x_n to x_{n+1} of one cell:
///   F_{n+½} = ½(F_n + F_{n+1})
///   conserving, SVK: S = ½(S(E_n) + S(E_{n+1}))   (Simo–Tarnow, exact energy)
///   conserving, any other law: S = Gonzalez's discrete gradient
///                              (fem/discrete_gradient.hpp, exact energy)
///   midpoint:   S = S(C(F_{n+½}))            (negative control)
///   f_A = V F_{n+½} S ∇N_A
/// A quadratic cell (fem/quadratic.hpp) sums the same terms over its
/// points: f_A = Σ_q w_q det J_q F_{n+½} S ∇N_A, each point with its own
/// F_n, S and exact energy. The tangent ∂f/∂x_{n+1} is not symmetric. SVK (material::Law::svk) has
/// a closed-form kernel; other laws go through S and ℂ of the law.
#include "fem/quadratic.hpp"
#include "fem/simplex.hpp"
#include "material/law.hpp"

namespace conserve::fem {

/// Which algorithmic stress a step uses.
enum class StressScheme { conserving, midpoint };

/// Positions of one cell at the start and end of a step.
template <int D>
struct StepPositions {
  NodeMatrix<D> x_n;
  NodeMatrix<D> x_np1;
};

/// What the kernels use of a cell's start of step x_n: F_n (E_n = E(F_n)
/// is recomputed where needed: kept per cell it would double a large
/// model's two step starts). Every iterate of a step shares it.
template <int D>
struct CellStart {
  Mat<D> F;
};

template <int D>
CellStart<D> cell_start(const SimplexGeometry<D>& g, const NodeMatrix<D>& x_n);

/// Internal force f (column A = f_A) [N] of the paper's residual (20), with
/// the conserving stress of docs/theory.md, "The conserving step (18)–(26)".
template <int D>
NodeMatrix<D> internal_force(const SimplexGeometry<D>& g, const material::Law& law, const StepPositions<D>& x,
                             StressScheme scheme);
/// The same from the cell's start (cell_start(g, x_n)) and x_{n+1}: the
/// same bits.
template <int D>
NodeMatrix<D> internal_force(const SimplexGeometry<D>& g, const material::Law& law, const CellStart<D>& start,
                             const NodeMatrix<D>& x_np1, StressScheme scheme);

/// Internal force and its tangent K = ∂f/∂x_{n+1}, dof order (A, i) → A·D+i.
template <int D>
void internal_force_tangent(const SimplexGeometry<D>& g, const material::Law& law, const StepPositions<D>& x,
                            StressScheme scheme, NodeMatrix<D>& f, ElementMatrix<D>& K);
template <int D>
void internal_force_tangent(const SimplexGeometry<D>& g, const material::Law& law, const CellStart<D>& start,
                            const NodeMatrix<D>& x_np1, StressScheme scheme, NodeMatrix<D>& f, ElementMatrix<D>& K);

/// Stored energy W = V ρ0Ψ(E(F)) of the cell at positions x [J].
template <int D>
double strain_energy(const SimplexGeometry<D>& g, const material::Law& law, const NodeMatrix<D>& x);

/// Cauchy stress σ = J⁻¹ F S Fᵀ at positions x, embedded in 3×3 (plane
/// strain: σ_zz = J⁻¹ S_zz, λ tr E / J for SVK) [Pa].
template <int D>
Mat3 cauchy_stress(const SimplexGeometry<D>& g, const material::Law& law, const NodeMatrix<D>& x);

/// Quadratic cells: `start` holds the cell's Quadratic<D>::kPoints point
/// starts (one CellStart per point, in the rule's order).
template <int D>
void cell_start(const QuadraticGeometry<D>& g, const QuadraticNodes<D>& x_n, CellStart<D>* start);
template <int D>
QuadraticNodes<D> internal_force(const QuadraticGeometry<D>& g, const material::Law& law, const CellStart<D>* start,
                                 const QuadraticNodes<D>& x_np1, StressScheme scheme);
template <int D>
void internal_force_tangent(const QuadraticGeometry<D>& g, const material::Law& law, const CellStart<D>* start,
                            const QuadraticNodes<D>& x_np1, StressScheme scheme, QuadraticNodes<D>& f,
                            QuadraticMatrix<D>& K);
/// W = Σ_q w_q det J_q ρ0Ψ(E(F_q)) [J], by the force's rule.
template <int D>
double strain_energy(const QuadraticGeometry<D>& g, const material::Law& law, const QuadraticNodes<D>& x);
/// The cell's mean Cauchy stress (volume-weighted over its points) [Pa].
template <int D>
Mat3 cauchy_stress(const QuadraticGeometry<D>& g, const material::Law& law, const QuadraticNodes<D>& x);
/// The smallest det F over the cell's points.
template <int D>
double min_det_F(const QuadraticGeometry<D>& g, const QuadraticNodes<D>& x);

/// Quadratic cells with the cell's mean dilatation (fem/mean_dilatation.hpp,
/// the near-incompressibility option): W = Σ_q w_q ρ0Ψ(C̄_q), f_A = Σ_q w_q
/// F_{n+½,q} S_q ∇N_A(ξ_q) with the joint discrete gradient S_q (conserving:
/// exact energy; S symmetric: L and J) or S_q(C(F_{n+½})) (midpoint), and
/// its tangent, which couples the cell's points through J̄.
template <int D>
QuadraticNodes<D> internal_force_mean_dilatation(const QuadraticGeometry<D>& g, const material::Law& law,
                                                 const CellStart<D>* start, const QuadraticNodes<D>& x_np1,
                                                 StressScheme scheme);
template <int D>
void internal_force_tangent_mean_dilatation(const QuadraticGeometry<D>& g, const material::Law& law,
                                            const CellStart<D>* start, const QuadraticNodes<D>& x_np1,
                                            StressScheme scheme, QuadraticNodes<D>& f, QuadraticMatrix<D>& K);
template <int D>
double strain_energy_mean_dilatation(const QuadraticGeometry<D>& g, const material::Law& law,
                                     const QuadraticNodes<D>& x);
/// The volume-weighted mean of J⁻¹ F S_q Fᵀ (S_q of fem/mean_dilatation.hpp) [Pa].
template <int D>
Mat3 cauchy_stress_mean_dilatation(const QuadraticGeometry<D>& g, const material::Law& law,
                                   const QuadraticNodes<D>& x);

}  // namespace conserve::fem
