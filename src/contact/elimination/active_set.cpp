#include "contact/elimination/active_set.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <unordered_map>

namespace conserve::contact {

template <int D>
ActiveSet<D>::ActiveSet(const model::Model<D>& model, std::vector<ContactPair<D>> pairs)
    : model_(model),
      collisions_(model, std::move(pairs)),
      index_(model.num_nodes(), collisions_.pairs()),
      locator_(model.num_nodes(), collisions_.size()),
      slot_(static_cast<std::size_t>(model.num_nodes()), -1),
      held_(static_cast<std::size_t>(model.num_nodes()), 0),
      switched_(static_cast<std::size_t>(model.num_nodes()), 0),
      given_up_(static_cast<std::size_t>(model.num_nodes()), 0),
      repeated_(static_cast<std::size_t>(model.num_nodes()), 0) {
  for (const ContactPair<D>& pr : collisions_.pairs()) coulomb_ = coulomb_ || (pr.friction && *pr.friction > 0.0);
}

template <int D>
std::optional<Constraint<D>> ActiveSet<D>::activation(int p, int s, const Match<D>& match, const Positions<D>& x_n,
                                                      const Positions<D>& x_np1) const {
  if (!(match.projection.gap < -pair(p).search.penetration_tolerance)) return std::nullopt;
  // Two constraints on one slave are held on facets of one order (the pair
  // kernels, zero_work::pair_frictionless_test, take both linear or both curved).
  const auto quadratic = [&](int q) { return pair(q).master.facets.rows() != D; };
  if (index_.count(s) > 0 && quadratic(p) != quadratic(index_.first_pair(s))) return std::nullopt;
  if (index_.active_in(p, s)) {
    if (index_.count(s) != 1 || index_.first_pair(s) != p) return std::nullopt;
    const auto held =
        std::find_if(active_.begin(), active_.end(), [s](const Constraint<D>& c) { return c.slave == s; });
    if (held == active_.end() || !forms_crease(pair(p), *held, match)) return std::nullopt;
    return make(p, s, match, x_n, x_np1);
  }
  if (!index_.can_hold(p, s, match.projection.normal)) return std::nullopt;
  return make(p, s, match, x_n, x_np1);
}

template <int D>
Constraint<D> ActiveSet<D>::make(int p, int s, const Match<D>& end, const Positions<D>& x_n,
                                 const Positions<D>& x_np1) const {
  ActivationContext context;
  context.step = step_;
  context.first = index_.count(s) == 0;
  context.given_up = given_up_[static_cast<std::size_t>(s)] != 0;
  context.facet_size = facet_size(p, s);
  const ContactPair<D>& pr = pair(p);
  if (!pr.friction || !(*pr.friction > 0.0)) return make_constraint(pr, p, s, end, x_n, x_np1, context);
  // A Coulomb pair's slave: held after a release in this step (its force
  // may be tensile), frictionless for the rest of it; moving along the
  // facet at the step's start by more than its slip regularization over
  // the step, slipping; else sticking (friction.hpp).
  const bool held = locator_.released_in_step(s);
  const bool slides = !held && slides_in(p, s, end, x_n, context.facet_size);
  if (held || slides) context.kind = Kind::frictionless;
  Constraint<D> c = make_constraint(pr, p, s, end, x_n, x_np1, context);
  if (slides) c = to_slip(c, *pr.friction, context.facet_size);
  return c;
}

template <int D>
void ActiveSet<D>::begin_step(std::int64_t step, double time, double dt, const Eigen::VectorXd& v_n) {
  locator_.begin_step(time, dt, v_n, active_);
  if (coulomb_) v_n_ = v_n, dt_ = dt;
  std::fill(held_.begin(), held_.end(), 0);
  std::fill(switched_.begin(), switched_.end(), 0);
  std::fill(given_up_.begin(), given_up_.end(), 0);
  std::fill(repeated_.begin(), repeated_.end(), 0);
  old_given_up_ = 0;
  step_ = step;
  double sum = 0.0;
  for (Constraint<D>& c : active_) {
    // A Coulomb pair's slave held frictionless after a release in the last
    // step slips with its friction from this one on.
    const ContactPair<D>& pr = pair(c.pair);
    if (pr.friction && *pr.friction > 0.0 && c.kind == Kind::frictionless && c.friction == 0.0 &&
        index_.count(c.slave) == 1)
      c = to_slip(c, *pr.friction, facet_size(c.pair, c.slave));
    c.start_force = c.normal_force;
    sum += c.normal_force;
    // A slave held behind its facet (the second constraint of a slave on
    // two surfaces keeps its start gap; its first has been released), or
    // part of the way out of a push-out deeper than a step's (push_target),
    // is pushed out in this step, as at its activation (make_constraint),
    // unless a push-out of it was given up (hold).
    c.push = c.kind == Kind::frictionless && c.gap < -pair(c.pair).search.penetration_tolerance &&
             index_.count(c.slave) == 1 && !c.hold;
    if (c.push) c.gap = push_target(c.gap, facet_size(c.pair, c.slave));
    if (c.hold) given_up_[c.slave] = 1;
  }
  start_mean_force_ = active_.empty() ? 0.0 : sum / static_cast<double>(active_.size());
}

template <int D>
Elimination<D> ActiveSet<D>::elimination(const Eigen::VectorXd& u_n, const Eigen::VectorXd& u,
                                         std::shared_ptr<TangentReduction<D>> reduction) {
  return Elimination<D>(model_.X, u_n, u, active_, collisions_.pairs(), std::move(reduction));
}

template <int D>
void ActiveSet<D>::set_constraints(std::vector<Constraint<D>> constraints) {
  active_ = std::move(constraints);
  index_active();
  normal_forces_.clear();
  for (const Constraint<D>& c : active_) normal_forces_.push_back(c.normal_force);
}

template <int D>
Positions<D> ActiveSet<D>::positions(const Eigen::VectorXd& u) const {
  return model_.X + u.reshaped(D, model_.num_nodes());
}

template <int D>
SetChange ActiveSet<D>::update(const Eigen::VectorXd& u_n, const Eigen::VectorXd& u_np1, const Eigen::VectorXd& g,
                               StepContactStats& stats, HeldCounts& counts) {
  ++stats.passes;
  const Positions<D> x_n = positions(u_n), x_np1 = positions(u_np1);
  const Positions<D> x_mid = 0.5 * (x_n + x_np1);
  const bool released = release_tensile(x_mid, g, stats, counts);
  const SetChange activated = activate_penetrating(x_n, x_np1, stats, counts);
  if (activated == SetChange::split) return activated;
  if (released || activated == SetChange::changed) return SetChange::changed;
  if (switch_friction(x_n, x_np1)) return SetChange::changed;
  // A slave that held (48) and ends the step behind its facet is pushed
  // out in this step instead, as one left behind at its start is
  // (begin_step): the step is solved again with it held at γ = 0.
  std::vector<double> end_gap(active_.size(), 0.0);
  bool pushed = false;
  for (std::size_t k = 0; k < active_.size(); ++k) {
    Constraint<D>& c = active_[k];
    if (!c.rate) continue;
    end_gap[k] = project_on<D>(x_np1.col(c.slave), pair(c.pair).master, c.facet, x_np1).gap;
    if (end_gap[k] < -pair(c.pair).search.penetration_tolerance && c.kind == Kind::frictionless &&
        index_.count(c.slave) == 1 && !c.hold)
      c.rate = false, c.gap = 0.0, c.push = pushed = true;
  }
  if (pushed) return SetChange::changed;
  // The step is taken: a slave that held (48) in it holds its end gap from now on.
  for (std::size_t k = 0; k < active_.size(); ++k) {
    Constraint<D>& c = active_[k];
    if (!c.rate) continue;
    c.gap = end_gap[k];
    c.rate = false;
    ++counts.rate_steps;
  }
  counts.pushes =
      static_cast<int>(std::count_if(active_.begin(), active_.end(), [](const Constraint<D>& c) { return c.push; }));
  // Slaves held afresh in the step: not those held before it and
  // re-activated in it after a release.
  counts.pushes_given_up =
      old_given_up_ + static_cast<int>(std::count_if(active_.begin(), active_.end(), [&](const Constraint<D>& c) {
        return c.hold && c.activated_step == step_ && given_up_[c.slave] != 1;
      }));
  return SetChange::none;
}

template <int D>
bool ActiveSet<D>::slides_in(int p, int s, const Match<D>& end, const Positions<D>& x_n, double facet_size) const {
  if (v_n_.size() == 0) return false;
  const ContactPair<D>& pr = pair(p);
  const Projection<D> start = project_on<D>(x_n.col(s), pr.master, end.facet, x_n);
  const auto nodes = static_cast<int>(pr.master.facets.rows());
  const FacetWeights<D> N = facet_weights<D>(nodes, start.xi);
  Vec<D> relative = v_n_.template segment<D>(s * D);
  for (int b = 0; b < nodes; ++b) relative -= N(b) * v_n_.template segment<D>(pr.master.facets(b, end.facet) * D);
  const double normal = start.normal.dot(relative);
  relative -= normal * start.normal;
  // An impact's tangential impulse can stop the slave's sliding within the
  // cone when |v_T| ≤ μ |v_N| (a node coming to rest on the facet): it is
  // activated sticking, as the stick kind's slaves are, and a μ that large
  // gives the stick kind's run.
  return relative.norm() * dt_ > kSlipScale * facet_size && relative.norm() > *pr.friction * std::abs(normal);
}

template <int D>
bool ActiveSet<D>::switch_friction(const Positions<D>& x_n, const Positions<D>& x_np1) {
  bool changed = false;
  for (Constraint<D>& c : active_) {
    const ContactPair<D>& pr = pair(c.pair);
    if (!pr.friction || !(*pr.friction > 0.0) || index_.count(c.slave) != 1 || held_[c.slave]) continue;
    char& switched = switched_[static_cast<std::size_t>(c.slave)];
    if (switched & kToSlip) continue;
    if (c.kind == Kind::stick) {
      if (!leaves_cone(c, c.force, *pr.friction)) continue;
      c = to_slip(c, *pr.friction, facet_size(c.pair, c.slave));
      switched |= kToSlip;
      changed = true;
    } else if (!(switched & kToStick) && c.friction > 0.0 && !c.push &&
               friction_step(c, x_n, x_np1).slip < kStickSlip * c.slip_scale) {
      c = to_stick(c, pr, x_n);
      switched |= kToStick;
      changed = true;
    }
  }
  return changed;
}

template <int D>
bool ActiveSet<D>::stick_slipping(const Positions<D>& x_n) {
  bool changed = false;
  for (Constraint<D>& c : active_) {
    char& switched = switched_[static_cast<std::size_t>(c.slave)];
    if (!(c.friction > 0.0) || c.push || (switched & kToStick) || index_.count(c.slave) != 1 || held_[c.slave])
      continue;
    c = to_stick(c, pair(c.pair), x_n);
    switched |= kToStick;
    changed = true;
  }
  return changed;
}

template <int D>
void ActiveSet<D>::hold_pushes(const Eigen::VectorXd& u_n) {
  const Positions<D> x_n = positions(u_n);
  for (Constraint<D>& c : active_) {
    if (!c.push) continue;
    c.push = false;
    c.hold = true;
    if (given_up_[c.slave] == 0) given_up_[c.slave] = 2;
    if (c.activated_step != step_) ++old_given_up_;
    c.gap = project_on<D>(x_n.col(c.slave), pair(c.pair).master, c.facet, x_n).gap;
  }
}

template <int D>
void ActiveSet<D>::end_step(double time) {
  locator_.end_step(time);
}

template <int D>
double ActiveSet<D>::split_fraction(const Eigen::VectorXd& u_n, const Eigen::VectorXd& u) {
  if (!locator_.located() || !allow_splits_) return 1.0;
  const Positions<D> x_n = positions(u_n), x = positions(u);
  double fraction = 1.0;
  collisions_.for_each_match(
      x,
      [&](int p, std::size_t, int s, const Match<D>& match) {
        if (const auto c = activation(p, s, match, x_n, x)) fraction = std::min(fraction, split_at(*c, match, x_n));
      },
      &x_n);
  return fraction;
}

// (46), (65): keep the constraint while f_N = g_s·n_{n+½} ≥ 0 (or while it
// is held after a release earlier in the step).
template <int D>
bool ActiveSet<D>::release_tensile(const Positions<D>& x_mid, const Eigen::VectorXd& g, StepContactStats& stats,
                                   HeldCounts& counts) {
  for (Constraint<D>& c : active_) {
    if (c.master.size() != D) {  // a curved facet's normal at ξ_{n+½}
      typename CurvedFacet<D>::Nodes xm;
      for (int a = 0; a < c.master.size(); ++a) xm.col(a) = x_mid.col(c.master[a]);
      c.normal = CurvedFacet<D>::normal(xm, c.xi);
      continue;
    }
    FacetNodes<D> xm;
    for (int a = 0; a < D; ++a) xm.col(a) = x_mid.col(c.master[a]);
    c.normal = facet_normal<D>(xm);
  }
  std::vector<double> forces = contact::normal_forces(active_, g, slot_);
  // A driven slave's constraint left out of the last maps (no node of its
  // facet free to hold it) carried no force: kept.
  for (std::size_t j = 0; j < active_.size(); ++j)
    if (active_[j].eliminated < 0 && collisions_.pairs()[active_[j].pair].slave_driven()) forces[j] = 0.0;
  std::vector<Constraint<D>> kept;
  normal_forces_.clear();
  std::map<int, int> held_by;  // constraints per slave
  for (const Constraint<D>& c : active_) ++held_by[c.slave];
  for (std::size_t j = 0; j < active_.size(); ++j) {
    Constraint<D>& c = active_[j];
    const double f_n = forces[j];
    c.force = held_by[c.slave] == 1 && c.eliminated < 0 ? Vec<D>(g.template segment<D>(c.slave * D))
                                                        : Vec<D>(f_n * c.normal);
    c.mid = x_mid.col(c.slave);
    if (f_n < 0.0 && !held_[c.slave]) {
      locator_.released(c.slave);
      ++stats.releases;
      if (step_ - c.activated_step < kChatterWindow) ++counts.chatter;
      if (c.activated_step < step_ && c.start_force > kLoadedFraction * start_mean_force_) ++counts.loaded_releases;
      continue;
    }
    c.normal_force = f_n;
    kept.push_back(c);
    normal_forces_.push_back(f_n);
  }
  const bool changed = kept.size() != active_.size();
  active_ = std::move(kept);
  if (changed) index_active();
  return changed;
}

// One search of every slave at x_{n+1} serves two ends: the inactive
// slaves found behind a master facet are activated, and the contact
// geometry of the pass (deepest penetration, active gaps) is recorded by
// the rules of slave_penetration() and active_gaps(); when nothing changes,
// this pass's u_{n+1} is the step's end and so is that geometry.
template <int D>
SetChange ActiveSet<D>::activate_penetrating(const Positions<D>& x_n, const Positions<D>& x_np1,
                                             StepContactStats& stats, HeldCounts& counts) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  bool changed = false;
  const bool split = allow_splits_ && locator_.located();
  std::map<std::pair<int, int>, double> active_gap;  // by pair and slave node, for the active constraints
  std::vector<Constraint<D>> activated;
  // Constraints by slave node, active and activated here, for repeats().
  std::unordered_multimap<int, std::pair<bool, std::size_t>> by_slave;
  // Whether c repeats another constraint (any, or only one it gives way to).
  auto repeated = [&](const Constraint<D>& c, bool yielding) {
    for (const int m : c.master)
      for (auto [it, end] = by_slave.equal_range(m); it != end; ++it) {
        const auto [fresh, k] = it->second;
        const Constraint<D>& other = fresh ? activated[k] : active_[k];
        if ((!yielding || gives_way(c, other, collisions_.pairs())) && repeats(c, other, x_np1)) return true;
      }
    return false;
  };
  // Slaves that came onto each other's nodes while held: the constraint
  // that gives way (gives_way: the second pass's, or self-contact's of the
  // larger slave) goes, and the step is solved again without it.
  // A driven slave's constraint (ContactPair::slave_driven) that no node
  // of its facet was free to hold at the last build (they hold others, or
  // are prescribed) repeats those: it goes too.
  auto unheld = [&](const Constraint<D>& c) {
    const ContactPair<D>& pr = pair(c.pair);
    if (!pr.slave_driven()) return false;
    return std::all_of(c.master.begin(), c.master.end(), [&](int m) {
      return by_slave.count(m) > 0 || std::binary_search(pr.fixed.begin(), pr.fixed.end(), m);
    });
  };
  for (std::size_t k = 0; k < active_.size(); ++k) by_slave.emplace(active_[k].slave, std::make_pair(false, k));
  for (std::size_t k = 0; k < active_.size(); ++k) {
    const bool left_out = pair(active_[k].pair).slave_driven() && active_[k].eliminated < 0;
    if (!left_out && !active_[k].repeat && (!pair(active_[k].pair).yields() || !repeated(active_[k], true)))
      continue;
    if (!left_out) repeated_[active_[k].slave] = 1;
    active_.erase(active_.begin() + static_cast<std::ptrdiff_t>(k));
    normal_forces_.erase(normal_forces_.begin() + static_cast<std::ptrdiff_t>(k));
    ++counts.repeats;
    index_active();
    return SetChange::changed;
  }
  double deepest = 0.0, min_gap = inf, max_gap = -inf;
  collisions_.for_each_match(
      x_np1,
      [&](int p, std::size_t, int s, const Match<D>& match) {
        deepest = std::max(deepest, -match.projection.gap);
        if (index_.active_in(p, s)) active_gap[{p, s}] = match.projection.gap;
        if (auto c = activation(p, s, match, x_n, x_np1)) {
          if (repeated(*c, false) || unheld(*c) || (repeated_[c->slave] && pair(c->pair).yields())) {
            ++counts.repeats;
            return;
          }
          by_slave.emplace(c->slave, std::make_pair(true, activated.size()));
          if (split) stats.split_fraction = std::min(stats.split_fraction, split_at(*c, match, x_n));
          if (index_.active_in(p, s)) ++counts.creases;
          index_.mark(*c);  // a node on two slave surfaces or at a crease: a third is refused
          activated.push_back(*c);
        }
      },
      &x_n);
  for (const Constraint<D>& c : active_) {
    const ContactPair<D>& pr = pair(c.pair);
    const auto found = active_gap.find({c.pair, c.slave});
    const double gap = found != active_gap.end()
                           ? found->second
                           : project_on<D>(x_np1.col(c.slave), pr.master, c.facet, x_np1).gap;
    min_gap = std::min(min_gap, gap);
    max_gap = std::max(max_gap, gap);
  }
  stats.slave_penetration = deepest;
  const bool none = min_gap > max_gap;
  stats.min_active_gap = none ? std::numeric_limits<double>::quiet_NaN() : min_gap;
  stats.max_active_gap = none ? std::numeric_limits<double>::quiet_NaN() : max_gap;
  if (stats.split_fraction < 1.0) {
    index_active();
    return SetChange::split;
  }
  for (const Constraint<D>& c : activated) {
    counts.max_activation_gap = std::max(counts.max_activation_gap, c.gap);
    ++stats.activations;
    locator_.activated(c.pair);
    if (locator_.released_in_step(c.slave)) held_[c.slave] = 1, ++counts.held;
    active_.push_back(c);
    normal_forces_.push_back(0.0);
    changed = true;
  }
  return changed ? SetChange::changed : SetChange::none;
}

template <int D>
Penetration ActiveSet<D>::master_penetration(const Eigen::VectorXd& u, const Eigen::VectorXd& u_n) {
  return collisions_.master_penetration(positions(u), positions(u_n));
}

template <int D>
Penetration ActiveSet<D>::slave_penetration(const Eigen::VectorXd& u, const Eigen::VectorXd* u_n) {
  const Positions<D> x_n = u_n ? positions(*u_n) : Positions<D>();
  return collisions_.slave_penetration(positions(u), u_n ? &x_n : nullptr);
}

template <int D>
ActiveGaps ActiveSet<D>::active_gaps(const Eigen::VectorXd& u, const Eigen::VectorXd* u_n) {
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  if (active_.empty()) return {nan, nan};
  const Positions<D> x = positions(u);
  const Positions<D> x_n = u_n ? positions(*u_n) : Positions<D>();
  // Only the pairs of active constraints are searched.
  std::vector<std::vector<Vec<D>>> normals(static_cast<std::size_t>(collisions_.size()));
  for (const Constraint<D>& c : active_) {
    if (!normals[c.pair].empty()) continue;
    collisions_.refit(c.pair, x);
    normals[c.pair] = node_normals<D>(pair(c.pair).slave, x);
  }
  ActiveGaps gaps{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  for (const Constraint<D>& c : active_) {
    const ContactPair<D>& pr = pair(c.pair);
    const auto i = static_cast<std::size_t>(pr.slave.local_node(c.slave));
    const auto match = collisions_.match(c.pair, i, x, normals[c.pair][i], u_n ? &x_n : nullptr);
    const double gap =
        match ? match->projection.gap : project_on<D>(x.col(c.slave), pr.master, c.facet, x).gap;
    gaps.min = std::min(gaps.min, gap);
    gaps.max = std::max(gaps.max, gap);
  }
  return gaps;
}

template class ActiveSet<2>;
template class ActiveSet<3>;

}  // namespace conserve::contact
