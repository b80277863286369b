#pragma once
/// Contact pairs and active node-to-segment constraints.
#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "contact/broad_phase.hpp"
#include "contact/facet.hpp"
#include "contact/search.hpp"
#include "contact/surface.hpp"

namespace conserve::contact {

enum class Kind {
  frictionless,  ///< (47)–(65): zero relative normal mid-point velocity, free slip
  stick,         ///< (35)–(46): the slave moves with a frozen point of the master facet
};

/// A crease pair (two constraints of one pair on a slave, on two facets
/// that share a node and fold concave under it: ActiveSet::crease) is
/// formed, and its facets switched (Elimination::place_pair), only while
/// the sine of the angle between their normals is at least this: nearer
/// coplanar facets leave a slave behind the second by less than this
/// fraction of its distance past their common edge, and the Gram system
/// of the two normals, whose determinant is the sine squared, would
/// amplify round-off by more than 1e6.
inline constexpr double kCreaseSine = 1e-3;

/// A slave surface against a master surface.
template <int D>
struct ContactPair {
  ContactSurface slave;
  ContactSurface master;
  /// The kind its slaves are activated with: a Coulomb pair's slaves
  /// start sticking (frictionless if μ = 0) and slip when their force
  /// leaves the cone (ActiveSet).
  Kind kind = Kind::frictionless;
  /// Coulomb friction coefficient μ ≥ 0 of a `kind = "coulomb"` pair;
  /// none for frictionless and stick pairs.
  std::optional<double> friction;
  /// The scenario's [[contact]] this pair comes from; a two-pass contact
  /// gives two pairs, the second (`second_pass`) with slave and master
  /// swapped, after every first pass.
  int contact = -1;
  int passes = 1;
  bool second_pass = false;
  /// Self-contact: slave and master are one surface; a node is not held
  /// on the facets at it and its neighbours (near_nodes).
  bool self = false;
  /// Whether this pair's constraints may be left out where they repeat
  /// another's (two passes' second, self-contact).
  [[nodiscard]] bool yields() const { return second_pass || self; }
  /// A second pass whose slaves are a driven rigid body's nodes: they have
  /// no unknowns, so each constraint is held by a node of its master facet
  /// instead (Constraint::eliminated). `fixed`: the master surface's nodes
  /// with a prescribed dof, sorted, which never hold one.
  [[nodiscard]] bool slave_driven() const { return second_pass && slave.rigid; }
  std::vector<int> fixed;
  SearchSettings search;
  FacetTree<D> tree;              ///< over master facets, refitted (refit) before each search
  mutable FacetFrames<D> frames;  ///< of master facets at the tree's positions, filled as searched

  /// Moves the search to positions x: the tree is refitted and the facets'
  /// frames, which belong to the old positions, are dropped. The only way
  /// the search's positions change, so the two cannot disagree.
  void refit(const Positions<D>& x) {
    tree.refit(x);
    frames.reset(master.num_facets());
  }
};

/// One active constraint: slave node s tied to a master facet. The
/// constraint holds the slave's gap γ at the end of every step (so that it
/// never ends behind its master) with a contact force that does no work
/// (contact/elimination/zero_work.hpp).
template <int D>
struct Constraint {
  int pair = -1;
  int slave = -1;  ///< global node
  /// The node whose unknowns hold the constraint: −1, the slave's; for a
  /// slave without unknowns (ContactPair::slave_driven), the node of its
  /// facet with the largest weight among those free to hold it, whose
  /// normal motion it eliminates (Elimination::make_groups; derived from
  /// the geometry at each build, not kept in checkpoints).
  int eliminated = -1;
  Kind kind = Kind::stick;
  /// The master facet (a column of the master surface's facets): stick:
  /// the facet the slave is frozen to; frictionless: the facet the slave's
  /// end position projects on, where its gap is held and its force acts.
  int facet = -1;
  FacetIndex<D> master;                        ///< global nodes of `facet` (D, or NF of a quadratic one)
  Xi<D> xi = Xi<D>::Zero();                    ///< stick: frozen ξ̄; frictionless: ξ_{n+½}
  Vec<D> normal = Vec<D>::Zero();              ///< n_{n+½}, outward normal of `facet` at the mid-point
  Tangents<D> tangents = Tangents<D>::Zero();  ///< τ_{n+½}
  /// γ: the gap held, the slave's gap at the start of the step it was
  /// activated in [m], or 0 if it started behind and could be pushed out
  /// at zero work (ActiveSet::make_constraint); negative for a slave held
  /// behind, or pushed out part of the way in this step (push). Stick: the
  /// height of the slave above ξ̄.
  double gap = 0.0;
  /// Frictionless, for the rest of the step: the paper's rate condition
  /// (48), n_{n+½}·(Δx_s − N_{n+½} Δx_m) = 0, instead of the held gap γ,
  /// because the zero-work direction of the held gap turned away from the
  /// normal (Elimination::enforce, kRateCosine). Under (48) a·Δx = 0, so
  /// the force is the paper's normal one. When the step is taken, γ
  /// becomes the slave's end gap and the flag is cleared; an end gap
  /// behind the facet makes it a push-out instead, and the step is solved
  /// again (ActiveSet::update).
  bool rate = false;
  /// Frictionless, for one step: the slave starts it behind its facet
  /// (activated there further than the step's other non-rigid motion can
  /// carry it out at zero work, ActiveSet::push_out; held behind as a
  /// slave's second constraint, ActiveSet::begin_step; or about to be left
  /// there by (48), ActiveSet::update), and is pushed out towards γ = 0 by
  /// the paper's normal force a (no zero-work correction), by at most
  /// kPushOutStep of its facet size in a step (ActiveSet::push_target;
  /// a deeper slave goes on in the next steps). That force does
  /// work, which the velocity update after the step takes back out of the
  /// bodies' deformation (PersistentVelocity::restore_energy), so E, L and
  /// J are kept. Cleared when the next step begins (ActiveSet::begin_step);
  /// given up, for good, if the work cannot be taken back (hold).
  bool push = false;
  /// Frictionless: never pushed out, held at γ (< 0 when behind) for as
  /// long as it stays active, as the paper's scheme holds every slave. Set
  /// when a push-out's work was more than the bodies' deformation velocity
  /// could give back (ActiveSet::hold_pushes): a slave that came in beyond
  /// the master surface's border, through a face that is no master, can be
  /// any depth behind it, and no step is short enough to push it out.
  bool hold = false;
  /// Two passes: left out of the maps for the rest of the solve because
  /// it repeats another constraint (Elimination::suspend_repeats), so that
  /// Newton's iterates do not take it in and out; the active set drops it
  /// once the solve ends (ActiveSet::update). Not kept in checkpoints.
  bool repeat = false;
  /// Coulomb friction (docs/theory.md, "Coulomb friction"): μ while the
  /// slave slips (a frictionless constraint of a Coulomb pair: its force
  /// has a friction part μ f_N against its slip,
  /// zero_work::friction_direction), 0 otherwise; and the slip ε below which
  /// its direction is regularized and the slave sticks instead [m].
  double friction = 0.0;
  double slip_scale = 0.0;
  /// The step the slave was activated in (its first step in contact).
  std::int64_t activated_step = 0;
  /// f_N = g_s·n_{n+½} at the last update of the active set [N], and at
  /// the end of the previous step (set by ActiveSet::begin_step).
  double normal_force = 0.0;
  double start_force = 0.0;
  /// Output only (not in checkpoints), set with normal_force: the whole
  /// force on the slave over the step, g_s (f_N n for each of a slave's
  /// two constraints) [N], and the slave's mid-point position x_{n+½} [m].
  Vec<D> force = Vec<D>::Zero();
  Vec<D> mid = Vec<D>::Zero();
};

}  // namespace conserve::contact
