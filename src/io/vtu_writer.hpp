#pragma once
/// ParaView output: VTU unstructured-grid files and a PVD time series.
#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace conserve::io {

/// A named field with `components` values per point or cell, stored
/// point-major: values[i * components + c].
struct VtuField {
  std::string name;
  int components = 1;
  std::vector<double> values;
};

/// One unstructured grid of simplices, of one kind or mixed (e.g. the
/// tetrahedra of bodies and the triangles of bare rigid surfaces).
struct VtuGrid {
  Eigen::MatrixXd points;  ///< dim × n (dim 2 is padded with z = 0)
  /// k × n_cells, a cell per column: its node numbers; a cell of m nodes
  /// (1 vertex, 2 line, 3 triangle, 4 tetrahedron) uses the column's first
  /// m entries, the others are not read.
  Eigen::MatrixXi cells;
  /// Per cell its number of nodes m ≤ k; empty: every cell has k.
  std::vector<int> nodes_per_cell;
  std::vector<VtuField> point_data;
  std::vector<VtuField> cell_data;
};

/// Writes a VTK XML UnstructuredGrid (binary, base64 inline) atomically:
/// to a temporary file renamed into place. Throws Error on I/O failure.
void write_vtu(const std::filesystem::path& file, const VtuGrid& grid);

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
