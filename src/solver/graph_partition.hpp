#pragma once
/// The nodes of a run on several ranks split into parts, one per rank, of
/// about equal work (a node weighs its neighbours: the entries of its
/// rows) with few edges between them, so that each rank's block of the
/// matrix holds most of its couplings (block Jacobi then loses little).
/// Two candidates: PT-Scotch through PETSc's MatPartitioning (Debian's
/// PETSc has no ParMETIS), and contiguous ranges of the nodes' order (a
/// reverse Cuthill–McKee order's ranges are slabs, good while they are
/// thick); the one with fewer edges cut is taken. Computed on rank 0 and
/// sent to all, so every rank has the same parts.
#include <vector>

namespace conserve::solver {

struct GraphPartition {
  std::vector<int> part;  ///< per node, 0 … parts−1
  long cut = 0;           ///< edges between parts
  bool scotch = false;    ///< PT-Scotch's (else contiguous ranges)
};

/// The parts of the graph's nodes (node B's neighbours, itself included,
/// are neighbours[offsets[B] .. offsets[B+1])). Collective.
GraphPartition partition_graph(const std::vector<int>& offsets, const std::vector<int>& neighbours, int parts);

/// The edges of the graph between different parts.
long edge_cut(const std::vector<int>& offsets, const std::vector<int>& neighbours, const std::vector<int>& part);

}  // namespace conserve::solver
