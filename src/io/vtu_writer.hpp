#pragma once
/// ParaView output: VTU unstructured-grid files and a PVD time series.
#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace conserve::io {

/// A named field with `components` values per point or cell, stored
/// point-major: values[i * components + c]. `component_names`, if given
/// (one per component), are written as ComponentName attributes, which
/// ParaView shows (e.g. stress "xx" … "xz").
struct VtuField {
  std::string name;
  int components = 1;
  std::vector<double> values;
  std::vector<std::string> component_names{};
};

/// VTK cell types of the simplices conserve writes.
inline constexpr std::uint8_t kVtkVertex = 1, kVtkLine = 3, kVtkTriangle = 5, kVtkTetra = 10;
inline constexpr std::uint8_t kVtkQuadraticEdge = 21, kVtkQuadraticTriangle = 22, kVtkQuadraticTetra = 24;

/// The VTK type of a simplex of dimension `dim` (0 vertex, 1 line, 2
/// triangle, 3 tetrahedron) with `nodes` nodes: linear (1, 2, 3, 4 nodes:
/// types 1, 3, 5, 10) or quadratic (line3, tri6, tet10: 21, 22, 24). E.g. a
/// body's cells: vtk_cell_type(D, mesh::cell_nodes(D, order)); its facets:
/// vtk_cell_type(D − 1, mesh::facet_nodes(D, order)). Throws Error for any
/// other pair.
std::uint8_t vtk_cell_type(int dim, int nodes);

/// Number of nodes of VTK cell type `type` (one of the above). Throws Error
/// for any other type.
int vtk_cell_nodes(std::uint8_t type);

/// One unstructured grid of simplices, of one kind or mixed (e.g. the
/// tetrahedra of bodies and the triangles of bare rigid surfaces), linear
/// or quadratic.
struct VtuGrid {
  Eigen::MatrixXd points;  ///< dim × n (dim 2 is padded with z = 0)
  /// k × n_cells, a cell per column: its node numbers, in Gmsh's order
  /// (mesh/mesh.hpp; the writer permutes a 10-node tetrahedron's to VTK's,
  /// whose slots 7–9 are edges (0,3), (1,3), (2,3): Gmsh slots 8 and 9
  /// swap). A cell of m nodes uses the column's first m entries, the others
  /// are not read.
  Eigen::MatrixXi cells;
  /// Per cell its number of nodes m ≤ k; empty: every cell has k, or with
  /// `types`, the nodes of its type.
  std::vector<int> nodes_per_cell;
  /// Per cell its VTK type (vtk_cell_type); empty: inferred from the
  /// number of nodes (1 vertex, 2 line, 3 triangle, 4 tetrahedron), as a
  /// linear grid needs. A quadratic cell needs it: a 3-node line and a
  /// 3-node triangle have the same count.
  std::vector<std::uint8_t> types;
  std::vector<VtuField> point_data;
  std::vector<VtuField> cell_data;
};

/// How a VTU stores its arrays.
struct VtuFormat {
  /// zlib-compressed blocks (VTK's vtkZLibDataCompressor), else raw bytes.
  bool compress = true;
  /// Point and cell fields as Float32 (the points stay Float64).
  bool single_precision = false;
};

/// Writes a VTK XML UnstructuredGrid atomically (to a temporary file
/// renamed into place), its arrays as appended raw binary data, and
/// returns the file's size [bytes]. Throws Error on I/O failure.
std::uintmax_t write_vtu(const std::filesystem::path& file, const VtuGrid& grid, const VtuFormat& format = {});

/// The cells [first, end) of `grid` with the points they use (renumbered in
/// ascending order), their node counts and types, and those points' and
/// cells' fields: one rank's piece of a grid written in parts.
VtuGrid piece(const VtuGrid& grid, Eigen::Index first, Eigen::Index end);

/// Writes a parallel unstructured grid (.pvtu) atomically: the fields of
/// `grid` (their names, components and types as write_vtu() gives them)
/// and the pieces' files (relative to the .pvtu's folder).
void write_pvtu(const std::filesystem::path& file, const VtuGrid& grid, const VtuFormat& format,
                const std::vector<std::string>& pieces);

/// A ParaView .pvd collection, rewritten atomically after each added step.
class PvdWriter {
 public:
  explicit PvdWriter(std::filesystem::path file);
  /// Adds a dataset (path relative to the .pvd's folder) at `time` [s].
  void add(double time, const std::string& relative_file);
  /// Continues a collection this writer wrote before (a restart): keeps the
  /// file's entries up to `time` [s]; the next add() rewrites the file.
  /// Does nothing if the file does not exist.
  void resume(double time);

 private:
  std::filesystem::path file_;
  std::vector<std::pair<double, std::string>> entries_;
};

}  // namespace conserve::io
