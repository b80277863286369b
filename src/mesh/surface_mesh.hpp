#pragma once
/// Bare surfaces: meshes without cells, made only of facets (3-node
/// triangles in 3D, 2-node segments in 2D), the master surfaces of rigid
/// bodies. Their facets' node order is their orientation: the normal is
/// the right-hand rule's (x1 − x0) × (x2 − x0) in 3D and (t_y, −t_x) for
/// the tangent t = x1 − x0 in 2D, as for boundary_facets() and
/// contact::facet_normal, and it points to the side where the slaves belong.
#include <Eigen/Core>
#include <optional>
#include <string>

#include "mesh/mesh.hpp"

namespace conserve::mesh {

/// A mesh without cells made of `facets` (dim × n, node indices into
/// `points`, dim × n_nodes): empty cell group "body", facet groups
/// "surface" and "boundary" both holding every facet.
Mesh bare_surface(int dim, Eigen::MatrixXd points, Eigen::MatrixXi facets);

/// Reverses every facet of every facet group (3D: swaps vertices 1 and 2,
/// and of a 6-node triangle the midside nodes 3 and 5; 2D: swaps the two
/// ends): the normals then point the other way.
void flip_normals(Mesh& mesh);

/// Two facets whose shared side runs the same way in both, which a
/// consistently oriented surface never has: in 3D both traverse the edge
/// from node `from` to node `to`; in 2D both start (`to` = −1) or both end
/// (`from` = −1) at the shared node.
struct OrientationClash {
  int first = -1;   ///< the earlier facet (column)
  int second = -1;  ///< the later facet (column)
  int from = -1, to = -1;
};

/// The first clash in facet order (the smallest `second`), or none when
/// every side shared by two facets is traversed once in each direction. A
/// side shared by three or more facets always clashes (no orientation makes
/// such a junction consistent). `facets`: dim × n, dim = 2 or 3.
std::optional<OrientationClash> orientation_clash(const Eigen::MatrixXi& facets);

/// The first facet with a repeated node or (nearly) no extent: area
/// ≤ 1e-12 · (longest edge)² in 3D, length ≤ 1e-12 · the bounding box's
/// diagonal in 2D; or none. `points`: dim × n_nodes.
std::optional<int> degenerate_facet(const Eigen::MatrixXd& points, const Eigen::MatrixXi& facets);

/// What `conserve check` states about a bare surface's orientation.
struct SurfaceSummary {
  int dim = 3;
  int facets = 0;
  int pieces = 0;        ///< connected components (through shared nodes)
  bool closed = false;   ///< every side is shared by two facets
  double measure = 0.0;  ///< total area [m²] (length [m] in 2D)
  /// Σ n dA / Σ dA: the area-weighted mean unit normal (3 components, z = 0 in 2D).
  Eigen::Vector3d mean_normal = Eigen::Vector3d::Zero();
  /// Σ (1/dim) x·n dA: with `closed`, the enclosed volume [m³] (area [m²] in
  /// 2D), positive when the normals point outward.
  double enclosed = 0.0;
};

SurfaceSummary summarize_surface(const Eigen::MatrixXd& points, const Eigen::MatrixXi& facets);

/// One line: "surface of 120 triangles, normals point mostly +z
/// (area-weighted mean normal (0.00, 0.01, 0.99)): the slaves belong on that
/// side", or for a closed surface "closed surface of 320 triangles, normals
/// point outward (enclosing 4.19 m³): the slaves belong outside".
std::string describe_surface(const SurfaceSummary& s);

}  // namespace conserve::mesh
