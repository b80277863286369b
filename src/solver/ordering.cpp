#include "solver/ordering.hpp"

#include <petscmat.h>

#include <algorithm>

#include "core/error.hpp"
#include "solver/petsc_session.hpp"

namespace conserve::solver {

using petsc::check;

std::vector<int> reverse_cuthill_mckee(const std::vector<int>& offsets, const std::vector<int>& neighbours) {
  const int n = offsets.empty() ? 0 : static_cast<int>(offsets.size()) - 1;
  if (n == 0) return {};
  if (offsets.front() != 0 || offsets.back() != static_cast<int>(neighbours.size()))
    throw SolverError("reverse_cuthill_mckee: offsets do not span the neighbours");
  petsc::ensure_initialized();
  // The pattern as a sequential AIJ matrix with its diagonal (PETSc's
  // orderings read the pattern only; the values are ones).
  std::vector<PetscInt> row(n + 1, 0), column;
  column.reserve(neighbours.size() + n);
  for (int v = 0; v < n; ++v) {
    const auto first = column.size();
    column.push_back(v);
    for (int k = offsets[v]; k < offsets[v + 1]; ++k) {
      if (neighbours[k] < 0 || neighbours[k] >= n) throw SolverError("reverse_cuthill_mckee: a neighbour is out of range");
      column.push_back(neighbours[k]);
    }
    std::sort(column.begin() + static_cast<std::ptrdiff_t>(first), column.end());
    column.erase(std::unique(column.begin() + static_cast<std::ptrdiff_t>(first), column.end()), column.end());
    row[v + 1] = static_cast<PetscInt>(column.size());
  }
  std::vector<PetscScalar> ones(column.size(), 1.0);
  ::Mat A = nullptr;
  IS rows = nullptr, columns = nullptr;
  std::vector<int> order(n);
  try {
    check(MatCreateSeqAIJWithArrays(PETSC_COMM_SELF, n, n, row.data(), column.data(), ones.data(), &A),
          "MatCreateSeqAIJWithArrays");
    check(MatGetOrdering(A, MATORDERINGRCM, &rows, &columns), "MatGetOrdering(rcm)");
    const PetscInt* p = nullptr;
    check(ISGetIndices(rows, &p), "ISGetIndices");
    // rows[k] is the original row placed k-th (MatPermute's convention).
    std::copy(p, p + n, order.begin());
    check(ISRestoreIndices(rows, &p), "ISRestoreIndices");
  } catch (...) {
    if (rows) ISDestroy(&rows);
    if (columns) ISDestroy(&columns);
    if (A) MatDestroy(&A);
    throw;
  }
  ISDestroy(&rows);
  ISDestroy(&columns);
  MatDestroy(&A);
  return order;
}

}  // namespace conserve::solver
