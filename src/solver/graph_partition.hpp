#pragma once
/// A graph partition of the nodes into parts of about equal work (a node
/// weighs its neighbours: the entries of its rows) with few edges between
/// them: PT-Scotch through PETSc's MatPartitioning (Debian's PETSc has no
/// ParMETIS), or contiguous ranges of the nodes' order, whichever cuts
/// fewer edges; computed on rank 0 and sent to all. A run's ranks own
/// contiguous ranges of the model's numbering (model::Model::rank_nodes),
/// which numbers a body's nodes part by part (simulation/rank_numbering.hpp).
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

/// The same with part p holding about shares[p] of the work (the shares
/// sum to 1, each > 0). Collective.
GraphPartition partition_graph(const std::vector<int>& offsets, const std::vector<int>& neighbours,
                               const std::vector<double>& shares);

/// The edges of the graph between different parts.
long edge_cut(const std::vector<int>& offsets, const std::vector<int>& neighbours, const std::vector<int>& part);

}  // namespace conserve::solver
