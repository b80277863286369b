#pragma once
/// The active set (docs/theory.md, "The step with contact"): after each
/// converged solve of a step, release the constraints whose slave pulls on
/// its master (f_N = g_s·n < 0, (46)/(65)) and activate every slave found
/// behind a master facet (g_N,n+1 < 0), including slaves released earlier in
/// the step: a slave
/// released and then found behind its master is re-activated and held
/// until the step ends (its force may then be tensile for that step), so
/// that no slave ends a converged step behind its master. A slave is
/// activated holding the gap it had at the start of the step (≥ 0), see
/// contact/elimination/elimination.hpp. The caller solves the step again while the set
/// changes. With impacts located (locate_impacts), a slave that would
/// start further out than its tolerance is not activated: the step is
/// split at its crossing instead (update() returns SetChange::split).
#include <limits>
#include <optional>
#include <vector>

#include "contact/collision_set.hpp"
#include "contact/constraint.hpp"
#include "contact/elimination/elimination.hpp"
#include "contact/method.hpp"
#include "contact/elimination/persistent_velocity.hpp"
#include "model/model.hpp"

namespace conserve::contact {

/// Two constraints of different pairs on one slave node whose facet
/// normals are closer to parallel than this (|n₁·n₂|) are not held
/// together: the second is not activated (the two gaps would fix the
/// slave's motion badly).
inline constexpr double kParallelCosine = 0.9;

/// The push-out a frictionless slave found behind its facet may be given
/// in its first step, relative to the other non-rigid motion of its
/// constraint's nodes (ActiveSet::push_out).
inline constexpr double kPushOut = 1.0;

/// The most a push-out by the paper's force (Constraint::push) moves its
/// slave out in one step, as a fraction of the slave's facet size
/// (ActiveSet::push_target): a slave found deeper behind is pushed out
/// over several steps. The work of a push-out grows as its depth squared,
/// and the bodies' deformation velocity has to give it back within the
/// step (PersistentVelocity::restore_energy); pushed out whole, a slave a
/// fifth of its facet behind inverted a cell (docs/theory.md, "Limits").
inline constexpr double kPushOutStep = 0.1;

/// A release counts as chatter if the slave was activated less than this
/// many steps before (history.csv `chatter`).
inline constexpr int kChatterWindow = 10;
/// A release counts as loaded if the slave's force at the end of the
/// previous step was above this fraction of the mean force then.
inline constexpr double kLoadedFraction = 0.01;

/// Releases located in time (ActiveSet::release_step): where a pressing
/// slave's force, falling at its rate over the last two steps, would turn
/// tensile within this many full steps, the next step is shortened ...
inline constexpr double kReleaseHorizon = 4.0;
/// ... to this fraction of the longest step whose mean force would stay
/// ≥ 0, so that the steps shrink geometrically towards the lift-off, ...
inline constexpr double kReleaseApproach = 0.25;
/// ... but not below the step over which the force falls by this fraction
/// of the loaded threshold (kLoadedFraction of the mean force), nor below
/// 1/kReleaseShortest of the scenario's step, and to at most twice the
/// last step.
inline constexpr double kReleaseUnloading = 0.5;
inline constexpr double kReleaseShortest = 256.0;

/// What ActiveSet::update did to the set.
enum class SetChange {
  none,     ///< settled: the solve is the step's
  changed,  ///< slaves were activated or released: solve the step again
  split,    ///< an impact within the step: end the step earlier (StepContactStats::split_fraction)
};

/// Signed gaps of the active slaves at some positions [m]: NaN if none.
struct ActiveGaps {
  double min = 0.0;
  double max = 0.0;
};

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
class ActiveSet {
 public:
  ActiveSet(const model::Model<D>& model, std::vector<ContactPair<D>> pairs);

  [[nodiscard]] bool empty() const { return collisions_.empty(); }
  [[nodiscard]] const std::vector<Constraint<D>>& constraints() const { return active_; }
  [[nodiscard]] const std::vector<ContactPair<D>>& pairs() const { return collisions_.pairs(); }
  /// The search this set activates from (contact/collision_set.hpp).
  [[nodiscard]] CollisionSet<D>& collisions() { return collisions_; }
  /// Normal force f_N = g_s·n_{n+½} of each constraint after the last update [N].
  [[nodiscard]] const std::vector<double>& normal_forces() const { return normal_forces_; }

  /// Starts step `step` (the index it will have once taken) of length dt
  /// from velocities v_n: forgets which slaves were released or held in
  /// the previous one and keeps each constraint's force at its end
  /// (Constraint::start_force); dt and v_n serve the crossing estimate of
  /// located impacts.
  /// Step `step` of length dt from time t_n with velocities v_n.
  void begin_step(std::int64_t step, double time, double dt, const Eigen::VectorXd& v_n);
  /// The step is taken, ending at time t_{n+1}: its releases and
  /// activations start their windows (ImpactLocation).
  void end_step(double time);

  /// The direct elimination of the active constraints for one solve of the
  /// step u_n → u (u is not modified: call enforce()). It works on this
  /// set's constraints, not on a copy: the facets, ξ, n and τ that its
  /// updates move are the set's. The set must outlive it and must not be
  /// updated while it is in use. `reduction` as in Elimination.
  [[nodiscard]] Elimination<D> elimination(const Eigen::VectorXd& u_n, const Eigen::VectorXd& u,
                                           std::shared_ptr<TangentReduction<D>> reduction = nullptr);

  /// After a converged solve of u_n → u_{n+1} with full residual g: updates
  /// the set (then solve the step again if it changed). Sets the stats'
  /// end-of-step geometry (slave_penetration, active gaps) at u_{n+1} for
  /// the set after its releases, from the same search as the activations:
  /// when the set did not change, that is the step's end. With impacts
  /// located, a slave found behind its master that started the step
  /// further than its gap tolerance in front of it is not activated:
  /// the result is `split`, and stats.split_fraction is where the step
  /// should end for the earliest such slave to arrive at half its
  /// tolerance, by the straight path of this solve (the set is then
  /// left as the caller must restore it: the step is taken again).
  SetChange update(const Eigen::VectorXd& u_n, const Eigen::VectorXd& u_np1, const Eigen::VectorXd& g,
                   StepContactStats& stats);

  /// Gives up the step's push-outs (Constraint::push) after a solve whose
  /// push-out work the bodies cannot give back: each such slave is held
  /// from now on where it started the step (u_n), at zero work
  /// (Constraint::hold); solve the step again.
  void hold_pushes(const Eigen::VectorXd& u_n);

  /// With impacts located: where the step u_n → u should end for the
  /// earliest slave found behind its master at u that started the step
  /// further out than its tolerance to arrive at half of it (as update()
  /// would say), 1 if none; the set is not changed.
  [[nodiscard]] double split_fraction(const Eigen::VectorXd& u_n, const Eigen::VectorXd& u);

  /// Impacts located in time (ImpactLocation): a step that would activate
  /// a slave further out than its tolerance is split (update());
  /// onset = 0 turns it off (the paper's activation).
  void locate_impacts(const ImpactLocation& location);
  /// Per node the time of its last release, and per pair of its last
  /// activation, in taken steps (−∞: none): the windows of ImpactLocation,
  /// which the method's saved state carries.
  [[nodiscard]] const std::vector<double>& release_times() const { return released_at_; }
  [[nodiscard]] const std::vector<double>& activation_times() const { return activated_at_; }
  void set_event_times(std::vector<double> releases, std::vector<double> activations);
  /// Whether update() may ask for a split (the stepper forbids it once a
  /// step has been split too often or would become too short).
  void allow_splits(bool allow) { allow_splits_ = allow; }
  /// Releases located in time ([active_set] locate_releases): after step
  /// `step`, of length `last`, which followed one of length `previous`, the
  /// longest next step (at most `full`, the scenario's) for which no
  /// active slave that pressed with more than kLoadedFraction of the mean
  /// force is expected to let go more than about kReleaseUnloading of
  /// that threshold late. Its force's rate of fall is taken from its force
  /// at the ends of the two steps (Constraint::start_force, normal_force);
  /// slaves activated in step `step` have none and are left out.
  [[nodiscard]] double release_step(std::int64_t step, double full, double last, double previous) const;
  /// The largest gap slave node `slave` of pair `pair` is activated with
  /// when impacts are located [m] (+∞ when they are not).
  [[nodiscard]] double gap_tolerance(int pair, int slave) const;
  /// The longest edge of the slave facets at slave node `slave` of pair
  /// `pair` in the reference configuration [m]: the mesh size that the
  /// gap tolerance and a push-out's step (push_target) are fractions of.
  [[nodiscard]] double facet_size(int pair, int slave) const;

  /// Replaces the active set (restoring a checkpoint or a failed step's
  /// start); the per-node flags follow, the normal forces are the constraints'
  /// own (Constraint::normal_force) until
  /// the next update.
  void set_constraints(std::vector<Constraint<D>> constraints);

  /// The deepest slave node behind a master facet at displacements u,
  /// active or not, by the activation search's rules (far side, slave
  /// normal, surface border; given the step's start displacements u_n,
  /// also a facet beyond the border entered through in the step, as the
  /// step's own search and its reported StepContactStats do); depth 0 and
  /// node −1 if none.
  [[nodiscard]] Penetration slave_penetration(const Eigen::VectorXd& u, const Eigen::VectorXd* u_n = nullptr);
  /// The other way: the deepest master surface node behind a facet of its
  /// pair's slave surface at displacements u (the step from u_n), by the
  /// same rules, prescribed nodes included. Node-to-segment contact holds
  /// slaves only: a master finer than its slave may sink its nodes into
  /// the slave's facets, and this measures how far.
  [[nodiscard]] Penetration master_penetration(const Eigen::VectorXd& u, const Eigen::VectorXd& u_n);
  /// The smallest and largest gap of the active slaves at displacements u,
  /// each measured on the master surface as slave_penetration does (on its
  /// constraint's facet if that search finds none).
  [[nodiscard]] ActiveGaps active_gaps(const Eigen::VectorXd& u, const Eigen::VectorXd* u_n = nullptr);

 private:
  bool release_tensile(const Positions<D>& x_mid, const Eigen::VectorXd& g, StepContactStats& stats);
  SetChange activate_penetrating(const Positions<D>& x_n, const Positions<D>& x_np1, StepContactStats& stats);
  /// The constraint that makes slave s of pair p hold what it had at the
  /// start of the step; `end` is the facet it was found behind at the end.
  /// Where the step should end for slave `c` (just made, with its end
  /// match `end`) to arrive at half its tolerance; 1 if it starts within it.
  [[nodiscard]] double split_at(const Constraint<D>& c, const Match<D>& end, const Positions<D>& x_n) const;
  [[nodiscard]] Constraint<D> make_constraint(int p, int s, const Match<D>& end, const Positions<D>& x_n,
                                              const Positions<D>& x_np1) const;
  [[nodiscard]] Positions<D> positions(const Eigen::VectorXd& u) const;
  /// How far frictionless constraint c's slave may be moved out towards
  /// its facet in a step from positions x_a to x_b (read at the
  /// constraint's nodes) at zero work with a force close to the normal:
  /// kPushOut |w|, w the non-rigid part of the nodes' motion without the
  /// slave's normal motion relative to the facet (make_constraint).
  [[nodiscard]] double push_out(const Constraint<D>& c, const Positions<D>& x_a, const Positions<D>& x_b) const;
  /// The gap γ a push-out by the paper's force (Constraint::push) holds
  /// frictionless constraint c's slave at, from `start_gap` < 0 behind its
  /// facet: out by at most kPushOutStep of the slave's facet size, up to
  /// γ = 0. Deeper slaves stay behind and are pushed on in the next step
  /// (begin_step).
  [[nodiscard]] double push_target(const Constraint<D>& c, double start_gap) const;

  /// Whether slave node s may take a constraint of pair p whose facet has
  /// normal `normal`: when it holds none, or holds one frictionless
  /// constraint of another pair whose normal is not near-parallel
  /// (|n·n′| < kParallelCosine) and p is frictionless too; then it holds
  /// both (a node on two slave surfaces, contact/elimination/elimination.hpp).
  [[nodiscard]] bool can_hold(int p, int s, const Vec<D>& normal) const;
  /// The constraint slave `pair.slave.nodes[i]` (node s) of pair p takes
  /// for its match at the end of a solve (positions x_np1, the step from
  /// x_n), if any: a slave found behind a facet further than the
  /// penetration tolerance is activated if it holds no constraint of p
  /// (and can_hold() allows it), or given a crease pair (crease()).
  [[nodiscard]] std::optional<Constraint<D>> activation(int p, std::size_t i, int s, const Match<D>& match,
                                                        const Positions<D>& x_n, const Positions<D>& x_np1) const;
  /// The second constraint of a crease pair: slave s holds one
  /// frictionless constraint, of pair p, on one facet (neither pushed out
  /// nor under (48)), and is found behind another facet `end` of the same
  /// master surface that shares a node with the first and whose normal is
  /// on the same side and not within kCreaseSine of parallel. A slave
  /// pressed into a crease the master folds concave under it has no
  /// single facet that keeps it in front of both (docs/theory.md, "Two
  /// constraints on one slave"); it holds both, as a node on two slave
  /// surfaces does.
  [[nodiscard]] std::optional<Constraint<D>> crease(int p, int s, const Match<D>& end, const Positions<D>& x_n,
                                                    const Positions<D>& x_np1) const;
  /// Records constraint c in the per-node and per-pair flags.
  void mark(const Constraint<D>& c);
  /// The flags anew from active_.
  void index_active();
  /// f_N of each active constraint from the full residual g at the
  /// mid-point normals: g_s·n, or for a slave holding two constraints the
  /// split of g_s along both normals (their Gram system).
  [[nodiscard]] std::vector<double> split_forces(const Eigen::VectorXd& g);

  const model::Model<D>& model_;
  CollisionSet<D> collisions_;
  /// Pair p of the collision set.
  [[nodiscard]] const ContactPair<D>& pair(int p) const { return collisions_.pair(p); }
  std::vector<Constraint<D>> active_;
  std::vector<double> normal_forces_;
  std::vector<char> count_;                   ///< per node: active constraints it is the slave of (0–2)
  std::vector<int> first_pair_;               ///< per node: the pair of the first of them
  std::vector<Vec<D>> first_normal_;          ///< per node: that constraint's normal
  std::vector<std::vector<char>> active_in_;  ///< per pair, per slave (local): active in that pair
  std::vector<int> slot_;                     ///< per node: scratch of split_forces(), −1
  std::vector<char> released_;    ///< per node: released during this step
  std::vector<char> held_;        ///< per node: re-activated after a release in this step; not released again
  /// Per node: a push-out of it was given up, 1: before this step (an
  /// active constraint of it holds at the step's start, Constraint::hold),
  /// 2: in it (hold_pushes). Re-activated in the step, it is held, not
  /// pushed again.
  std::vector<char> given_up_;
  /// Constraints from before this step whose push-out was given up in it
  /// (hold_pushes); with the step's new held slaves, StepContactStats::pushes_given_up.
  int old_given_up_ = 0;
  std::int64_t step_ = 0;          ///< the step under way
  double start_mean_force_ = 0.0;  ///< mean f_N of the active slaves at the end of the previous step
  /// With impacts located, the largest gaps a slave is activated with as
  /// fractions of its facet size (gap_tolerance()); onset 0 when they are not.
  ImpactLocation location_;
  [[nodiscard]] bool located() const { return location_.onset > 0.0; }
  double time_ = 0.0;                 ///< t_n of the step under way
  std::vector<double> released_at_;   ///< per node: its last release in a taken step [s]
  std::vector<double> activated_at_;  ///< per pair: its last activation in a taken step [s]
  std::vector<char> activated_;       ///< per pair: a slave activated in this step
  std::vector<char> in_contact_;      ///< per pair: a constraint active at the step's start
  bool allow_splits_ = true;
  double dt_ = 0.0;         ///< the step under way (located impacts)
  Eigen::VectorXd v_n_;     ///< velocities at its start (located impacts)
};

}  // namespace conserve::contact
