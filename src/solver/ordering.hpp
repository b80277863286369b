#pragma once
/// Orders of a graph's vertices that keep neighbours close in memory.
#include <vector>

namespace conserve::solver {

/// Reverse Cuthill–McKee order of the undirected graph whose vertex v has
/// the neighbours neighbours[offsets[v] … offsets[v+1]) (PETSc's
/// MatGetOrdering, "rcm"): order[k] is the vertex to place k-th. Narrows
/// the band of a matrix with that pattern, and so the spread of the nodes
/// a cell loop touches and the reach of ILU(0)'s fill.
[[nodiscard]] std::vector<int> reverse_cuthill_mckee(const std::vector<int>& offsets,
                                                     const std::vector<int>& neighbours);

}  // namespace conserve::solver
