#pragma once
/// Which quantities a scenario conserves, and how far a run drifted from
/// them. A drift is the quantity's largest deviation from its initial
/// value so far divided by the run's own scale so far (one definition for
/// history.csv, summary.json and the end-of-run line; at the run's end,
/// its largest deviation over its own scale):
///   E: `total` + Σ released (docs/user-guide.md, "history.csv"), scale
///      E_ref = the largest K + W (+ a penalty's springs) [J];
///   L_i: scale L_ref = the largest Σ_A |(MV)_A| [kg m/s];
///   J_i: scale J_ref = L_ref × the model's size (its bounding-box
///      diagonal) [kg m²/s].
/// A quantity the scenario does not conserve (gravity, supports, surface
/// loads, stick contact, the mid-point stress) has no drift: it is named
/// with why. A zero deviation is a zero drift, whatever the scale.
#include <array>
#include <string>
#include <string_view>

#include "io/scenario.hpp"
#include "time/diagnostics.hpp"

namespace conserve::simulation {

/// E, L_x, L_y, L_z, J_x, J_y, J_z, in this order.
inline constexpr int kQuantities = 7;
inline constexpr std::array<std::string_view, kQuantities> kQuantityNames = {"E",   "L_x", "L_y", "L_z",
                                                                             "J_x", "J_y", "J_z"};

/// What the scenario conserves.
struct Conservation {
  /// Per quantity: exists in the dimension (2D: not L_z, J_x, J_y).
  std::array<bool, kQuantities> present{};
  /// Per quantity: why it is not conserved ("gravity, supports"); empty:
  /// conserved.
  std::array<std::string, kQuantities> why_not;
  [[nodiscard]] bool conserved(int q) const { return present[q] && why_not[q].empty(); }
};

/// From the scenario's dimension, loads, supports, rigid bodies, contact
/// kinds and stress scheme.
Conservation conservation(const io::Scenario& scenario);

/// The running deviations and scales (a checkpoint carries them, so that
/// a restart continues them).
struct DriftState {
  std::array<double, kQuantities> deviation{};  ///< largest |q − q0| so far
  double energy_reference = 0.0;                ///< E_ref [J]
  double momentum_reference = 0.0;              ///< L_ref [kg m/s]
};

/// A row's drifts: E, and the largest of the conserved components of L and
/// of J (NaN when none is conserved).
struct Drifts {
  double energy = 0.0;
  double linear = 0.0;
  double angular = 0.0;
};

class DriftTracker {
 public:
  /// `size`: the model's size [m]; `d0`: the initial state's quantities.
  DriftTracker(double size, const time::Diagnostics& d0, Conservation conservation)
      : size_(size), d0_(d0), conservation_(std::move(conservation)) {}

  /// Adds the state `d` to the running deviations and scales in `state`;
  /// returns the drifts so far.
  Drifts add(const time::Diagnostics& d, DriftState& state) const;
  /// Quantity q's drift so far (NaN if not conserved).
  [[nodiscard]] double drift(int q, const DriftState& state) const;
  /// The scale of quantity q [J, kg m/s or kg m²/s].
  [[nodiscard]] double reference(int q, const DriftState& state) const;
  [[nodiscard]] const Conservation& conservation() const { return conservation_; }

 private:
  double size_;
  time::Diagnostics d0_;
  Conservation conservation_;
};

}  // namespace conserve::simulation
