#pragma once
/// The constraint a slave found behind a master facet is activated with
/// (docs/theory.md, "The step with contact"), the crease rule that gives a
/// slave a second facet of the same surface, and the push-out of a slave
/// that starts its first step in contact behind its facet.
#include <algorithm>
#include <cstdint>
#include <optional>

#include "contact/constraint.hpp"

namespace conserve::contact {

/// The push-out a frictionless slave found behind its facet may be given
/// in its first step at zero work, relative to the other non-rigid motion
/// of its constraint's nodes (push_out).
inline constexpr double kPushOut = 1.0;

/// The most a push-out by the paper's force (Constraint::push) moves its
/// slave out in one step, as a fraction of the slave's facet size
/// (push_target): a slave found deeper behind is pushed out over several
/// steps. The work of a push-out grows as its depth squared, and the
/// bodies' deformation velocity has to give it back within the step
/// (PersistentVelocity::restore_energy); pushed out whole, a slave a fifth
/// of its facet behind inverted a cell (docs/theory.md, "Limits").
inline constexpr double kPushOutStep = 0.1;

/// What the activation of a slave needs to know of the set it joins.
struct ActivationContext {
  std::int64_t step = 0;     ///< the step under way (Constraint::activated_step)
  bool first = true;         ///< the slave holds no other constraint
  bool given_up = false;     ///< a push-out of it was given up (it is held where it starts)
  double facet_size = 0.0;   ///< its slave facets' longest edge [m] (push_target)
  /// The kind it is activated with if not its pair's (a Coulomb pair's
  /// slave that slips from the start, ActiveSet).
  std::optional<Kind> kind;
};

/// The constraint slave node s of pair `pr` (index p) takes for the facet
/// `end` it was found behind at the end of a solve from x_n to x_np1: it
/// holds what the slave had at the START of the step on that facet, so
/// that it does no work: stick, its frozen ξ̄ and height γ; frictionless,
/// its start gap γ (ξ, n, τ at the mid-point). A frictionless slave that
/// starts behind is held at γ = 0 if within the search's penetration
/// tolerance or if the step's other non-rigid motion can carry it out at
/// zero work (push_out); otherwise it is pushed out by the paper's force a
/// step's share at a time (Constraint::push, push_target) if it is the
/// slave's first constraint, or held where it started (Constraint::hold)
/// if a push-out of it was given up; a second constraint keeps its start gap.
template <int D>
Constraint<D> make_constraint(const ContactPair<D>& pr, int p, int s, const Match<D>& end, const Positions<D>& x_n,
                              const Positions<D>& x_np1, const ActivationContext& context);

/// Whether slave s, which holds `held` (one frictionless constraint of
/// pair `pr`, neither pushed out nor under (48)), and is found behind
/// another facet `end` of the same master surface, is pressed into a
/// crease: the two facets share a node and their normals are on the same
/// side and not within kCreaseSine of parallel. The master folds concave
/// under the slave, no single facet keeps it in front of both, and it
/// holds both (docs/theory.md, "Two constraints on one slave").
template <int D>
bool forms_crease(const ContactPair<D>& pr, const Constraint<D>& held, const Match<D>& end);

/// Two passes (and self-contact) hold each side's nodes on the other's
/// facets. Where a slave sits on a node m of its facet and m is held on a
/// facet at that slave, the two constraints say one thing (the two nodes
/// keep together) and eliminating both is singular: their normal motions
/// couple by 1 − w_a w_b (n_a·n_b)², w_a the weight of a's slave at b's
/// and n_a a's facet normal. Below this the two repeat each other (the
/// slaves are within about half of it of a facet of each other's node).
inline constexpr double kRepeatPivot = 1e-2;

/// Whether constraints a and b repeat each other (kRepeatPivot) at
/// positions x: each slave's weight at the other is that of its
/// projection on its facet there.
template <int D>
bool repeats(const Constraint<D>& a, const Constraint<D>& b, const Positions<D>& x);

/// Of two constraints that repeat each other, whether k is the one left
/// out: its pair yields (ContactPair::yields) and the other's does not,
/// or both do and k's slave is the larger node number.
template <int D>
[[nodiscard]] bool gives_way(const Constraint<D>& k, const Constraint<D>& other, const std::vector<ContactPair<D>>& pairs) {
  const bool mine = pairs[static_cast<std::size_t>(k.pair)].yields();
  const bool theirs = pairs[static_cast<std::size_t>(other.pair)].yields();
  return mine && (!theirs || other.slave < k.slave);
}

/// How far frictionless constraint c's slave may be moved out towards its
/// facet in a step from positions x_a to x_b (read at the constraint's
/// nodes) at zero work with a force close to the normal: kPushOut |w|, w
/// the non-rigid part of the nodes' motion without the slave's normal
/// motion relative to the facet (make_constraint).
template <int D>
double push_out(const Constraint<D>& c, const Positions<D>& x_a, const Positions<D>& x_b);

/// The gap γ a push-out by the paper's force holds a slave at, from
/// `start_gap` < 0 behind its facet: out by at most kPushOutStep of the
/// slave's facet size `facet_size`, up to γ = 0.
[[nodiscard]] inline double push_target(double start_gap, double facet_size) {
  return std::min(0.0, start_gap + kPushOutStep * facet_size);
}

}  // namespace conserve::contact
