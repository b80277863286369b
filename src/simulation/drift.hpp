#pragma once
/// Relative drifts of the conserved quantities, against reference scales
/// that are never zero while anything moves (issue 11: a body dropped from
/// rest has E0 = L0 = J0 = 0, so the initial values are no scale):
///   E_ref = the largest K + W seen so far [J],
///   L_ref = the largest Σ_A |(MV)_A| seen so far [kg m/s],
///   J_ref = L_ref × the model's size (its bounding-box diagonal) [kg m²/s].
/// drift_E = |E − E0| / E_ref, and likewise for L and J (norms; per
/// component in the summary). A zero change is a zero drift, whatever the
/// scale.
#include "simulation/checkpoint.hpp"
#include "time/diagnostics.hpp"

namespace conserve::simulation {

/// This step's relative drifts.
struct Drifts {
  double energy = 0.0;
  double linear = 0.0;   ///< |L − L0| / L_ref
  double angular = 0.0;  ///< |J − J0| / J_ref
};

class DriftTracker {
 public:
  /// `size`: the model's size [m]; `d0`: the initial state's quantities.
  DriftTracker(double size, const time::Diagnostics& d0) : size_(size), d0_(d0) {}

  /// Updates the references and the running maxima in `totals` (which a
  /// checkpoint carries, so that a restart continues them) with the state
  /// `d`; returns this step's drifts.
  Drifts add(const time::Diagnostics& d, RunTotals& totals) const;

 private:
  double size_;
  time::Diagnostics d0_;
};

}  // namespace conserve::simulation
