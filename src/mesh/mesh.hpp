#pragma once
/// A mesh of simplices with named groups, as read from a Gmsh file or made by
/// a generator: linear (order 1: 3-node triangles in 2D, 4-node tetrahedra in
/// 3D, boundary facets 2-node lines / 3-node triangles) or quadratic (order 2:
/// 6-node triangles / 10-node tetrahedra, facets 3-node lines / 6-node
/// triangles). All cells of a mesh have one order. Nodes are in Gmsh's order,
/// vertices first, so that the first dim+1 rows of a cell (dim of a facet)
/// are always its vertices:
/// - line3: 0, 1 the ends, 2 the middle;
/// - tri6: 3 = (0,1), 4 = (1,2), 5 = (2,0);
/// - tet10: 4 = (0,1), 5 = (1,2), 6 = (2,0), 7 = (3,0), 8 = (3,2), 9 = (3,1).
/// A quadratic cell's midside nodes may lie off the straight edges (a mesh
/// of a curved body puts those of its boundary on the true surface).
#include <Eigen/Core>
#include <map>
#include <string>
#include <vector>

namespace conserve::mesh {

/// Nodes of a simplex cell of dimension `dim` (2, 3) and order 1 or 2:
/// dim+1 (3, 4), or (dim+1)(dim+2)/2 (6, 10).
constexpr int cell_nodes(int dim, int order) { return order == 2 ? (dim + 1) * (dim + 2) / 2 : dim + 1; }

/// Nodes of a boundary facet of a cell of dimension `dim` and order 1 or 2:
/// dim (2, 3), or dim(dim+1)/2 (3, 6).
constexpr int facet_nodes(int dim, int order) { return order == 2 ? dim * (dim + 1) / 2 : dim; }

/// Named set of boundary facets (segments in 2D, triangles in 3D).
struct FacetGroup {
  /// facet_nodes(dim, order) × n_facets node indices (0-based, into Mesh::points).
  Eigen::MatrixXi facets;
};

/// A simplex mesh. Node and cell indices are 0-based and contiguous.
struct Mesh {
  int dim = 3;  ///< spatial and cell dimension, 2 or 3
  /// dim × n_nodes reference coordinates [m] (midside nodes included).
  Eigen::MatrixXd points;
  /// cell_nodes(dim, order) × n_cells node indices; cells are positively
  /// oriented (positive Jacobian determinant).
  Eigen::MatrixXi cells;
  /// Named volume (3D) / surface (2D) physical groups: cell indices.
  std::map<std::string, std::vector<int>> cell_groups;
  /// Named boundary physical groups.
  std::map<std::string, FacetGroup> facet_groups;

  [[nodiscard]] int num_nodes() const { return static_cast<int>(points.cols()); }
  [[nodiscard]] int num_cells() const { return static_cast<int>(cells.cols()); }

  /// 1 or 2, from the rows of `cells`; for a mesh without cells (a bare
  /// surface, always linear so far) from the rows of its facet groups.
  /// Derived, never stored, so that it cannot disagree with the arrays.
  [[nodiscard]] int order() const {
    if (cells.rows() == cell_nodes(dim, 2)) return 2;
    if (cells.cols() > 0) return 1;
    for (const auto& [name, group] : facet_groups)
      if (group.facets.cols() > 0) return group.facets.rows() == facet_nodes(dim, 2) ? 2 : 1;
    return 1;
  }
};

}  // namespace conserve::mesh
