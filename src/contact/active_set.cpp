#include "contact/active_set.hpp"

#include <algorithm>

namespace conserve::contact {

template <int D>
ActiveSet<D>::ActiveSet(const model::Model<D>& model, std::vector<ContactPair<D>> pairs)
    : model_(model),
      pairs_(std::move(pairs)),
      is_active_(model.num_nodes(), 0),
      released_(model.num_nodes(), 0),
      prescribed_(model.num_nodes(), 0) {
  for (int d : model.prescribed.dofs) prescribed_[d / D] = 1;
  const Positions<D> x = model.X;
  for (auto& pair : pairs_) pair.tree.build(pair.master.facets, x);
}

template <int D>
void ActiveSet<D>::set_constraints(std::vector<Constraint<D>> constraints) {
  const bool same_set = constraints.size() == active_.size() &&
                        std::equal(constraints.begin(), constraints.end(), active_.begin(),
                                   [](const Constraint<D>& a, const Constraint<D>& b) { return a.slave == b.slave; });
  active_ = std::move(constraints);
  if (same_set) return;  // the same slaves (the solve's own updates): flags and forces stand
  std::fill(is_active_.begin(), is_active_.end(), 0);
  for (const Constraint<D>& c : active_) is_active_[c.slave] = 1;
  normal_forces_.assign(active_.size(), 0.0);
}

template <int D>
Positions<D> ActiveSet<D>::positions(const Eigen::VectorXd& u) const {
  return model_.X + u.reshaped(D, model_.num_nodes());
}

/// A match counts for activation if its projection lies inside the facet
/// or leaves it only across edges shared with another facet of the surface
/// (a convex corner); a point beyond the surface's border is not in contact.
template <int D>
bool within_surface(const ContactSurface& surface, const Match<D>& m, double tol) {
  if (m.projection.inside(tol)) return true;
  const Vec<D> N = facet_shape<D>(m.projection.xi);
  for (int k = 0; k < D; ++k)
    if (N(k) < -tol && surface.facet_neighbours(k, m.facet) < 0) return false;
  return true;
}

template <int D>
bool ActiveSet<D>::update(const Eigen::VectorXd& u_n, const Eigen::VectorXd& u_np1, const Eigen::VectorXd& g,
                          StepContactStats& stats) {
  ++stats.passes;
  const Positions<D> x_n = positions(u_n), x_np1 = positions(u_np1);
  const Positions<D> x_mid = 0.5 * (x_n + x_np1);
  const bool released = release_tensile(x_mid, g, stats);
  const bool activated = activate_penetrating(x_n, x_np1, stats);
  return released || activated;
}

// (46), (65): keep the constraint while f_N = g_s·n_{n+½} ≥ 0.
template <int D>
bool ActiveSet<D>::release_tensile(const Positions<D>& x_mid, const Eigen::VectorXd& g, StepContactStats& stats) {
  std::vector<Constraint<D>> kept;
  normal_forces_.clear();
  for (Constraint<D>& c : active_) {
    FacetNodes<D> xm;
    for (int a = 0; a < D; ++a) xm.col(a) = x_mid.col(c.master[a]);
    c.normal = facet_normal<D>(xm);
    const double f_n = g.template segment<D>(c.slave * D).dot(c.normal);
    if (f_n < 0.0) {
      is_active_[c.slave] = 0;
      released_[c.slave] = 1;
      ++stats.releases;
      continue;
    }
    kept.push_back(c);
    normal_forces_.push_back(f_n);
  }
  const bool changed = kept.size() != active_.size();
  active_ = std::move(kept);
  return changed;
}

template <int D>
bool ActiveSet<D>::activate_penetrating(const Positions<D>& x_n, const Positions<D>& x_np1, StepContactStats& stats) {
  const Positions<D> x_mid = 0.5 * (x_n + x_np1);
  bool changed = false;
  for (int p = 0; p < static_cast<int>(pairs_.size()); ++p) {
    ContactPair<D>& pair = pairs_[p];
    pair.tree.refit(x_np1);
    const std::vector<Vec<D>> normals = node_normals<D>(pair.slave, x_np1);
    for (std::size_t i = 0; i < pair.slave.nodes.size(); ++i) {
      const int s = pair.slave.nodes[i];
      if (is_active_[s] || released_[s] || prescribed_[s]) continue;
      const auto match = find_master<D>(x_np1.col(s), pair.master, pair.tree, x_np1, pair.search, normals[i]);
      if (!match || match->projection.gap >= -pair.search.penetration_tolerance) continue;
      if (!within_surface<D>(pair.master, *match, pair.search.inside_tolerance)) continue;
      // ξ̄ and n from the mid-point configuration of this solve (§5, §7).
      Match<D> mid = *match;
      mid.projection = project<D>(x_mid.col(s), facet_nodes<D>(pair.master, mid.facet, x_mid));
      mid = follow<D>(x_mid.col(s), mid, pair.master, x_mid, pair.search.inside_tolerance);
      Constraint<D> c;
      c.pair = p;
      c.slave = s;
      c.facet = mid.facet;
      for (int a = 0; a < D; ++a) c.master[a] = pair.master.facets(a, mid.facet);
      c.xi = mid.projection.xi;
      c.normal = mid.projection.normal;
      c.tangents = mid.projection.tangents;
      c.kind = pair.kind;
      c.activation_gap = project<D>(x_n.col(s), facet_nodes<D>(pair.master, mid.facet, x_n)).gap;
      stats.max_activation_gap = std::max(stats.max_activation_gap, c.activation_gap);
      ++stats.activations;
      is_active_[s] = 1;
      active_.push_back(c);
      normal_forces_.push_back(0.0);
      changed = true;
    }
  }
  return changed;
}

template class ActiveSet<2>;
template class ActiveSet<3>;

}  // namespace conserve::contact
