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
/// The set coordinates its pieces, each with its own tests: which slaves
/// hold what (slave_index.hpp), the constraint a slave is activated with,
/// creases and push-outs (activation.hpp), releases and their timing
/// (release.hpp), Coulomb friction's stick and slip (friction.hpp), and
/// impacts located in time (impact_locator.hpp).
#include <limits>
#include <optional>
#include <vector>

#include "contact/collision_set.hpp"
#include "contact/constraint.hpp"
#include "contact/elimination/activation.hpp"
#include "contact/elimination/elimination.hpp"
#include "contact/elimination/friction.hpp"
#include "contact/elimination/held_statistics.hpp"
#include "contact/elimination/impact_locator.hpp"
#include "contact/elimination/release.hpp"
#include "contact/elimination/slave_index.hpp"
#include "contact/method.hpp"
#include "model/model.hpp"

namespace conserve::contact {

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
                   StepContactStats& stats, HeldCounts& counts);

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
  void locate_impacts(const ImpactLocation& location) { locator_.configure(location); }
  /// Per node the time of its last release, and per pair of its last
  /// activation, in taken steps (−∞: none): the windows of ImpactLocation,
  /// which the method's saved state carries.
  [[nodiscard]] const std::vector<double>& release_times() const { return locator_.release_times(); }
  [[nodiscard]] const std::vector<double>& activation_times() const { return locator_.activation_times(); }
  void set_event_times(std::vector<double> releases, std::vector<double> activations) {
    locator_.set_event_times(std::move(releases), std::move(activations));
  }
  /// Whether update() may ask for a split (the stepper forbids it once a
  /// step has been split too often or would become too short).
  void allow_splits(bool allow) { allow_splits_ = allow; }
  /// Releases located in time ([active_set] locate_releases): the longest
  /// next step after step `step` (contact/elimination/release.hpp).
  [[nodiscard]] double release_step(std::int64_t step, double full, double last, double previous) const {
    return contact::release_step(active_, step, full, last, previous);
  }
  /// The largest gap slave node `slave` of pair `pair` is activated with
  /// when impacts are located [m] (+∞ when they are not).
  [[nodiscard]] double gap_tolerance(int pair, int slave) const {
    return locator_.gap_tolerance(pair, slave, facet_size(pair, slave));
  }
  /// The longest edge of the slave facets at slave node `slave` of pair
  /// `pair` in the reference configuration [m]: the mesh size that the
  /// gap tolerance and a push-out's step (push_target) are fractions of.
  [[nodiscard]] double facet_size(int pair, int slave) const { return collisions_.facet_size(pair, slave); }

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

  /// After a solve that did not converge: the slipping slaves of Coulomb
  /// pairs that have not gone from slip to stick in this step stick
  /// (friction.hpp, to_stick), marked so. A slip whose friction direction
  /// turns within the step (a slave stopping, |Δs| of order ε) can send
  /// Newton back and forth across zero slip; from the stick solution the
  /// slip it is switched back to (switch_friction) starts at zero slip,
  /// where Newton approaches the slip monotonically. True if any changed.
  bool stick_slipping(const Positions<D>& x_n);

 private:
  /// switched_ bits: went from stick to slip, from slip to stick.
  static constexpr char kToSlip = 1, kToStick = 2;
  bool release_tensile(const Positions<D>& x_mid, const Eigen::VectorXd& g, StepContactStats& stats,
                       HeldCounts& counts);
  SetChange activate_penetrating(const Positions<D>& x_n, const Positions<D>& x_np1, StepContactStats& stats,
                                 HeldCounts& counts);
  /// Coulomb pairs' slaves (one constraint, not held after a release):
  /// a sticking one whose force leaves the cone slips, a slipping one
  /// whose slip stays below kStickSlip × its regularization sticks
  /// (friction.hpp); in
  /// one step a slave goes from slip to stick at most once, and not after
  /// it went from stick to slip. True if any changed.
  bool switch_friction(const Positions<D>& x_n, const Positions<D>& x_np1);
  /// Whether slave s of Coulomb pair p, found behind facet `end`, moved
  /// along that facet at the step's start by more than its slip
  /// regularization (kSlipScale × facet_size) over the step, and faster
  /// than μ times its speed towards it: it is activated slipping, not
  /// sticking.
  [[nodiscard]] bool slides_in(int p, int s, const Match<D>& end, const Positions<D>& x_n, double facet_size) const;
  /// Where the step should end for constraint c (just made, with its end
  /// match `end`) to arrive at half its gap tolerance; 1 if it starts within it.
  [[nodiscard]] double split_at(const Constraint<D>& c, const Match<D>& end, const Positions<D>& x_n) const {
    return locator_.split_at(c, end, pair(c.pair).master, x_n, gap_tolerance(c.pair, c.slave));
  }
  [[nodiscard]] Positions<D> positions(const Eigen::VectorXd& u) const;
  /// The constraint slave node s of pair p takes
  /// for its match at the end of a solve (positions x_np1, the step from
  /// x_n), if any: a slave found behind a facet further than the
  /// penetration tolerance is activated if it holds no constraint of p
  /// (and SlaveIndex::can_hold allows it), or given a crease pair when it
  /// holds one frictionless constraint of p on another facet (forms_crease).
  [[nodiscard]] std::optional<Constraint<D>> activation(int p, int s, const Match<D>& match, const Positions<D>& x_n,
                                                        const Positions<D>& x_np1) const;
  /// make_constraint with this set's context for slave s of pair p.
  [[nodiscard]] Constraint<D> make(int p, int s, const Match<D>& end, const Positions<D>& x_n,
                                   const Positions<D>& x_np1) const;
  /// The index anew from active_.
  void index_active() { index_.rebuild(active_); }

  const model::Model<D>& model_;
  CollisionSet<D> collisions_;
  /// Pair p of the collision set.
  [[nodiscard]] const ContactPair<D>& pair(int p) const { return collisions_.pair(p); }
  std::vector<Constraint<D>> active_;
  std::vector<double> normal_forces_;
  SlaveIndex<D> index_;       ///< which slaves hold which constraints
  ImpactLocator<D> locator_;  ///< gap tolerances, splits, and the events they follow
  std::vector<int> slot_;     ///< per node: scratch of normal_forces(), −1
  std::vector<char> held_;    ///< per node: re-activated after a release in this step; not released again
  /// Per node, its friction switches in this step: 1 to slip, 2 to stick (bits).
  std::vector<char> switched_;
  /// Per node: a push-out of it was given up, 1: before this step (an
  /// active constraint of it holds at the step's start, Constraint::hold),
  /// 2: in it (hold_pushes). Re-activated in the step, it is held, not
  /// pushed again.
  std::vector<char> given_up_;
  /// Per node: a constraint of it that gives way (ContactPair::yields) was
  /// dropped as a repeat in this step; none of its is activated again in
  /// the step, so that the solves do not take it in and out.
  std::vector<char> repeated_;
  /// Constraints from before this step whose push-out was given up in it
  /// (hold_pushes); with the step's new held slaves, HeldCounts::pushes_given_up.
  int old_given_up_ = 0;
  std::int64_t step_ = 0;          ///< the step under way
  double start_mean_force_ = 0.0;  ///< mean f_N of the active slaves at the end of the previous step
  bool allow_splits_ = true;
  bool coulomb_ = false;  ///< a pair has Coulomb friction μ > 0
  Eigen::VectorXd v_n_;   ///< with coulomb_: velocities at the step's start
  double dt_ = 0.0;       ///< with coulomb_: the step's length
};

}  // namespace conserve::contact
