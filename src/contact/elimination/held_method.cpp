#include "contact/elimination/held_method.hpp"

#include <map>

#include "core/bytes.hpp"

namespace conserve::contact {
namespace {

template <int D>
void write_constraint(ByteWriter& w, const Constraint<D>& c) {
  w.value(static_cast<std::int32_t>(c.pair));
  w.value(static_cast<std::int32_t>(c.slave));
  w.value(static_cast<std::int32_t>(c.facet));
  for (int m : c.master) w.value(static_cast<std::int32_t>(m));
  w.doubles(c.xi.data(), c.xi.size());
  w.doubles(c.normal.data(), c.normal.size());
  w.doubles(c.tangents.data(), c.tangents.size());
  w.value(static_cast<std::int32_t>(c.kind));
  w.value(c.gap);
  w.value(static_cast<std::int64_t>(c.activated_step));
  w.value(c.normal_force);
  w.value(c.start_force);
  w.value(static_cast<std::int32_t>(c.hold));
  w.value(c.friction);
  w.value(c.slip_scale);
}

/// A constraint as write_constraint wrote it: its master facet has as many
/// nodes as its pair's master surface's facets (D, or NF if quadratic).
template <int D>
Constraint<D> read_constraint(ByteReader& r, int num_nodes, const std::vector<ContactPair<D>>& pairs) {
  const int num_pairs = static_cast<int>(pairs.size());
  Constraint<D> c;
  c.pair = r.template value<std::int32_t>();
  c.slave = r.template value<std::int32_t>();
  c.facet = r.template value<std::int32_t>();
  if (c.pair < 0 || c.pair >= num_pairs) r.fail("a contact constraint is malformed (an unknown pair)");
  c.master.resize(static_cast<int>(pairs[static_cast<std::size_t>(c.pair)].master.facets.rows()));
  for (int& m : c.master) m = r.template value<std::int32_t>();
  r.doubles(c.xi.data(), c.xi.size(), "a constraint's ξ");
  r.doubles(c.normal.data(), c.normal.size(), "a constraint's normal");
  r.doubles(c.tangents.data(), c.tangents.size(), "a constraint's tangents");
  const auto kind = r.template value<std::int32_t>();
  c.gap = r.template value<double>();
  c.activated_step = r.template value<std::int64_t>();
  c.normal_force = r.template value<double>();
  c.start_force = r.template value<double>();
  const auto hold = r.template value<std::int32_t>();
  c.friction = r.template value<double>();
  c.slip_scale = r.template value<double>();
  bool nodes_ok = c.slave >= 0 && c.slave < num_nodes;
  for (int m : c.master) nodes_ok = nodes_ok && m >= 0 && m < num_nodes;
  if (!nodes_ok || (kind != 0 && kind != 1) || (hold != 0 && hold != 1) || !(c.friction >= 0.0) ||
      !(c.slip_scale >= 0.0) || (c.friction > 0.0 && !(c.slip_scale > 0.0)))
    r.fail("a contact constraint is malformed (a node out of range, or an unknown kind, flag or friction)");
  c.kind = static_cast<Kind>(kind);
  c.hold = hold == 1;
  return c;
}

}  // namespace

template <int D>
HeldMethod<D>::HeldMethod(const model::Model<D>& model, const SparseMatrix& mass,
                                        std::vector<ContactPair<D>> pairs, const ImpactLocation& location,
                                        bool persistent)
    : model_(model), active_(model, std::move(pairs)), restorer_(model, mass) {
  if (persistent) persistent_.emplace(model, mass);
  active_.locate_impacts(location);
  reduction_->set_owned(model.first_owned(), model.end_owned());
}

template <int D>
void HeldMethod<D>::begin_step(std::int64_t step, double dt, const model::State& start) {
  active_.begin_step(step, start.time, dt, start.v);
  end_time_ = start.time + dt;
  dt_ = dt;
  counts_ = {};
}

template <int D>
bool HeldMethod<D>::recover(const Eigen::VectorXd& u_n) {
  return active_.stick_slipping(model_.X + u_n.reshaped(D, model_.X.cols()));
}

template <int D>
Verdict HeldMethod<D>::settle(const model::State& start, double dt, const Eigen::VectorXd& u_np1,
                                     const Eigen::VectorXd& g, Eigen::VectorXd& v_np1, StepContactStats& stats) {
  const SetChange change = active_.update(start.u, u_np1, g, stats, counts_);
  if (change == SetChange::split) return Verdict::split;
  if (change == SetChange::changed) return Verdict::changed;
  counts_.push_work = 0.0;
  friction(start.u, u_np1, stats);
  if (counts_.pushes == 0) return Verdict::accept;
  // The step's energy error E_{n+1} − E_n is Δu·g over the free dofs (the
  // zero-work forces contribute nothing, Newton's leftover its round-off):
  // here the push-outs' work, and the friction's (−dissipated).
  Eigen::VectorXd g_free = g;
  for (int d : model_.prescribed.dofs) g_free[d] = 0.0;
  const double push_work = (u_np1 - start.u).dot(g_free) + stats.dissipated;
  const Positions<D> x = model_.X + u_np1.reshaped(D, model_.X.cols());
  v_np1 = (2.0 / dt) * (u_np1 - start.u) - start.v;  // (19)
  if (restorer_.restore_energy(x, push_work, v_np1)) {
    counts_.push_work = push_work;
    return Verdict::accept;
  }
  // More than the bodies' deformation velocity holds, at this Δt and (the
  // work grows as the push-out's speed squared) any shorter one: the
  // slaves are held where they started instead.
  active_.hold_pushes(start.u);  // counted in HeldCounts::pushes_given_up by the next update
  v_np1.resize(0);
  return Verdict::changed;
}

template <int D>
void HeldMethod<D>::friction(const Eigen::VectorXd& u_n, const Eigen::VectorXd& u_np1, StepContactStats& stats) const {
  stats.dissipated = 0.0;
  stats.sticking = stats.slipping = 0;
  const Positions<D> x_n = model_.X + u_n.reshaped(D, model_.X.cols());
  const Positions<D> x_np1 = model_.X + u_np1.reshaped(D, model_.X.cols());
  for (const Constraint<D>& c : active_.constraints()) {
    if (!active_.pairs()[static_cast<std::size_t>(c.pair)].friction) continue;
    if (c.kind == Kind::stick) {
      ++stats.sticking;
      continue;
    }
    ++stats.slipping;
    if (c.friction > 0.0) stats.dissipated += friction_step<D>(c, x_n, x_np1).dissipated;
  }
}

template <int D>
void HeldMethod<D>::finish_step(const Eigen::VectorXd& u_n, const Eigen::VectorXd& u_np1,
                                       Eigen::VectorXd& v_np1, StepContactStats& stats) {
  active_.end_step(end_time_);
  stats.master_penetration = active_.master_penetration(u_np1, u_n).depth;
  const auto& constraints = active_.constraints();
  const auto& normal = active_.normal_forces();
  std::vector<SlaveImpulse<D>> impulses(constraints.size());
  const Positions<D> x = model_.X + u_np1.reshaped(D, model_.X.cols());
  if (persistent_ && !constraints.empty())
    counts_.velocity = persistent_->apply(constraints, active_.pairs(), x, v_np1, &impulses);
  forces_.clear();
  for (std::size_t i = 0; i < constraints.size(); ++i) {
    const Constraint<D>& c = constraints[i];
    const Vec<D> step = (u_np1 - u_n).template segment<D>(c.slave * D);
    forces_.push_back({.slave = c.slave,
                       .normal = normal[i],
                       .direction = c.normal,
                       .pair = c.pair,
                       .sticks = c.kind == Kind::stick,
                       .force = c.force,
                       .moment = moment_of<D>(c.mid, c.force),
                       .work = c.force.dot(step),
                       .impulse = impulses[i].impulse,
                       .master = c.master,
                       .weights = impulses[i].weights});
  }
  stats.own = held_values(counts_);
}

template <int D>
std::string HeldMethod<D>::save() const {
  ByteWriter w;
  w.value(static_cast<std::uint64_t>(active_.constraints().size()));
  for (const auto& c : active_.constraints()) write_constraint<D>(w, c);
  w.doubles(active_.release_times().data(), active_.release_times().size());
  w.doubles(active_.activation_times().data(), active_.activation_times().size());
  return w.bytes();
}

template <int D>
void HeldMethod<D>::load(const std::string& bytes, const std::string& what) {
  forces_.clear();
  ByteReader r(bytes, what);
  const auto count = r.value<std::uint64_t>();
  if (count > static_cast<std::uint64_t>(model_.num_nodes())) r.fail("more constraints than nodes");
  std::vector<Constraint<D>> constraints;
  for (std::uint64_t i = 0; i < count; ++i)
    constraints.push_back(read_constraint<D>(r, model_.num_nodes(), active_.pairs()));
  std::vector<double> releases(active_.release_times().size()), activations(active_.activation_times().size());
  r.doubles(releases.data(), releases.size(), "the slaves' release times");
  r.doubles(activations.data(), activations.size(), "the pairs' activation times");
  if (!r.at_end()) r.fail("trailing bytes after the constraints");
  active_.set_constraints(std::move(constraints));
  active_.set_event_times(std::move(releases), std::move(activations));
}

// After a restart, the loaded constraints' normal forces alone (until the next step).
template <int D>
std::vector<ContactForce<D>> HeldMethod<D>::contact_forces() const {
  const auto& constraints = active_.constraints();
  if (forces_.size() == constraints.size()) return forces_;
  std::vector<ContactForce<D>> forces;
  const auto& normal = active_.normal_forces();
  for (std::size_t i = 0; i < constraints.size(); ++i)
    forces.push_back({.slave = constraints[i].slave,
                      .normal = normal[i],
                      .direction = constraints[i].normal,
                      .pair = constraints[i].pair,
                      .sticks = constraints[i].kind == Kind::stick,
                      .force = normal[i] * constraints[i].normal});
  return forces;
}

template class HeldMethod<2>;
template class HeldMethod<3>;

}  // namespace conserve::contact
