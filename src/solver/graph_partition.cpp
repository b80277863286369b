#include "solver/graph_partition.hpp"

#include <petscmat.h>
// scotch.h needs <cstdio> and <cstdint> first.
#include <scotch.h>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include <algorithm>

#include "solver/petsc_session.hpp"
#include "solver/ranks.hpp"

namespace conserve::solver {

using petsc::check;

namespace {

/// Contiguous ranges of nodes, part p about shares[p] of the neighbours' sum.
std::vector<int> contiguous(const std::vector<int>& offsets, const std::vector<double>& shares) {
  const int nodes = static_cast<int>(offsets.size()) - 1;
  const int parts = static_cast<int>(shares.size());
  std::vector<int> part(static_cast<std::size_t>(nodes));
  const auto total = static_cast<double>(offsets.back());
  int p = 0;
  double end = shares[0] * total;  // the work before part p's end
  for (int B = 0; B < nodes; ++B) {
    while (p + 1 < parts && offsets[B] >= end) end += shares[static_cast<std::size_t>(++p)] * total;
    part[static_cast<std::size_t>(B)] = p;
  }
  return part;
}

std::vector<int> scotch(const std::vector<int>& offsets, const std::vector<int>& neighbours,
                        const std::vector<double>& shares) {
  const int nodes = static_cast<int>(offsets.size()) - 1;
  const int parts = static_cast<int>(shares.size());
  std::vector<int> part(static_cast<std::size_t>(nodes), 0);
  petsc::ensure_initialized();
  {
    // MPIAdj takes PETSc-allocated arrays without the diagonal, and owns them.
    PetscInt *ia = nullptr, *ja = nullptr, *weights = nullptr;
    check(PetscMalloc1(nodes + 1, &ia), "PetscMalloc1");
    check(PetscMalloc1(static_cast<PetscInt>(neighbours.size()), &ja), "PetscMalloc1");
    check(PetscMalloc1(nodes, &weights), "PetscMalloc1");
    ia[0] = 0;
    for (int B = 0; B < nodes; ++B) {
      ia[B + 1] = ia[B];
      for (int k = offsets[B]; k < offsets[B + 1]; ++k)
        if (neighbours[k] != B) ja[ia[B + 1]++] = neighbours[k];
      weights[B] = offsets[B + 1] - offsets[B];
    }
    Mat graph = nullptr;
    check(MatCreateMPIAdj(PETSC_COMM_SELF, nodes, nodes, ia, ja, nullptr, &graph), "MatCreateMPIAdj");
    MatPartitioning partitioning = nullptr;
    check(MatPartitioningCreate(PETSC_COMM_SELF, &partitioning), "MatPartitioningCreate");
    check(MatPartitioningSetAdjacency(partitioning, graph), "MatPartitioningSetAdjacency");
    check(MatPartitioningSetNParts(partitioning, parts), "MatPartitioningSetNParts");
    check(MatPartitioningSetVertexWeights(partitioning, weights), "MatPartitioningSetVertexWeights");
    if (std::any_of(shares.begin(), shares.end(), [&](double s) { return s != shares[0]; })) {
      PetscReal* targets = nullptr;  // PETSc-allocated, owned by the partitioning
      check(PetscMalloc1(parts, &targets), "PetscMalloc1");
      std::copy(shares.begin(), shares.end(), targets);
      check(MatPartitioningSetPartitionWeights(partitioning, targets), "MatPartitioningSetPartitionWeights");
    }
    check(MatPartitioningSetType(partitioning, MATPARTITIONINGPTSCOTCH), "MatPartitioningSetType(ptscotch)");
    // Scotch seeds its random choices from the clock unless told, and its
    // threads (Scotch 7) take them in any order: one thread and the same
    // seed each time give the same parts run after run.
    setenv("SCOTCH_PTHREAD_NUMBER", "1", 1);
    SCOTCH_randomSeed(1);
    SCOTCH_randomReset();
    IS is = nullptr;
    check(MatPartitioningApply(partitioning, &is), "MatPartitioningApply");
    const PetscInt* p = nullptr;
    check(ISGetIndices(is, &p), "ISGetIndices");
    for (int B = 0; B < nodes; ++B) part[static_cast<std::size_t>(B)] = static_cast<int>(p[B]);
    check(ISRestoreIndices(is, &p), "ISRestoreIndices");
    ISDestroy(&is);
    MatPartitioningDestroy(&partitioning);
    MatDestroy(&graph);
  }
  return part;
}

}  // namespace

long edge_cut(const std::vector<int>& offsets, const std::vector<int>& neighbours, const std::vector<int>& part) {
  long cut = 0;
  const int nodes = static_cast<int>(offsets.size()) - 1;
  for (int B = 0; B < nodes; ++B)
    for (int k = offsets[B]; k < offsets[B + 1]; ++k)
      if (neighbours[k] > B && part[neighbours[k]] != part[B]) ++cut;
  return cut;
}

GraphPartition partition_graph(const std::vector<int>& offsets, const std::vector<int>& neighbours, int parts) {
  return partition_graph(offsets, neighbours,
                         std::vector<double>(static_cast<std::size_t>(std::max(parts, 1)), 1.0 / std::max(parts, 1)));
}

GraphPartition partition_graph(const std::vector<int>& offsets, const std::vector<int>& neighbours,
                               const std::vector<double>& shares) {
  GraphPartition best;
  const int nodes = static_cast<int>(offsets.size()) - 1;
  if (shares.size() > 1 && nodes > 0 && ranks::root()) {
    best.part = contiguous(offsets, shares);
    best.cut = edge_cut(offsets, neighbours, best.part);
    std::vector<int> other = scotch(offsets, neighbours, shares);
    const long cut = edge_cut(offsets, neighbours, other);
    if (cut < best.cut) {
      best.part = std::move(other);
      best.cut = cut;
      best.scotch = true;
    }
  }
  best.part.resize(static_cast<std::size_t>(std::max(nodes, 0)), 0);
  ranks::broadcast(best.part);
  std::vector<int> figures = {static_cast<int>(best.cut), best.scotch ? 1 : 0};
  ranks::broadcast(figures);
  best.cut = figures[0];
  best.scotch = figures[1] != 0;
  return best;
}

}  // namespace conserve::solver
