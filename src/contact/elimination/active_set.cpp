#include "contact/elimination/active_set.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "contact/elimination/zero_work.hpp"

namespace conserve::contact {

template <int D>
ActiveSet<D>::ActiveSet(const model::Model<D>& model, std::vector<ContactPair<D>> pairs)
    : model_(model),
      collisions_(model, std::move(pairs)),
      released_(model.num_nodes(), 0),
      held_(model.num_nodes(), 0),
      given_up_(model.num_nodes(), 0),
      released_at_(model.num_nodes(), -std::numeric_limits<double>::infinity()),
      activated_at_(static_cast<std::size_t>(collisions_.size()), -std::numeric_limits<double>::infinity()),
      activated_(static_cast<std::size_t>(collisions_.size()), 0),
      in_contact_(static_cast<std::size_t>(collisions_.size()), 0) {
  slot_.assign(model.num_nodes(), -1);
  index_active();
}

template <int D>
void ActiveSet<D>::index_active() {
  count_.assign(model_.num_nodes(), 0);
  first_pair_.assign(model_.num_nodes(), -1);
  first_normal_.assign(model_.num_nodes(), Vec<D>::Zero());
  active_in_.resize(static_cast<std::size_t>(collisions_.size()));
  for (int p = 0; p < collisions_.size(); ++p) active_in_[p].assign(pair(p).slave.nodes.size(), 0);
  for (const Constraint<D>& c : active_) mark(c);
}

template <int D>
void ActiveSet<D>::mark(const Constraint<D>& c) {
  if (count_[c.slave]++ == 0) first_pair_[c.slave] = c.pair, first_normal_[c.slave] = c.normal;
  const int i = pair(c.pair).slave.local_node(c.slave);
  if (i >= 0) active_in_[c.pair][static_cast<std::size_t>(i)] = 1;
}

template <int D>
bool ActiveSet<D>::can_hold(int p, int s, const Vec<D>& normal) const {
  if (count_[s] == 0) return true;
  if (count_[s] > 1 || first_pair_[s] == p) return false;
  return pair(p).kind == Kind::frictionless && pair(first_pair_[s]).kind == Kind::frictionless &&
         std::abs(normal.dot(first_normal_[s])) < kParallelCosine;
}

template <int D>
std::optional<Constraint<D>> ActiveSet<D>::activation(int p, std::size_t i, int s, const Match<D>& match,
                                                      const Positions<D>& x_n, const Positions<D>& x_np1) const {
  if (!(match.projection.gap < -pair(p).search.penetration_tolerance)) return std::nullopt;
  if (active_in_[p][i]) return crease(p, s, match, x_n, x_np1);
  if (!can_hold(p, s, match.projection.normal)) return std::nullopt;
  return make_constraint(p, s, match, x_n, x_np1);
}

template <int D>
std::optional<Constraint<D>> ActiveSet<D>::crease(int p, int s, const Match<D>& end, const Positions<D>& x_n,
                                                  const Positions<D>& x_np1) const {
  if (count_[s] != 1 || first_pair_[s] != p || pair(p).kind != Kind::frictionless) return std::nullopt;
  const auto held = std::find_if(active_.begin(), active_.end(), [s](const Constraint<D>& c) { return c.slave == s; });
  if (held == active_.end() || held->facet == end.facet || held->push || held->rate) return std::nullopt;
  const auto& facets = pair(p).master.facets;
  bool shared = false;
  for (int a = 0; a < D; ++a)
    for (int b = 0; b < D; ++b) shared = shared || facets(a, end.facet) == held->master[b];
  const double cosine = held->normal.dot(end.projection.normal);
  if (!shared || !(cosine > 0.0) || 1.0 - cosine * cosine < kCreaseSine * kCreaseSine) return std::nullopt;
  return make_constraint(p, s, end, x_n, x_np1);
}

template <int D>
void ActiveSet<D>::begin_step(std::int64_t step, double time, double dt, const Eigen::VectorXd& v_n) {
  if (located()) dt_ = dt, v_n_ = v_n;
  time_ = time;
  std::fill(released_.begin(), released_.end(), 0);
  std::fill(activated_.begin(), activated_.end(), 0);
  std::fill(in_contact_.begin(), in_contact_.end(), 0);
  for (const Constraint<D>& c : active_) in_contact_[static_cast<std::size_t>(c.pair)] = 1;
  std::fill(held_.begin(), held_.end(), 0);
  std::fill(given_up_.begin(), given_up_.end(), 0);
  old_given_up_ = 0;
  step_ = step;
  double sum = 0.0;
  for (Constraint<D>& c : active_) {
    c.start_force = c.normal_force;
    sum += c.normal_force;
    // A slave held behind its facet (the second constraint of a slave on
    // two surfaces keeps its start gap; its first has been released), or
    // part of the way out of a push-out deeper than a step's (push_target),
    // is pushed out in this step, as at its activation (make_constraint),
    // unless a push-out of it was given up (hold).
    c.push = c.kind == Kind::frictionless && c.gap < -pair(c.pair).search.penetration_tolerance &&
             count_[c.slave] == 1 && !c.hold;
    if (c.push) c.gap = push_target(c, c.gap);
    if (c.hold) given_up_[c.slave] = 1;
  }
  start_mean_force_ = active_.empty() ? 0.0 : sum / static_cast<double>(active_.size());
}

// A step's normal force is its mean over the step, f(t) at about the
// step's middle. A slave lets go in the first step whose mean is
// tensile, and the force that measures its release (loaded_releases) is
// the mean of the step before, which is of order (rate of fall) × (that
// step). With f falling linearly at rate r from f_N at the middle of the
// last step (length h), the next step's mean stays ≥ 0 for steps up to
// 2 f_N / r − h. Where that is within kReleaseHorizon full steps, the next
// step is a kReleaseApproach part of it: the steps shrink geometrically
// towards the lift-off, which a step then meets with a force of about
// kReleaseUnloading × (the loaded threshold) left in the step before.
template <int D>
double ActiveSet<D>::release_step(std::int64_t step, double full, double last, double previous) const {
  if (active_.empty() || !(last > 0.0) || !(previous > 0.0)) return full;
  double sum = 0.0;
  for (const Constraint<D>& c : active_) sum += c.normal_force;
  const double loaded = kLoadedFraction * sum / static_cast<double>(active_.size());
  double next = full;
  for (const Constraint<D>& c : active_) {
    if (c.activated_step >= step || !(c.normal_force > loaded)) continue;
    const double rate = (c.start_force - c.normal_force) / (0.5 * (previous + last));  // −df/dt
    if (!(rate > 0.0)) continue;
    const double ahead = 2.0 * c.normal_force / rate - last;
    if (ahead > kReleaseHorizon * full) continue;
    next = std::min({next, 2.0 * last, std::max(kReleaseApproach * ahead, kReleaseUnloading * loaded / rate)});
  }
  return std::max(next, full / kReleaseShortest);
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
                               StepContactStats& stats) {
  ++stats.passes;
  const Positions<D> x_n = positions(u_n), x_np1 = positions(u_np1);
  const Positions<D> x_mid = 0.5 * (x_n + x_np1);
  const bool released = release_tensile(x_mid, g, stats);
  const SetChange activated = activate_penetrating(x_n, x_np1, stats);
  if (activated == SetChange::split) return activated;
  if (released || activated == SetChange::changed) return SetChange::changed;
  // A slave that held (48) and ends the step behind its facet is pushed
  // out in this step instead, as one left behind at its start is
  // (begin_step): the step is solved again with it held at γ = 0.
  std::vector<double> end_gap(active_.size(), 0.0);
  bool pushed = false;
  for (std::size_t k = 0; k < active_.size(); ++k) {
    Constraint<D>& c = active_[k];
    if (!c.rate) continue;
    end_gap[k] = project<D>(x_np1.col(c.slave), facet_nodes<D>(pair(c.pair).master, c.facet, x_np1)).gap;
    if (end_gap[k] < -pair(c.pair).search.penetration_tolerance && c.kind == Kind::frictionless &&
        count_[c.slave] == 1 && !c.hold)
      c.rate = false, c.gap = 0.0, c.push = pushed = true;
  }
  if (pushed) return SetChange::changed;
  // The step is taken: a slave that held (48) in it holds its end gap from now on.
  for (std::size_t k = 0; k < active_.size(); ++k) {
    Constraint<D>& c = active_[k];
    if (!c.rate) continue;
    c.gap = end_gap[k];
    c.rate = false;
    ++stats.rate_steps;
  }
  stats.pushes =
      static_cast<int>(std::count_if(active_.begin(), active_.end(), [](const Constraint<D>& c) { return c.push; }));
  // Slaves held afresh in the step: not those held before it and
  // re-activated in it after a release.
  stats.pushes_given_up =
      old_given_up_ + static_cast<int>(std::count_if(active_.begin(), active_.end(), [&](const Constraint<D>& c) {
        return c.hold && c.activated_step == step_ && given_up_[c.slave] != 1;
      }));
  return SetChange::none;
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
    c.gap = project<D>(x_n.col(c.slave), facet_nodes<D>(pair(c.pair).master, c.facet, x_n)).gap;
  }
}

template <int D>
void ActiveSet<D>::locate_impacts(const ImpactLocation& location) {
  location_ = location;
  if (!(location_.onset > 0.0)) location_ = {};
  location_.cluster = std::max(location_.cluster, location_.onset);
}

template <int D>
void ActiveSet<D>::end_step(double time) {
  for (std::size_t node = 0; node < released_.size(); ++node)
    if (released_[node]) released_at_[node] = time;
  for (std::size_t p = 0; p < activated_.size(); ++p)
    if (activated_[p]) activated_at_[p] = time;
}

template <int D>
void ActiveSet<D>::set_event_times(std::vector<double> releases, std::vector<double> activations) {
  released_at_ = std::move(releases);
  activated_at_ = std::move(activations);
}

// The path within the step that the mid-point scheme implies is the
// quadratic through x_n with slope V_n that ends at x_{n+1} (its end slope
// is then V_{n+1} of (19)); on it the gap is, to first order in the
// facet's rotation, g(s) = γ + s Δt ġ_n + s² (g_{n+1} − γ − Δt ġ_n), with ġ_n
// the slave's normal velocity relative to its facet point at the start.
// The step should end at the first s where g = δ/2.
template <int D>
double ActiveSet<D>::split_at(const Constraint<D>& c, const Match<D>& end, const Positions<D>& x_n) const {
  const double tolerance = gap_tolerance(c.pair, c.slave);
  if (!(c.gap > tolerance)) return 1.0;
  const double target = c.gap - 0.5 * tolerance;  // > 0: the drop of the gap to reach δ/2
  const double drop = c.gap - end.projection.gap;  // > target
  double fraction = target / drop;                 // the straight path's estimate
  if (v_n_.size() > 0) {
    const ContactPair<D>& pr = pair(c.pair);
    const Projection<D> start = project<D>(x_n.col(c.slave), facet_nodes<D>(pr.master, c.facet, x_n));
    const Vec<D> N = facet_shape<D>(start.xi);
    Vec<D> relative = v_n_.template segment<D>(c.slave * D);
    for (int b = 0; b < D; ++b) relative -= N(b) * v_n_.template segment<D>(c.master[b] * D);
    const double slope = dt_ * relative.dot(start.normal);  // dg/ds at s = 0
    const double curve = -drop - slope;                     // g(s) = γ + slope s + curve s²
    // Smallest root in (0, 1] of curve s² + slope s + target = 0, written
    // to avoid cancellation; g(0) > δ/2 > g(1), so there is one.
    const double disc = slope * slope - 4.0 * curve * target;
    if (std::abs(curve) > 1e-12 * drop && disc >= 0.0) {
      const double q = -0.5 * (slope + std::copysign(std::sqrt(disc), slope));
      double best = 2.0;
      for (double s : {q / curve, q != 0.0 ? target / q : 2.0})
        if (s > 0.0 && s <= 1.0) best = std::min(best, s);
      if (best <= 1.0) fraction = best;
    }
  }
  return std::clamp(fraction, 0.0, 1.0);
}

template <int D>
double ActiveSet<D>::split_fraction(const Eigen::VectorXd& u_n, const Eigen::VectorXd& u) {
  if (!located() || !allow_splits_) return 1.0;
  const Positions<D> x_n = positions(u_n), x = positions(u);
  double fraction = 1.0;
  collisions_.for_each_match(
      x,
      [&](int p, std::size_t i, int s, const Match<D>& match) {
        if (const auto c = activation(p, i, s, match, x_n, x)) fraction = std::min(fraction, split_at(*c, match, x_n));
      },
      &x_n);
  return fraction;
}

template <int D>
double ActiveSet<D>::push_target(const Constraint<D>& c, double start_gap) const {
  return std::min(0.0, start_gap + kPushOutStep * facet_size(c.pair, c.slave));
}

template <int D>
double ActiveSet<D>::facet_size(int pair, int slave) const {
  return collisions_.facet_size(pair, slave);
}

template <int D>
double ActiveSet<D>::gap_tolerance(int pair, int slave) const {
  if (!located()) return std::numeric_limits<double>::infinity();
  const auto p = static_cast<std::size_t>(pair);
  const bool follows = in_contact_[p] || time_ - activated_at_[p] <= location_.window ||
                       time_ - released_at_[slave] <= location_.window;
  return (follows ? location_.cluster : location_.onset) * facet_size(pair, slave);
}

template <int D>
std::vector<double> ActiveSet<D>::split_forces(const Eigen::VectorXd& g) {
  const std::size_t n = active_.size();
  std::vector<double> f(n);
  std::vector<int> partner(n, -1);
  for (std::size_t j = 0; j < n; ++j) {
    int& first = slot_[active_[j].slave];
    if (first < 0) {
      first = static_cast<int>(j);
    } else {
      partner[j] = first;
      partner[static_cast<std::size_t>(first)] = static_cast<int>(j);
    }
  }
  for (std::size_t j = 0; j < n; ++j) {
    const Constraint<D>& c = active_[j];
    slot_[c.slave] = -1;
    const Vec<D> g_s = g.template segment<D>(c.slave * D);
    if (partner[j] < 0) {
      f[j] = g_s.dot(c.normal);
      continue;
    }
    const Vec<D>& m = active_[static_cast<std::size_t>(partner[j])].normal;
    // g_s = f n + f′ m in the least-squares sense: Gram system, f by Cramer.
    const double nm = c.normal.dot(m), det = 1.0 - nm * nm;
    f[j] = (g_s.dot(c.normal) - nm * g_s.dot(m)) / det;
  }
  return f;
}

// (46), (65): keep the constraint while f_N = g_s·n_{n+½} ≥ 0 (or while it
// is held after a release earlier in the step).
template <int D>
bool ActiveSet<D>::release_tensile(const Positions<D>& x_mid, const Eigen::VectorXd& g, StepContactStats& stats) {
  for (Constraint<D>& c : active_) {
    FacetNodes<D> xm;
    for (int a = 0; a < D; ++a) xm.col(a) = x_mid.col(c.master[a]);
    c.normal = facet_normal<D>(xm);
  }
  const std::vector<double> forces = split_forces(g);
  std::vector<Constraint<D>> kept;
  normal_forces_.clear();
  std::map<int, int> held_by;  // constraints per slave
  for (const Constraint<D>& c : active_) ++held_by[c.slave];
  for (std::size_t j = 0; j < active_.size(); ++j) {
    Constraint<D>& c = active_[j];
    const double f_n = forces[j];
    c.force = held_by[c.slave] == 1 ? Vec<D>(g.template segment<D>(c.slave * D)) : Vec<D>(f_n * c.normal);
    c.mid = x_mid.col(c.slave);
    if (f_n < 0.0 && !held_[c.slave]) {
      released_[c.slave] = 1;
      ++stats.releases;
      if (step_ - c.activated_step < kChatterWindow) ++stats.chatter;
      if (c.activated_step < step_ && c.start_force > kLoadedFraction * start_mean_force_) ++stats.loaded_releases;
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
                                             StepContactStats& stats) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  bool changed = false;
  const bool split = allow_splits_ && located();
  std::vector<std::vector<double>> active_gap(static_cast<std::size_t>(collisions_.size()));  // per pair, per slave
  for (int p = 0; p < collisions_.size(); ++p) active_gap[p].assign(pair(p).slave.nodes.size(), nan);
  std::vector<Constraint<D>> activated;
  double deepest = 0.0, min_gap = inf, max_gap = -inf;
  collisions_.for_each_match(x_np1, [&](int p, std::size_t i, int s, const Match<D>& match) {
    deepest = std::max(deepest, -match.projection.gap);
    if (active_in_[p][i]) active_gap[p][i] = match.projection.gap;
    if (const auto c = activation(p, i, s, match, x_n, x_np1)) {
      if (split) stats.split_fraction = std::min(stats.split_fraction, split_at(*c, match, x_n));
      if (active_in_[p][i]) ++stats.creases;
      mark(*c);  // a node on two slave surfaces or at a crease: a third is refused
      activated.push_back(*c);
    }
  }, &x_n);
  for (const Constraint<D>& c : active_) {
    const ContactPair<D>& pr = pair(c.pair);
    double gap = active_gap[c.pair][static_cast<std::size_t>(pr.slave.local_node(c.slave))];
    if (std::isnan(gap)) gap = project<D>(x_np1.col(c.slave), facet_nodes<D>(pr.master, c.facet, x_np1)).gap;
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
    stats.max_activation_gap = std::max(stats.max_activation_gap, c.gap);
    ++stats.activations;
    activated_[static_cast<std::size_t>(c.pair)] = 1;
    if (released_[c.slave]) held_[c.slave] = 1, ++stats.held;
    active_.push_back(c);
    normal_forces_.push_back(0.0);
    changed = true;
  }
  return changed ? SetChange::changed : SetChange::none;
}

// The facet the slave was found behind at the end of the step; its gap
// γ and, for stick, its frozen ξ̄ are those of the slave's position at the
// START of the step on that facet, so that the constraint holds what the
// slave had: for stick F(x_m,n) = x_s,n exactly (no work, whatever the
// facet); for frictionless its start gap too, even when it is negative (a
// slave that was over a neighbouring facet across a convex edge, or that
// sank beyond the surface's border unseen, starts behind this facet's
// plane). Pushing it out to γ = 0 within the step at zero work needs other
// non-rigid motion of the constraint's nodes as large as the push-out: a
// push-out alone is met by a force direction ā with ā_s·n = 0 exactly
// (contact/elimination/zero_work.hpp), a tangential force Newton cannot balance
// (docs/validation.md, §6.2). Otherwise the paper's force pushes it out
// (Constraint::push), unless a push-out of it was given up (hold_pushes):
// then, as a slave's second constraint, it is held as far behind as it
// started; the history's min_active_gap shows it.
template <int D>
Constraint<D> ActiveSet<D>::make_constraint(int p, int s, const Match<D>& end, const Positions<D>& x_n,
                                            const Positions<D>& x_np1) const {
  const ContactPair<D>& pr = pair(p);
  const Positions<D> x_mid = 0.5 * (x_n + x_np1);
  const Projection<D> start = project<D>(x_n.col(s), facet_nodes<D>(pr.master, end.facet, x_n));
  const Projection<D> mid = project<D>(x_mid.col(s), facet_nodes<D>(pr.master, end.facet, x_mid));
  Constraint<D> c;
  c.pair = p;
  c.slave = s;
  c.kind = pr.kind;
  c.facet = end.facet;
  for (int a = 0; a < D; ++a) c.master[a] = pr.master.facets(a, c.facet);
  c.xi = c.kind == Kind::stick ? start.xi : mid.xi;
  c.normal = mid.normal;
  c.tangents = mid.tangents;
  c.gap = start.gap;
  // Behind: pushed out to γ = 0, at zero work if the step's other
  // non-rigid motion can carry it, else by the paper's force (push), whose
  // work the velocity update after the step takes back, a step's share at
  // a time (push_target). The second
  // constraint of a slave on two surfaces has no such force (its pair's
  // forces are always the zero-work ones): it keeps its start gap, and so
  // does a slave whose push-out was given up (given_up_). A slave behind
  // by no more than the search's penetration tolerance (the round-off of
  // the positions: a face met exactly at a step's end) is on its facet:
  // held at γ = 0.
  if (c.kind == Kind::frictionless && start.gap < 0.0 && start.gap >= -pr.search.penetration_tolerance) {
    c.gap = 0.0;
  } else if (c.kind == Kind::frictionless && start.gap < 0.0) {
    if (-start.gap <= push_out(c, x_n, x_np1)) {
      c.gap = 0.0;
    } else if (given_up_[s]) {
      c.hold = true;
    } else if (count_[s] == 0) {
      c.gap = push_target(c, start.gap);
      c.push = true;
    }
  }
  c.activated_step = step_;
  return c;
}

template <int D>
double ActiveSet<D>::push_out(const Constraint<D>& c, const Positions<D>& x_a, const Positions<D>& x_b) const {
  zero_work::Nodes<D, double> y, d;
  auto put = [&](int column, int node) {
    y.col(column) = 0.5 * (x_a.col(node) + x_b.col(node));
    d.col(column) = x_b.col(node) - x_a.col(node);
  };
  put(0, c.slave);
  for (int b = 0; b < D; ++b) put(b + 1, c.master[b]);
  // A push-out alone is met by ā_s·n = 0 (see make_constraint): only the
  // other non-rigid motion, slip and the facet's strain, can take it.
  d.col(0) -= c.normal * c.normal.dot(d.col(0) - d.template rightCols<D>() * facet_shape<D>(c.xi));
  return kPushOut * zero_work::non_rigid_part<D, D + 1, double>(y, d).norm();
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
  std::vector<std::vector<Vec<D>>> normals;
  for (int p = 0; p < collisions_.size(); ++p) {
    collisions_.refit(p, x);
    normals.push_back(node_normals<D>(pair(p).slave, x));
  }
  ActiveGaps gaps{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  for (const Constraint<D>& c : active_) {
    const ContactPair<D>& pr = pair(c.pair);
    const auto i = static_cast<std::size_t>(pr.slave.local_node(c.slave));
    const auto match = collisions_.match(c.pair, i, x, normals[c.pair][i], u_n ? &x_n : nullptr);
    const double gap = match ? match->projection.gap
                             : project<D>(x.col(c.slave), facet_nodes<D>(pr.master, c.facet, x)).gap;
    gaps.min = std::min(gaps.min, gap);
    gaps.max = std::max(gaps.max, gap);
  }
  return gaps;
}

template class ActiveSet<2>;
template class ActiveSet<3>;

}  // namespace conserve::contact
