#pragma once
/// Discrete energies and momenta of a state (paper (23)–(24)).
#include <vector>

#include "assembly/assembler.hpp"
#include "model/state.hpp"

namespace conserve::time {

struct Diagnostics {
  double kinetic = 0.0;         ///< K = ½ V·MV [J]
  double strain = 0.0;          ///< W = Σ ∫ ρ0Ψ [J]
  double potential = 0.0;       ///< Π_ext = −f_ext·u of the constant loads (gravity, tractions) [J]
  double contact = 0.0;         ///< stored by the contact method (a penalty's springs) [J]; set by the caller
  double load_work = 0.0;       ///< work of the loads without a potential so far (State::load_work) [J]
  double support_work = 0.0;    ///< work of the prescribed motions so far (Σ State::support_work) [J]
  double released = 0.0;        ///< energy contact let go of so far (State::released) [J]
  double dissipated = 0.0;      ///< energy friction dissipated so far (State::dissipated) [J]
  /// K + W + Π_ext − load_work − support_work (+ contact, once the caller
  /// sets it) [J]: what the scheme conserves.
  double total = 0.0;
  Vec3 linear = Vec3::Zero();   ///< L = Σ_A (MV)_A [kg m/s] (z = 0 in 2D)
  Vec3 angular = Vec3::Zero();  ///< J = Σ_A x_A × (MV)_A about the origin [kg m²/s] (2D: z only)
  std::vector<Vec3> body_linear;  ///< L of each body [kg m/s]
  double momentum_magnitude = 0.0;  ///< Σ_A |(MV)_A| [kg m/s]: the scale L and J are sums at
  double min_det_F = 0.0;           ///< smallest det F over the cells (1 if none)
  int min_det_F_cell = -1;          ///< its global cell, −1 if there are no cells
};

template <int D>
Diagnostics diagnostics(const assembly::Assembler<D>& assembler, const model::State& state);

}  // namespace conserve::time
