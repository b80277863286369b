#pragma once
/// Which thread adds into which entries: the nodes are cut into contiguous
/// ranges, one per part, and each part owns the entries of its nodes (the
/// force components and the tangent's block columns of those nodes). A
/// part visits, in ascending order, every cell with a corner among its
/// nodes and adds that cell's terms into the corners it owns only. So no
/// two threads write the same entry, nothing waits, and every entry gets
/// its cells' terms in ascending cell order: the same bits for any number
/// of parts. A cell on the border of two parts is computed by both, each
/// keeping its own corners; with a banded numbering (reverse Cuthill–McKee,
/// as generated meshes get) those are a thin layer of the cells.
///
/// Why not colours: with a shared result vector every residual moves its
/// cache lines between the cores, and on a virtual machine whose two cores
/// sit far apart that cost more than the cells' arithmetic (bench/README.md,
/// "Parallel assembly"). A part writes into its own buffer and the
/// result's range of its nodes, in order.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace conserve::assembly {

/// One bit per node of a cell (a 10-node tetrahedron's fit).
using CornerMask = std::uint16_t;
inline constexpr int kMaxCorners = 16;

struct NodePartition {
  /// Part p owns nodes [first_node[p], first_node[p+1]).
  std::vector<int> first_node;
  /// Part p visits visits [visit_start[p], visit_start[p+1]).
  std::vector<int> visit_start;
  std::vector<int> visit_cell;  ///< ascending within a part
  /// Bit a set: the part owns the cell's node a.
  std::vector<CornerMask> visit_owned;

  [[nodiscard]] int num_parts() const { return static_cast<int>(first_node.size()) - 1; }
  [[nodiscard]] int num_visits() const { return static_cast<int>(visit_cell.size()); }
};

/// `parts` (≥ 1) contiguous node ranges holding about equal numbers of
/// cell corners (the work of adding into them), covering the nodes
/// [first, end) (end < 0: all nodes); the parts visit only cells with a
/// corner there. `cells`: nodes × n_cells node numbers below `num_nodes`,
/// at most kMaxCorners nodes per cell.
NodePartition partition_nodes(int num_nodes, const Eigen::MatrixXi& cells, int parts, int first = 0, int end = -1);

}  // namespace conserve::assembly
