#include "solver/petsc_system.hpp"

#include <algorithm>

#include "solver/petsc_session.hpp"
#include "solver/ranks.hpp"

namespace conserve::solver::petsc {

DistributedSystem::~DistributedSystem() { destroy(); }

void DistributedSystem::destroy() {
  if (gather_) VecScatterDestroy(&gather_);
  if (all_) VecDestroy(&all_);
  if (b_) VecDestroy(&b_);
  if (x_) VecDestroy(&x_);
  if (A_) MatDestroy(&A_);
}

bool DistributedSystem::same_pattern(const SparseMatrix& M) const {
  return A_ && static_cast<Eigen::Index>(outer_.size()) == M.outerSize() + 1 &&
         static_cast<Eigen::Index>(inner_.size()) == M.nonZeros() &&
         std::equal(outer_.begin(), outer_.end(), M.outerIndexPtr()) &&
         std::equal(inner_.begin(), inner_.end(), M.innerIndexPtr());
}

void DistributedSystem::make(const SparseMatrix& M, int block, int nodal_rows, bool blocked,
                             const std::vector<int>* node_part) {
  destroy();
  const int n = static_cast<int>(M.rows());
  outer_.assign(M.outerIndexPtr(), M.outerIndexPtr() + M.outerSize() + 1);
  inner_.assign(M.innerIndexPtr(), M.innerIndexPtr() + M.nonZeros());
  const int parts = ranks::size(), me = ranks::rank();
  ranges_.assign(static_cast<std::size_t>(parts) + 1, 0);
  order_.resize(static_cast<std::size_t>(n));
  const int nodes = nodal_rows / block;
  if (node_part && static_cast<int>(node_part->size()) == nodes) {
    // The parts' nodes in turn (ascending within a part), each node's rows
    // together; the rows that are no node's (multipliers) on the last rank.
    std::vector<int> count(static_cast<std::size_t>(parts), 0);
    for (const int p : *node_part) ++count[static_cast<std::size_t>(p)];
    std::vector<int> next(static_cast<std::size_t>(parts), 0);
    for (int r = 1; r < parts; ++r) next[r] = next[r - 1] + count[r - 1] * block;
    for (int B = 0; B < nodes; ++B)
      for (int i = 0; i < block; ++i) order_[next[(*node_part)[B]]++] = B * block + i;
    for (int i = nodal_rows; i < n; ++i) order_[i] = i;
    for (int r = 0; r < parts; ++r) ranges_[r + 1] = ranges_[r] + count[r] * block;
    ranges_[parts] = n;
  } else {
    // Contiguous ranges cut where the entries before reach r/N of all,
    // moved down to a node's first row among the nodal rows.
    std::vector<long> entries(static_cast<std::size_t>(n) + 1, 0);
    for (const int i : inner_) ++entries[static_cast<std::size_t>(i) + 1];
    for (int i = 0; i < n; ++i) entries[i + 1] += entries[i];
    for (int r = 1; r < parts; ++r) {
      const long target = entries[n] * r / parts;
      int i = static_cast<int>(std::lower_bound(entries.begin(), entries.end(), target) - entries.begin());
      i = std::min(i, n);
      if (i < nodal_rows) i -= i % block;
      ranges_[r] = std::max<std::int64_t>(i, ranges_[r - 1]);
    }
    ranges_[parts] = n;
    for (int i = 0; i < n; ++i) order_[i] = i;
  }
  std::vector<PetscInt> index(static_cast<std::size_t>(n));  // model row → PETSc row
  for (int p = 0; p < n; ++p) index[order_[p]] = p;
  first_ = static_cast<PetscInt>(ranges_[me]);
  end_ = static_cast<PetscInt>(ranges_[me + 1]);
  const int local = static_cast<int>(end_ - first_);
  block_ = blocked ? block : 1;
  const int b = block_;
  const int rows = local / b;  // this rank's (block) rows
  // Two passes over the columns: count each (block) row's (block)
  // columns, then hand out their slots; then each row's slots are sorted by
  // their PETSc column.
  std::vector<PetscInt> seen(static_cast<std::size_t>(rows), -1);
  row_start_.assign(static_cast<std::size_t>(rows) + 1, 0);
  const int columns = n / b;
  const auto local_row = [&](int i) { return (index[i] - first_) / b; };
  const auto mine = [&](int i) { return index[i] >= first_ && index[i] < end_; };
  for (int J = 0; J < columns; ++J)
    for (int k = outer_[J * b]; k < outer_[(J + 1) * b]; ++k)
      if (const int i = inner_[k]; mine(i))
        if (const PetscInt I = local_row(i); seen[I] != J) seen[I] = J, ++row_start_[I + 1];
  for (int I = 0; I < rows; ++I) row_start_[I + 1] += row_start_[I];
  column_.resize(static_cast<std::size_t>(row_start_[rows]));
  std::vector<PetscInt> slot_of(inner_.size(), -1);
  std::vector<PetscInt> next(row_start_.begin(), row_start_.end() - 1);
  std::vector<PetscInt> slot(static_cast<std::size_t>(rows), -1);
  std::fill(seen.begin(), seen.end(), -1);
  for (int J = 0; J < columns; ++J)
    for (int j = J * b; j < (J + 1) * b; ++j)
      for (int k = outer_[j]; k < outer_[j + 1]; ++k) {
        const int i = inner_[k];
        if (!mine(i)) continue;
        const PetscInt I = local_row(i);
        if (seen[I] != J) {
          seen[I] = J;
          slot[I] = next[I]++;
          column_[slot[I]] = index[J * b] / b;
        }
        slot_of[k] = slot[I];
      }
  // Sorted columns within each row (as PETSc keeps them); rank[s] is slot
  // s's place in its row after sorting.
  std::vector<PetscInt> rank(column_.size());
  for (int I = 0; I < rows; ++I) {
    const PetscInt begin = row_start_[I], end = row_start_[I + 1];
    std::vector<PetscInt> by_column(static_cast<std::size_t>(end - begin));
    for (PetscInt s = begin; s < end; ++s) by_column[s - begin] = s;
    std::sort(by_column.begin(), by_column.end(), [&](PetscInt x, PetscInt y) { return column_[x] < column_[y]; });
    std::vector<PetscInt> sorted(by_column.size());
    for (std::size_t q = 0; q < by_column.size(); ++q) {
      rank[by_column[q]] = static_cast<PetscInt>(q);
      sorted[q] = column_[by_column[q]];
    }
    std::copy(sorted.begin(), sorted.end(), column_.begin() + begin);
  }
  to_.assign(inner_.size(), -1);
  for (int j = 0; j < n; ++j)
    for (int k = outer_[j]; k < outer_[j + 1]; ++k) {
      if (slot_of[k] < 0) continue;
      const int i = inner_[k];
      const PetscInt I = local_row(i);
      // Row-major within the block row: b rows of (blocks · b) values.
      const PetscInt width = (row_start_[I + 1] - row_start_[I]) * b;
      to_[k] = row_start_[I] * b * b + (index[i] % b) * width + rank[slot_of[k]] * b + index[j] % b;
    }
  values_.assign(static_cast<std::size_t>(row_start_[rows]) * b * b, 0.0);
  check(MatCreate(PETSC_COMM_WORLD, &A_), "MatCreate");
  check(MatSetSizes(A_, local, local, n, n), "MatSetSizes");
  if (blocked) {
    check(MatSetType(A_, MATMPIBAIJ), "MatSetType");
    check(MatMPIBAIJSetPreallocationCSR(A_, b, row_start_.data(), column_.data(), nullptr),
          "MatMPIBAIJSetPreallocationCSR");
  } else {
    check(MatSetType(A_, MATMPIAIJ), "MatSetType");
    if (block > 1 && nodal_rows == n) check(MatSetBlockSize(A_, block), "MatSetBlockSize");
    check(MatMPIAIJSetPreallocationCSR(A_, row_start_.data(), column_.data(), nullptr), "MatMPIAIJSetPreallocationCSR");
  }
  // Every rank sets its own rows: the assembly sends nothing.
  check(MatSetOption(A_, MAT_NO_OFF_PROC_ENTRIES, PETSC_TRUE), "MatSetOption");
  check(MatSetOption(A_, MAT_NEW_NONZERO_LOCATION_ERR, PETSC_TRUE), "MatSetOption");
  check(MatCreateVecs(A_, &x_, &b_), "MatCreateVecs");
  check(VecScatterCreateToAll(x_, &gather_, &all_), "VecScatterCreateToAll");
}

void DistributedSystem::copy_values(const SparseMatrix& M) {
  const double* v = M.valuePtr();
  const auto size = static_cast<std::ptrdiff_t>(to_.size());
  for (std::ptrdiff_t k = 0; k < size; ++k)
    if (to_[k] >= 0) values_[static_cast<std::size_t>(to_[k])] = v[k];
  const int b = block_;
  const auto rows = static_cast<PetscInt>(row_start_.size()) - 1;
  for (PetscInt I = 0; I < rows; ++I) {
    const PetscInt row = first_ / b + I, m = row_start_[I + 1] - row_start_[I];
    const PetscScalar* values = values_.data() + row_start_[I] * b * b;
    if (b > 1)
      check(MatSetValuesBlocked(A_, 1, &row, m, column_.data() + row_start_[I], values, INSERT_VALUES),
            "MatSetValuesBlocked");
    else
      check(MatSetValues(A_, 1, &row, m, column_.data() + row_start_[I], values, INSERT_VALUES), "MatSetValues");
  }
  check(MatAssemblyBegin(A_, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
  check(MatAssemblyEnd(A_, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
}

void DistributedSystem::local_entries(const double* full, PetscScalar* out) const {
  for (PetscInt p = first_; p < end_; ++p) out[p - first_] = full[order_[p]];
}

void DistributedSystem::set_rhs(const Eigen::VectorXd& rhs) {
  PetscScalar* v = nullptr;
  check(VecGetArrayWrite(b_, &v), "VecGetArrayWrite");
  local_entries(rhs.data(), v);
  check(VecRestoreArrayWrite(b_, &v), "VecRestoreArrayWrite");
}

void DistributedSystem::gather_solution(Eigen::VectorXd& out) {
  check(VecScatterBegin(gather_, x_, all_, INSERT_VALUES, SCATTER_FORWARD), "VecScatterBegin");
  check(VecScatterEnd(gather_, x_, all_, INSERT_VALUES, SCATTER_FORWARD), "VecScatterEnd");
  PetscInt n = 0;
  check(VecGetSize(all_, &n), "VecGetSize");
  const PetscScalar* v = nullptr;
  out.resize(n);
  check(VecGetArrayRead(all_, &v), "VecGetArrayRead");
  for (PetscInt p = 0; p < n; ++p) out[order_[p]] = v[p];
  check(VecRestoreArrayRead(all_, &v), "VecRestoreArrayRead");
}

}  // namespace conserve::solver::petsc
