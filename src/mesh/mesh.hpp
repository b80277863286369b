#pragma once
/// A mesh of linear simplices (3-node triangles in 2D, 4-node tetrahedra in
/// 3D) with named groups, as read from a Gmsh file or made by a generator.
#include <Eigen/Core>
#include <map>
#include <string>
#include <vector>

namespace conserve::mesh {

/// Named set of boundary facets (segments in 2D, triangles in 3D).
struct FacetGroup {
  /// dim × n_facets node indices (0-based, into Mesh::points).
  Eigen::MatrixXi facets;
};

/// A simplex mesh. Node and cell indices are 0-based and contiguous.
struct Mesh {
  int dim = 3;  ///< spatial and cell dimension, 2 or 3
  /// dim × n_nodes reference coordinates [m].
  Eigen::MatrixXd points;
  /// (dim+1) × n_cells node indices; cells are positively oriented
  /// (positive Jacobian determinant).
  Eigen::MatrixXi cells;
  /// Named volume (3D) / surface (2D) physical groups: cell indices.
  std::map<std::string, std::vector<int>> cell_groups;
  /// Named boundary physical groups.
  std::map<std::string, FacetGroup> facet_groups;

  [[nodiscard]] int num_nodes() const { return static_cast<int>(points.cols()); }
  [[nodiscard]] int num_cells() const { return static_cast<int>(cells.cols()); }
};

}  // namespace conserve::mesh
