#include "contact/collision_set.hpp"

#include <algorithm>

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
  const Projection<D> start = project<D>(x_n.col(s), facet_nodes<D>(pair.master, end.facet, x_n));
  if (!(start.gap >= 0.0) || !(end.projection.gap < start.gap)) return false;
  const double at = start.gap / (start.gap - end.projection.gap);
  const FacetNodes<D> facet = facet_nodes<D>(pair.master, end.facet, x);
  const Vec<D> crossing = facet * facet_shape<D>(start.xi + at * (end.projection.xi - start.xi));
  return over_surface<D>(crossing, Match<D>{end.facet, project<D>(crossing, facet)}, pair.master, x,
                         pair.search.border_tolerance);
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
}

template <int D>
std::optional<Match<D>> CollisionSet<D>::match_in(const ContactPair<D>& pair, std::size_t i, const Positions<D>& x,
                                                  const Vec<D>& slave_normal, const Positions<D>* x_n) {
  const int s = pair.slave.nodes[i];
  const std::vector<int> near = pair.self ? near_nodes(pair.master, s) : std::vector<int>{};
  const auto match = find_master<D>(x.col(s), pair.master, pair.tree, x, pair.search, slave_normal, &pair.frames,
                                    pair.self ? &near : nullptr);
  if (!match) return std::nullopt;
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
Penetration CollisionSet<D>::master_penetration(const Positions<D>& x, const Positions<D>& x_n) {
  Penetration deepest;
  std::vector<std::size_t> near;
  for (ContactPair<D>& r : reversed_) {
    near_slaves(r, x, near);
    if (near.empty()) continue;
    r.refit(x);
    const std::vector<Vec<D>> normals = node_normals<D>(r.slave, x);
    for (const std::size_t i : near)
      if (const auto m = match_in(r, i, x, normals[i], &x_n); m && -m->projection.gap > deepest.depth)
        deepest = {-m->projection.gap, r.slave.nodes[i]};
  }
  return deepest;
}

template <int D>
double CollisionSet<D>::facet_size(int p, int slave) const {
  return facet_size_[static_cast<std::size_t>(p)][static_cast<std::size_t>(pair(p).slave.local_node(slave))];
}

template class CollisionSet<2>;
template class CollisionSet<3>;

}  // namespace conserve::contact
