#include "contact/search.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace conserve::contact {

namespace {

template <int D>
double longest_edge(const FacetNodes<D>& x) {
  double longest = 0.0;
  for (int a = 0; a < D; ++a)
    for (int b = a + 1; b < D; ++b) longest = std::max(longest, (x.col(a) - x.col(b)).norm());
  return longest;
}

/// The best candidate whose projection is inside its facet: smallest |gap|.
template <int D>
struct InsideChoice {
  std::optional<Match<D>> match;
  void offer(int facet, const Projection<D>& p) {
    if (!match || std::abs(p.gap) < std::abs(match->projection.gap)) match = Match<D>{facet, p};
  }
};

/// The best candidate whose projection is outside its facet: nearest closed
/// facet, ties (within 1e-12 × facet size) to the best aligned normal.
template <int D>
struct NearestChoice {
  std::optional<Match<D>> match;
  double distance = std::numeric_limits<double>::infinity();
  double alignment = -std::numeric_limits<double>::infinity();
  double size = 0.0;

  /// p: x_s's projection on the facet; y, dist: the facet's nearest point and its distance.
  void offer(int facet, const Projection<D>& p, const Vec<D>& x_s, const Vec<D>& y, double dist, double facet_size) {
    const Vec<D> offset = x_s - y;
    const double norm = offset.norm();
    const double align = norm > 0.0 ? offset.dot(p.normal) / norm : 1.0;
    const double tie = 1e-12 * std::max(size, facet_size);
    const bool better = dist < distance - tie || (dist <= distance + tie && align > alignment);
    if (!match || better) {
      match = Match<D>{facet, p};
      distance = dist;
      alignment = align;
      size = facet_size;
    }
  }
};

/// Index of the most negative barycentric coordinate (N_0, …, N_{D−1}) of ξ:
/// the local node opposite the edge (vertex) the projection left by.
template <int D>
int exit_side(const Xi<D>& xi) {
  int k = 0;
  facet_shape<D>(xi).minCoeff(&k);
  return k;
}


/// The point of closed facet f nearest to x_s, given x_s's projection p
/// on it: (point, distance).
template <int D>
std::pair<Vec<D>, double> nearest_point(const Vec<D>& x_s, const ContactSurface& surface, int f,
                                        const Positions<D>& x, const Projection<D>& p) {
  if (quadratic<D>(surface)) {
    const auto [xi, dist, y] = closest_point_on_curved<D>(x_s, curved_nodes<D>(surface, f, x), p);
    return {y, dist};
  }
  const FacetNodes<D> nodes = facet_nodes<D>(surface, f, x);
  const auto [xi, dist] = closest_point_on_facet<D>(x_s, nodes, p);
  return {nodes * facet_shape<D>(xi), dist};
}

}  // namespace

template <int D>
FacetNodes<D> facet_nodes(const ContactSurface& surface, int f, const Positions<D>& x) {
  FacetNodes<D> nodes;
  for (int i = 0; i < D; ++i) nodes.col(i) = x.col(surface.facets(i, f));
  return nodes;
}

template <int D>
typename CurvedFacet<D>::Nodes curved_nodes(const ContactSurface& surface, int f, const Positions<D>& x) {
  typename CurvedFacet<D>::Nodes nodes;
  for (int i = 0; i < CurvedFacet<D>::kNodes; ++i) nodes.col(i) = x.col(surface.facets(i, f));
  return nodes;
}

template <int D>
Projection<D> project_on(const Vec<D>& x_s, const ContactSurface& surface, int f, const Positions<D>& x,
                         FacetFrames<D>* frames) {
  if (quadratic<D>(surface)) return project_curved<D>(x_s, curved_nodes<D>(surface, f, x)).projection;
  const FacetNodes<D> nodes = facet_nodes<D>(surface, f, x);
  return frames ? project<D>(x_s, frames->get(f, nodes)) : project<D>(x_s, nodes);
}

std::vector<int> near_nodes(const ContactSurface& surface, int node) {
  std::vector<int> out{node};
  const int local = surface.local_node(node);
  if (local >= 0)
    for (const int f : surface.node_facets[static_cast<std::size_t>(local)])
      for (Eigen::Index a = 0; a < surface.facets.rows(); ++a) out.push_back(surface.facets(a, f));
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

bool has_any(const ContactSurface& surface, int f, const std::vector<int>& nodes) {
  for (Eigen::Index a = 0; a < surface.facets.rows(); ++a)
    if (std::binary_search(nodes.begin(), nodes.end(), surface.facets(a, f))) return true;
  return false;
}

template <int D>
std::optional<Match<D>> find_master(const Vec<D>& x_s, const ContactSurface& surface, const FacetTree<D>& tree,
                                    const Positions<D>& x, const SearchSettings& settings,
                                    const std::optional<Vec<D>>& slave_normal, FacetFrames<D>* frames,
                                    const std::vector<int>* exclude) {
  std::vector<int> candidates;
  tree.query(x_s, settings.search_distance, candidates);
  InsideChoice<D> inside;
  NearestChoice<D> nearest;
  for (const int f : candidates) {
    if (exclude && has_any(surface, f, *exclude)) continue;
    const Projection<D> p = project_on<D>(x_s, surface, f, x, frames);
    if (slave_normal && faces_same_way(p.normal, *slave_normal)) continue;
    const double size = longest_edge<D>(facet_nodes<D>(surface, f, x));
    if (p.gap < -settings.depth_factor * size) continue;  // far side
    if (p.inside(settings.inside_tolerance)) {
      inside.offer(f, p);
    } else {
      const auto [y, dist] = nearest_point<D>(x_s, surface, f, x, p);
      nearest.offer(f, p, x_s, y, dist, size);
    }
  }
  // The nearest point of the surface: a facet it projects inside unless one
  // it projects outside of is nearer. A point behind a convex edge of a thin
  // body projects outside both facets at the edge and inside the face beyond
  // (a cylinder's top, half its height away): the edge's facets are its own.
  if (inside.match && nearest.match &&
      nearest.distance < std::abs(inside.match->projection.gap) - 1e-12 * nearest.size)
    return nearest.match;
  return inside.match ? inside.match : nearest.match;
}

template <int D>
Match<D> follow(const Vec<D>& x_s, const Match<D>& current, const ContactSurface& surface, const Positions<D>& x,
                double inside_tolerance, const Vec<D>* slave_normal) {
  const Match<D> here{current.facet, project_on<D>(x_s, surface, current.facet, x)};
  // Walk across the edges (vertices) the projection leaves by; accept the
  // first facet where it is inside, else stay on `current`, extrapolated.
  Match<D> walk = here;
  std::vector<int> visited{current.facet};
  for (int step = 0; step < surface.num_facets() && !walk.projection.inside(inside_tolerance); ++step) {
    const int next = surface.facet_neighbours(exit_side<D>(walk.projection.xi), walk.facet);
    if (next < 0 || std::find(visited.begin(), visited.end(), next) != visited.end()) return here;
    visited.push_back(next);
    walk = Match<D>{next, project_on<D>(x_s, surface, next, x)};
    if (slave_normal && faces_same_way(walk.projection.normal, *slave_normal)) return here;
  }
  return walk.projection.inside(inside_tolerance) ? walk : here;
}

// Leaving a facet across an edge it shares is not enough: a point beyond
// a border vertex leaves the facets that touch the border only there
// across shared edges. So walk, as follow() does, across the edges the
// projection leaves by: the point is over the surface if the walk comes to
// a facet it projects inside or back to one it has seen (it circles a
// convex edge or vertex), and beyond it if the walk leaves a facet across
// the border.
template <int D>
bool over_surface(const Vec<D>& x_s, const Match<D>& m, const ContactSurface& surface, const Positions<D>& x,
                  double tol) {
  if (m.projection.inside(tol)) return true;  // most matches: no walk, no allocation
  Match<D> walk = m;
  std::vector<int> visited{m.facet};
  for (int step = 0; step < surface.num_facets(); ++step) {
    if (walk.projection.inside(tol)) return true;
    const Vec<D> N = facet_shape<D>(walk.projection.xi);
    for (int k = 0; k < D; ++k)
      if (N(k) < -tol && surface.facet_neighbours(k, walk.facet) < 0) return false;
    const int next = surface.facet_neighbours(exit_side<D>(walk.projection.xi), walk.facet);
    if (std::find(visited.begin(), visited.end(), next) != visited.end()) return true;
    visited.push_back(next);
    walk = Match<D>{next, project_on<D>(x_s, surface, next, x)};
  }
  return true;
}

template <int D>
Vec<D> node_normal(const ContactSurface& surface, std::size_t i, const Positions<D>& x) {
  Vec<D> normal = Vec<D>::Zero();
  for (const int f : surface.node_facets[i]) {
    const FacetNodes<D> chord = facet_nodes<D>(surface, f, x);
    const Tangents<D> tau = facet_tangents<D>(chord);
    // area (length) × unit normal
    Vec<D> c;
    if constexpr (D == 3)
      c = 0.5 * tau.col(0).cross(tau.col(1));
    else
      c = Vec<2>(tau(1, 0), -tau(0, 0));
    if (quadratic<D>(surface)) {  // the normal at the node, the chord's area
      int a = 0;
      while (surface.facets(a, f) != surface.nodes[i]) ++a;
      c = c.norm() * CurvedFacet<D>::normal(curved_nodes<D>(surface, f, x), CurvedFacet<D>::Shape::node(a));
    }
    normal += c;
  }
  const double norm = normal.norm();
  return norm > 0.0 ? Vec<D>(normal / norm) : normal;
}

template <int D>
std::vector<Vec<D>> node_normals(const ContactSurface& surface, const Positions<D>& x) {
  std::vector<Vec<D>> normals(surface.nodes.size());
  for (std::size_t i = 0; i < surface.nodes.size(); ++i) normals[i] = node_normal<D>(surface, i, x);
  return normals;
}

#define CONSERVE_INSTANTIATE(D)                                                                                      \
  template FacetNodes<D> facet_nodes<D>(const ContactSurface&, int, const Positions<D>&);                            \
  template typename CurvedFacet<D>::Nodes curved_nodes<D>(const ContactSurface&, int, const Positions<D>&);          \
  template Projection<D> project_on<D>(const Vec<D>&, const ContactSurface&, int, const Positions<D>&,              \
                                       FacetFrames<D>*);                                                           \
  template std::optional<Match<D>> find_master<D>(const Vec<D>&, const ContactSurface&, const FacetTree<D>&,         \
                                                  const Positions<D>&, const SearchSettings&,                        \
                                                  const std::optional<Vec<D>>&, FacetFrames<D>*,                     \
                                                  const std::vector<int>*);                                          \
  template Match<D> follow<D>(const Vec<D>&, const Match<D>&, const ContactSurface&, const Positions<D>&, double,    \
                              const Vec<D>*);                                                                        \
  template bool over_surface<D>(const Vec<D>&, const Match<D>&, const ContactSurface&, const Positions<D>&, double); \
  template std::vector<Vec<D>> node_normals<D>(const ContactSurface&, const Positions<D>&);                          \
  template Vec<D> node_normal<D>(const ContactSurface&, std::size_t, const Positions<D>&);
CONSERVE_INSTANTIATE(2)
CONSERVE_INSTANTIATE(3)
#undef CONSERVE_INSTANTIATE

}  // namespace conserve::contact
