#pragma once
/// The statistics of the held methods (elimination and the multipliers)
/// beyond every method's (StepContactStats): what their active set, its
/// push-outs and the persistent velocity update count in a step, declared
/// once in held_statistics(): a history.csv column each, run values in
/// summary.json.
#include <vector>

#include "contact/elimination/persistent_velocity.hpp"
#include "contact/method.hpp"

namespace conserve::contact {

struct HeldCounts {
  int held = 0;  ///< released slaves re-activated (and kept) in the step
  /// Releases of slaves activated within the last kChatterWindow steps.
  int chatter = 0;
  /// Releases of slaves whose force at the end of the previous step was
  /// above kLoadedFraction of the mean force of the active slaves then.
  int loaded_releases = 0;
  /// Frictionless constraints that held the paper's rate condition (48).
  int rate_steps = 0;
  /// Slaves pushed out from behind their facet by the paper's force, and
  /// the work of that force [J] (taken back from the deformation velocity).
  int pushes = 0;
  double push_work = 0.0;
  /// Push-outs given up in the step (those slaves are held instead).
  int pushes_given_up = 0;
  /// Second constraints given to slaves pressed into a crease.
  int creases = 0;
  /// Constraints not activated, or released, because they repeat another
  /// (two passes: slaves on each other's nodes, repeats()).
  int repeats = 0;
  double max_activation_gap = 0.0;  ///< largest held gap γ of a slave activated in the step [m]
  VelocityUpdate velocity;          ///< the persistent-contact velocity update after the step
};

/// The held methods' own statistics, in history.csv's column order.
const std::vector<MethodStatistic>& held_statistics();
/// Their values for a step's counts, in held_statistics()' order.
std::vector<double> held_values(const HeldCounts& counts);

}  // namespace conserve::contact
