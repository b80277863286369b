#pragma once
/// Impacts located in time (docs/theory.md, "Impacts located in time"): the
/// largest gap a slave may be activated with, and where a step that would
/// activate one from further out is cut short. Keeps the contact events a
/// pair's windows are measured from.
#include <cstdint>
#include <vector>

#include "contact/collision_set.hpp"
#include "contact/constraint.hpp"

namespace conserve::contact {

/// Impacts located in time ([active_set] locate_impacts): a slave is
/// activated with a gap of at most a tolerance × its facet size, a step in
/// which one would arrive from further out being cut short where it
/// arrives. The first impact of a pair is located to `onset`; the impacts
/// that follow it (any slave of a pair in contact, or that had one
/// activated or released within `window`: contact that spreads, a patch
/// whose nodes rattle) are taken together, each held at the gap it has up
/// to `cluster`, so that they do not cut every step.
struct ImpactLocation {
  double onset = 0.0;    ///< fraction of the facet size; 0: impacts not located
  double cluster = 0.0;  ///< fraction of the facet size (≥ onset)
  double window = 0.0;   ///< [s]
};

template <int D>
class ImpactLocator {
 public:
  /// For `num_nodes` nodes and `num_pairs` pairs, impacts not located.
  ImpactLocator(int num_nodes, int num_pairs);

  /// onset = 0 turns location off (the paper's activation).
  void configure(const ImpactLocation& location);
  [[nodiscard]] bool located() const { return location_.onset > 0.0; }

  /// Starts a step at time t_n of length dt from velocities v_n with the
  /// constraints `active` (the pairs in contact): forgets the last step's
  /// releases and activations.
  void begin_step(double time, double dt, const Eigen::VectorXd& v_n, const std::vector<Constraint<D>>& active);
  /// A release of node s, an activation in pair p, within the step.
  void released(int s) { released_[static_cast<std::size_t>(s)] = 1; }
  void activated(int p) { activated_[static_cast<std::size_t>(p)] = 1; }
  /// Whether node s was released within the step.
  [[nodiscard]] bool released_in_step(int s) const { return released_[static_cast<std::size_t>(s)] != 0; }
  /// The step is taken, ending at time t_{n+1}: its releases and
  /// activations start their windows.
  void end_step(double time);

  /// The largest gap slave node s of pair p, whose facets' size is
  /// `facet_size`, is activated with [m] (+∞ when impacts are not located):
  /// `cluster` × facet_size when its pair is in contact or had an event
  /// within the window, else `onset` × facet_size.
  [[nodiscard]] double gap_tolerance(int p, int s, double facet_size) const;
  /// Where the step should end for constraint c, just made for its slave
  /// found behind facet `end` of `master` at the end of a solve from x_n,
  /// to arrive at half its tolerance `tolerance`; 1 if it starts within it.
  [[nodiscard]] double split_at(const Constraint<D>& c, const Match<D>& end, const ContactSurface& master,
                                const Positions<D>& x_n, double tolerance) const;

  /// Per node the time of its last release, and per pair of its last
  /// activation, in taken steps (−∞: none): what a method's saved state
  /// carries.
  [[nodiscard]] const std::vector<double>& release_times() const { return released_at_; }
  [[nodiscard]] const std::vector<double>& activation_times() const { return activated_at_; }
  void set_event_times(std::vector<double> releases, std::vector<double> activations);

 private:
  ImpactLocation location_;
  double time_ = 0.0;                 ///< t_n of the step under way
  double dt_ = 0.0;                   ///< its length (located impacts)
  Eigen::VectorXd v_n_;               ///< velocities at its start (located impacts)
  std::vector<double> released_at_;   ///< per node: its last release in a taken step [s]
  std::vector<double> activated_at_;  ///< per pair: its last activation in a taken step [s]
  std::vector<char> released_;        ///< per node: released during this step
  std::vector<char> activated_;       ///< per pair: a slave activated in this step
  std::vector<char> in_contact_;      ///< per pair: a constraint active at the step's start
};

}  // namespace conserve::contact
