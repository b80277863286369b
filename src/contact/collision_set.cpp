#include "contact/collision_set.hpp"

#include <algorithm>
#include <array>
#include <map>
#include <numeric>
#include <string>

namespace conserve::contact {
namespace {

/// Per node of `surface` (aligned with surface.nodes): the longest edge of
/// the facets at it, at positions x [m].
template <int D>
std::vector<double> longest_edges(const ContactSurface& surface, const Positions<D>& x) {
  const std::vector<double> facet = facet_sizes<D>(surface, x);
  std::vector<double> size(surface.nodes.size(), 0.0);
  for (std::size_t i = 0; i < surface.nodes.size(); ++i)
    for (int f : surface.node_facets[i]) size[i] = std::max(size[i], facet[static_cast<std::size_t>(f)]);
  return size;
}

/// `pair` the other way round: its master surface's nodes searched against
/// its slave surface's facets by the same rules, the broad phase's radius
/// from the slave facets' longest edge (as make_contact_pairs sets it from
/// the master's).
template <int D>
ContactPair<D> reversed(const ContactPair<D>& pair, const Positions<D>& x) {
  ContactPair<D> r;
  r.slave = pair.master;
  r.master = pair.slave;
  r.kind = pair.kind;
  r.self = pair.self;
  r.search = pair.search;
  const std::vector<double> edges = facet_sizes<D>(r.master, x);
  const double longest = edges.empty() ? 0.0 : *std::max_element(edges.begin(), edges.end());
  r.search.search_distance = r.search.depth_factor * longest;
  r.tree.build(r.master.facets, x);
  return r;
}

/// Whether slave s, behind facet `end.facet` at the end of the step (x)
/// but beyond the surface's border there, entered through the surface: it
/// was not behind that facet's plane at the start of the step (x_n), and
/// the point where its straight path crossed the plane (ξ interpolated
/// linearly at the gap's zero) lies over the surface. A slave level with
/// the border (the bottom rims of two rings standing on one plane) has its
/// projection pushed beyond a tilted border facet by any penetration, and
/// would sink unseen; one passing beside the master crosses the plane
/// beyond the border and is left alone.
template <int D>
bool entered_through(const ContactPair<D>& pair, int s, const Match<D>& end, const Positions<D>& x_n,
                     const Positions<D>& x) {
  const Projection<D> start = project_on<D>(x_n.col(s), pair.master, end.facet, x_n);
  if (!(start.gap >= 0.0) || !(end.projection.gap < start.gap)) return false;
  const double at = start.gap / (start.gap - end.projection.gap);
  const Xi<D> xi = start.xi + at * (end.projection.xi - start.xi);
  Vec<D> crossing = Vec<D>::Zero();
  const FacetWeights<D> N = facet_weights<D>(static_cast<int>(pair.master.facets.rows()), xi);
  for (Eigen::Index b = 0; b < N.size(); ++b) crossing += N(b) * x.col(pair.master.facets(b, end.facet));
  return over_surface<D>(crossing, Match<D>{end.facet, project_on<D>(crossing, pair.master, end.facet, x)},
                         pair.master, x, pair.search.border_tolerance);
}

}  // namespace

template <int D>
CollisionSet<D>::CollisionSet(const model::Model<D>& model, std::vector<ContactPair<D>> pairs)
    : pairs_(std::move(pairs)), prescribed_(static_cast<std::size_t>(model.num_nodes()), 0) {
  for (int d : model.held_dofs()) prescribed_[static_cast<std::size_t>(d / D)] = 1;
  const Positions<D> x = model.X;
  for (auto& pair : pairs_) {
    pair.tree.build(pair.master.facets, x);
    facet_size_.push_back(longest_edges<D>(pair.slave, x));
    reversed_.push_back(reversed<D>(pair, x));
  }
  std::map<std::string, int> id;
  auto surface = [&](const ContactSurface& s) {
    const auto [it, fresh] = id.emplace(s.name, static_cast<int>(surface_nodes_.size()));
    if (fresh) {
      surface_nodes_.push_back(s.nodes);
      surface_margin_.push_back(0.0);
    }
    return it->second;
  };
  std::vector<std::array<int, 2>> ids;
  for (std::size_t p = 0; p < pairs_.size(); ++p) {
    const int slave = surface(pairs_[p].slave), master = surface(pairs_[p].master);
    double& m = surface_margin_[static_cast<std::size_t>(master)];
    m = std::max(m, pairs_[p].search.search_distance);
    double& r = surface_margin_[static_cast<std::size_t>(slave)];
    r = std::max(r, reversed_[p].search.search_distance);
    ids.push_back({slave, master});
  }
  for (std::size_t p = 0; p < pairs_.size(); ++p)
    between_[static_cast<std::size_t>(ids[p][0]) * surface_nodes_.size() + static_cast<std::size_t>(ids[p][1])]
        .push_back(static_cast<int>(p));
}

template <int D>
void CollisionSet<D>::candidates(const Positions<D>& x, std::vector<int>& out) const {
  out.clear();
  const std::size_t n = surface_nodes_.size();
  std::vector<Eigen::AlignedBox<double, D>> box(n);
  Eigen::AlignedBox<double, D> centres;
  for (std::size_t s = 0; s < n; ++s) {
    for (const int node : surface_nodes_[s]) box[s].extend(x.col(node));
    box[s].min().array() -= surface_margin_[s];
    box[s].max().array() += surface_margin_[s];
    centres.extend(box[s].center());
  }
  int axis = 0;
  (centres.max() - centres.min()).maxCoeff(&axis);
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return box[a].min()(axis) < box[b].min()(axis); });
  auto add = [&](int slave, int master) {
    const auto it = between_.find(static_cast<std::size_t>(slave) * n + static_cast<std::size_t>(master));
    if (it != between_.end()) out.insert(out.end(), it->second.begin(), it->second.end());
  };
  std::vector<int> open;  // surfaces whose extent along the axis reaches the sweep's position
  for (const int s : order) {
    const double at = box[static_cast<std::size_t>(s)].min()(axis);
    std::erase_if(open, [&](int o) { return box[static_cast<std::size_t>(o)].max()(axis) < at; });
    for (const int o : open)
      if (box[static_cast<std::size_t>(o)].intersects(box[static_cast<std::size_t>(s)])) add(o, s), add(s, o);
    add(s, s);
    open.push_back(s);
  }
  std::sort(out.begin(), out.end());
}

template <int D>
std::optional<Match<D>> CollisionSet<D>::match_in(const ContactPair<D>& pair, std::size_t i, const Positions<D>& x,
                                                  const Vec<D>& slave_normal, const Positions<D>* x_n) {
  const int s = pair.slave.nodes[i];
  const std::vector<int> near = pair.self ? near_nodes(pair.master, s) : std::vector<int>{};
  const auto match = find_master<D>(x.col(s), pair.master, pair.tree, x, pair.search, slave_normal, &pair.frames,
                                    pair.self ? &near : nullptr);
  if (!match) return std::nullopt;
  if (pair.self) {
    // Every node of a body lies behind its own far facets by the body's
    // thickness (a thin plate's bottom behind its top): against its own
    // surface a node counts only if it came to the facet from in front,
    // in front of it at the step's start. Without a start, no match.
    if (!x_n) return std::nullopt;
    const Projection<D> start = project<D>(x_n->col(s), facet_nodes<D>(pair.master, match->facet, *x_n));
    if (!(start.gap >= -pair.search.penetration_tolerance)) return std::nullopt;
  }
  if (over_surface<D>(x.col(s), *match, pair.master, x, pair.search.border_tolerance)) return match;
  if (x_n && entered_through<D>(pair, s, *match, *x_n, x)) return match;
  return std::nullopt;
}

template <int D>
void CollisionSet<D>::near_slaves(const ContactPair<D>& pair, const Positions<D>& x, std::vector<std::size_t>& out) {
  out.clear();
  Eigen::AlignedBox<double, D> box;
  for (const int n : pair.master.nodes) box.extend(x.col(n));
  if (box.isEmpty()) return;
  const double margin = pair.search.search_distance;
  box.min().array() -= margin;
  box.max().array() += margin;
  for (std::size_t i = 0; i < pair.slave.nodes.size(); ++i)
    if (box.contains(x.col(pair.slave.nodes[i]))) out.push_back(i);
}

template <int D>
Penetration CollisionSet<D>::slave_penetration(const Positions<D>& x, const Positions<D>* x_n) {
  Penetration deepest;
  for_each_match(
      x,
      [&](int, std::size_t, int s, const Match<D>& m) {
        if (-m.projection.gap > deepest.depth) deepest = {-m.projection.gap, s};
      },
      x_n);
  return deepest;
}

template <int D>
template <class Visit>
void CollisionSet<D>::for_each_reversed_match(const Positions<D>& x, Visit&& visit, const Positions<D>* x_n) {
  std::vector<std::size_t> near;
  candidates(x, candidates_);
  for (const int p : candidates_) {
    ContactPair<D>& r = reversed_[static_cast<std::size_t>(p)];
    near_slaves(r, x, near);
    if (near.empty()) continue;
    r.refit(x);
    const std::vector<Vec<D>> normals = node_normals<D>(r.slave, x);
    for (const std::size_t i : near)
      if (const auto m = match_in(r, i, x, normals[i], x_n)) visit(p, r.slave.nodes[i], *m);
  }
}

template <int D>
Penetration CollisionSet<D>::master_penetration(const Positions<D>& x, const Positions<D>& x_n) {
  Penetration deepest;
  for_each_reversed_match(
      x,
      [&](int, int node, const Match<D>& m) {
        if (-m.projection.gap > deepest.depth) deepest = {-m.projection.gap, node};
      },
      &x_n);
  return deepest;
}

template <int D>
std::vector<typename CollisionSet<D>::PairPenetration> CollisionSet<D>::pair_penetrations(const Positions<D>& x,
                                                                                          const Positions<D>* x_n) {
  std::vector<PairPenetration> depth(pairs_.size());
  for_each_match(
      x,
      [&](int p, std::size_t, int s, const Match<D>& m) {
        Penetration& d = depth[static_cast<std::size_t>(p)].slave;
        if (-m.projection.gap > d.depth) d = {-m.projection.gap, s};
      },
      x_n);
  for_each_reversed_match(
      x,
      [&](int p, int node, const Match<D>& m) {
        Penetration& d = depth[static_cast<std::size_t>(p)].master;
        if (-m.projection.gap > d.depth) d = {-m.projection.gap, node};
      },
      x_n);
  return depth;
}

template <int D>
double CollisionSet<D>::facet_size(int p, int slave) const {
  return facet_size_[static_cast<std::size_t>(p)][static_cast<std::size_t>(pair(p).slave.local_node(slave))];
}

template class CollisionSet<2>;
template class CollisionSet<3>;

}  // namespace conserve::contact
