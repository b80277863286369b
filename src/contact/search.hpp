#pragma once
/// Narrow phase: which master facet a slave point belongs to, with the rules
/// the paper does not give (projections on edges and vertices, convex
/// corners, far-side facets, facet switching; docs/theory.md, "Contact
/// geometry (27)–(29)" and "The step with contact").
#include <optional>

#include "contact/broad_phase.hpp"
#include "contact/curved_facet.hpp"
#include "contact/facet.hpp"
#include "contact/surface.hpp"

namespace conserve::contact {

struct SearchSettings {
  double search_distance = 0.0;  ///< broad-phase radius [m]
  /// A facet counts only while the slave is less than depth_factor × (the
  /// facet's longest edge) behind it: deeper points belong to the far side.
  double depth_factor = 0.5;
  double inside_tolerance = 1e-10;  ///< isoparametric slack for inside()
  /// Isoparametric slack of the surface's border: a slave up to this
  /// fraction of a facet beyond the border of the master surface still
  /// counts as over it. Without it, a slave corner aligned with the
  /// master's border (equal bars, a block on a block) drifts out and back
  /// by round-off and deformation and enters behind the master unseen.
  double border_tolerance = 1e-3;
  /// A slave is activated only when it is more than this behind the master
  /// [m], so that nodes lying on the surface (gap 0 up to round-off) are
  /// not. Set to a round-off multiple of the facet size.
  double penetration_tolerance = 0.0;
};

template <int D>
struct Match {
  int facet = -1;
  Projection<D> projection;  ///< on that facet's plane, ξ not clamped
};

/// Whether a master facet with outward normal n faces the way a slave node
/// with outward normal m does (the slave is on the facet's back side): the
/// two within 60° (n·m > ½). A node normal is an average of its facets'
/// and on a coarse curved slave leans tens of degrees off the surface's, so
/// a facet square to it (a wall beside a ball standing on a floor) is not
/// counted as facing its way.
template <int D>
bool faces_same_way(const Vec<D>& n, const Vec<D>& m) {
  return n.dot(m) > 0.5;
}

/// Positions of the vertices of `surface.facets.col(f)` (its first D
/// nodes: the whole facet if linear, its chord if quadratic) from all
/// positions x.
template <int D>
FacetNodes<D> facet_nodes(const ContactSurface& surface, int f, const Positions<D>& x);

/// Whether the surface's facets are quadratic (3-node lines, 6-node
/// triangles) rather than linear (D nodes).
template <int D>
bool quadratic(const ContactSurface& surface) {
  return surface.facets.rows() != D;
}
/// Positions of all nodes of quadratic facet f.
template <int D>
typename CurvedFacet<D>::Nodes curved_nodes(const ContactSurface& surface, int f, const Positions<D>& x);

/// The shape values N_b(ξ) of a facet of `nodes` nodes (D: linear, else quadratic).
template <int D>
FacetWeights<D> facet_weights(int nodes, const Xi<D>& xi) {
  if (nodes == D) return facet_shape<D>(xi);
  return CurvedFacet<D>::Shape::shape(xi);
}

/// The projection of x_s on facet f of `surface`: on its plane (line) if
/// linear, from `frames` when given (project); on its curved surface if
/// quadratic (project_curved).
template <int D>
Projection<D> project_on(const Vec<D>& x_s, const ContactSurface& surface, int f, const Positions<D>& x,
                         FacetFrames<D>* frames = nullptr);

/// The master facet of x_s: among the tree's candidates, discard far-side
/// facets (see SearchSettings) and those that face the way the slave's
/// outward normal `slave_normal` does (if given, faces_same_way); of the
/// rest, the facet whose closed triangle/segment is nearest: one x_s
/// projects inside (smallest |gap|) unless one it projects outside of is
/// nearer (behind a convex edge), ties among those going to the one whose
/// normal is best aligned with x_s − its nearest point. std::nullopt if no
/// facet qualifies.
/// `exclude` (sorted node numbers, self-contact): facets with one of these
/// nodes are skipped.
template <int D>
std::optional<Match<D>> find_master(const Vec<D>& x_s, const ContactSurface& surface, const FacetTree<D>& tree,
                                    const Positions<D>& x, const SearchSettings& settings,
                                    const std::optional<Vec<D>>& slave_normal = std::nullopt,
                                    FacetFrames<D>* frames = nullptr, const std::vector<int>* exclude = nullptr);

/// Self-contact: node `node` of `surface` and its neighbours (the nodes of
/// the facets at it), sorted: the facets a node of a surface against
/// itself may not be held on.
std::vector<int> near_nodes(const ContactSurface& surface, int node);
/// Whether facet f of `surface` has one of the (sorted) `nodes`.
bool has_any(const ContactSurface& surface, int f, const std::vector<int>& nodes);

/// Whether x_s, matched to `m` by find_master (surface at positions x),
/// lies over the surface: its projection is inside the facet up to `tol`
/// (isoparametric), or a walk across the edges it leaves by (as follow()
/// walks) reaches a facet it projects inside or circles a convex edge or
/// vertex, without leaving a facet across the surface's border by more
/// than `tol`.
template <int D>
bool over_surface(const Vec<D>& x_s, const Match<D>& m, const ContactSurface& surface, const Positions<D>& x,
                  double tol);

/// Re-projects x_s on its current facet; if the projection has left the
/// facet and lands inside a neighbouring facet (across the edge it left by),
/// moves there (repeatedly, bounded by the number of facets); otherwise keeps
/// the facet and extrapolates. "Left by" is the most negative barycentric
/// coordinate (1 − Σξ, ξ[, η]). The walk crosses exit edges tentatively and
/// never revisits a facet: it ends on the first facet where the projection is
/// inside, or, if it meets the border or a revisit first, on `current`. Given
/// the slave's outward normal `slave_normal`, a facet that faces its way
/// (faces_same_way) is a border too, as find_master discards it: a slave on the rim
/// of one body pressed against the side of another does not walk round the
/// other's convex edge onto its top face, which faces the way it does.
template <int D>
Match<D> follow(const Vec<D>& x_s, const Match<D>& current, const ContactSurface& surface, const Positions<D>& x,
                double inside_tolerance = 1e-10, const Vec<D>* slave_normal = nullptr);

/// Outward unit normal at each surface node (the facets' normals at the
/// node weighted by the facets' (chords') areas), aligned with
/// surface.nodes.
template <int D>
std::vector<Vec<D>> node_normals(const ContactSurface& surface, const Positions<D>& x);
/// The same at surface node surface.nodes[i] alone.
template <int D>
Vec<D> node_normal(const ContactSurface& surface, std::size_t i, const Positions<D>& x);

}  // namespace conserve::contact
