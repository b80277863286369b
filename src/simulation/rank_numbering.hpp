#pragma once
/// The nodes of a run on several ranks: each rank owns a contiguous range
/// of the model's numbering (model::Model::rank_nodes) holding about 1/N
/// of the cells' corners (the assembly's work). A body whose range several
/// ranks share, and whose numbering is the program's (a generated mesh, or
/// a file's with `reorder`), has its nodes numbered part by part of a graph
/// partition (solver/graph_partition.hpp) with those ranks' shares of it,
/// in reverse Cuthill–McKee order within a part: each rank's nodes are then
/// a compact piece of the body instead of a slab of the band, and its
/// ghost nodes (the columns of its rows on other ranks) fewer
/// (bench/results/scaling_model.md). Bodies stay contiguous ranges.
#include <vector>

#include "mesh/mesh.hpp"

namespace conserve::simulation {

struct RankNumbering {
  std::vector<int> rank_nodes;  ///< rank r owns nodes [rank_nodes[r], rank_nodes[r+1])
  bool by_parts = false;        ///< some body was numbered by graph parts
};

/// Splits the bodies' meshes (in model order, each body's nodes after the
/// previous one's) over `ranks`; with `graph`, renumbers in place each
/// mesh that `renumber[b]` allows and several ranks share. Collective
/// (rank 0 partitions, every rank gets the same numbering).
RankNumbering number_for_ranks(std::vector<mesh::Mesh>& meshes, const std::vector<bool>& renumber, int ranks,
                               bool graph);

}  // namespace conserve::simulation
