#include "solver/petsc_system.hpp"

#include <algorithm>
#include <iterator>
#include <utility>

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

namespace {

/// A block of this rank's part in another rank's rows: (block row, block column).
using BlockPair = std::pair<PetscInt, PetscInt>;

/// Sends each rank its counts[r] items of `send` (in rank order) and
/// returns what the ranks sent here, received_counts[r] from rank r, in
/// rank order.
template <class T>
std::vector<T> exchange(const std::vector<T>& send, const std::vector<int>& counts,
                        const std::vector<int>& received_counts, MPI_Datatype type) {
  const auto parts = counts.size();
  std::vector<int> send_at(parts, 0), receive_at(parts, 0);
  for (std::size_t r = 1; r < parts; ++r) {
    send_at[r] = send_at[r - 1] + counts[r - 1];
    receive_at[r] = receive_at[r - 1] + received_counts[r - 1];
  }
  std::vector<T> received(static_cast<std::size_t>(receive_at[parts - 1] + received_counts[parts - 1]));
  MPI_Alltoallv(send.data(), counts.data(), send_at.data(), type, received.data(), received_counts.data(),
                receive_at.data(), type, PETSC_COMM_WORLD);
  return received;
}

/// What each rank sends here, for the counts this rank sends each.
std::vector<int> received_counts(const std::vector<int>& counts) {
  std::vector<int> received(counts.size(), 0);
  MPI_Alltoall(counts.data(), 1, MPI_INT, received.data(), 1, MPI_INT, PETSC_COMM_WORLD);
  return received;
}

/// PETSc's diagonal and off-diagonal blocks of a distributed matrix (BAIJ
/// if `blocked`, else AIJ), and the global (block) column of each of the
/// off-diagonal block's.
struct LocalBlocks {
  ::Mat diagonal = nullptr, off = nullptr;
  const PetscInt* columns = nullptr;
  LocalBlocks(::Mat A, bool blocked) {
    if (blocked)
      check(MatMPIBAIJGetSeqBAIJ(A, &diagonal, &off, &columns), "MatMPIBAIJGetSeqBAIJ");
    else
      check(MatMPIAIJGetSeqAIJ(A, &diagonal, &off, &columns), "MatMPIAIJGetSeqAIJ");
  }
};

/// A sequential block's values, for writing (BAIJ or AIJ).
class Values {
 public:
  Values(::Mat block, bool blocked) : block_(block), blocked_(blocked) {
    if (blocked_)
      check(MatSeqBAIJGetArray(block_, &values_), "MatSeqBAIJGetArray");
    else
      check(MatSeqAIJGetArray(block_, &values_), "MatSeqAIJGetArray");
  }
  ~Values() {
    if (blocked_)
      MatSeqBAIJRestoreArray(block_, &values_);
    else
      MatSeqAIJRestoreArray(block_, &values_);
  }
  Values(const Values&) = delete;
  Values& operator=(const Values&) = delete;
  [[nodiscard]] PetscScalar* data() const { return values_; }

 private:
  ::Mat block_;
  bool blocked_;
  PetscScalar* values_ = nullptr;
};

}  // namespace

void DistributedSystem::make(const SparseMatrix& M, int block, bool blocked, const std::vector<int>& rank_nodes) {
  destroy();
  const int n = static_cast<int>(M.rows());
  outer_.assign(M.outerIndexPtr(), M.outerIndexPtr() + M.outerSize() + 1);
  inner_.assign(M.innerIndexPtr(), M.innerIndexPtr() + M.nonZeros());
  const int parts = ranks::size(), me = ranks::rank();
  ranges_.assign(static_cast<std::size_t>(parts) + 1, n);
  if (static_cast<int>(rank_nodes.size()) == parts + 1) {
    for (int r = 0; r < parts; ++r) ranges_[r] = static_cast<std::int64_t>(rank_nodes[r]) * block;
  } else {
    const std::int64_t nodes = n / block;
    for (int r = 0; r < parts; ++r) ranges_[r] = nodes * r / parts * block;
  }
  first_ = static_cast<PetscInt>(ranges_[me]);
  end_ = static_cast<PetscInt>(ranges_[me + 1]);
  block_ = blocked ? block : 1;
  const int b = block_, bb = b * b;
  const PetscInt rows = (end_ - first_) / b;  // this rank's (block) rows
  const int columns = n / b;
  const auto owner = [&](int i) {
    return static_cast<int>(std::upper_bound(ranges_.begin(), ranges_.end(), static_cast<std::int64_t>(i)) -
                            ranges_.begin()) -
           1;
  };
  const auto mine = [&](int i) { return i >= first_ && i < end_; };
  // This rank's own (block) rows' columns, ascending: count, then fill.
  std::vector<PetscInt> seen(static_cast<std::size_t>(rows), -1);
  std::vector<PetscInt> own_start(static_cast<std::size_t>(rows) + 1, 0);
  std::vector<std::vector<BlockPair>> remote(static_cast<std::size_t>(parts));
  for (int J = 0; J < columns; ++J)
    for (int k = outer_[J * b]; k < outer_[(J + 1) * b]; ++k) {
      const int i = inner_[k];
      if (!mine(i)) {
        remote[static_cast<std::size_t>(owner(i))].emplace_back(i / b, J);
        continue;
      }
      if (const PetscInt I = (i - first_) / b; seen[I] != J) seen[I] = J, ++own_start[I + 1];
    }
  for (PetscInt I = 0; I < rows; ++I) own_start[I + 1] += own_start[I];
  std::vector<PetscInt> own(static_cast<std::size_t>(own_start[rows]));
  {
    std::vector<PetscInt> next(own_start.begin(), own_start.end() - 1);
    std::fill(seen.begin(), seen.end(), -1);
    for (int J = 0; J < columns; ++J)
      for (int k = outer_[J * b]; k < outer_[(J + 1) * b]; ++k)
        if (const int i = inner_[k]; mine(i))
          if (const PetscInt I = (i - first_) / b; seen[I] != J) seen[I] = J, own[next[I]++] = J;
  }
  // The blocks this rank adds into other ranks' rows, sorted, to them; and theirs here.
  std::vector<PetscInt> pairs_out;
  std::vector<int> pair_counts(static_cast<std::size_t>(parts), 0);
  for (int r = 0; r < parts; ++r) {
    auto& list = remote[static_cast<std::size_t>(r)];
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
    for (const auto& [I, J] : list) pairs_out.push_back(I), pairs_out.push_back(J);
    pair_counts[r] = static_cast<int>(2 * list.size());
  }
  const std::vector<int> pairs_in_counts = received_counts(pair_counts);
  const std::vector<PetscInt> pairs_in = exchange(pairs_out, pair_counts, pairs_in_counts, MPIU_INT);
  std::vector<BlockPair> incoming;
  for (std::size_t q = 0; q < pairs_in.size(); q += 2) incoming.emplace_back(pairs_in[q] - first_ / b, pairs_in[q + 1]);
  std::vector<BlockPair> extra = incoming;
  std::sort(extra.begin(), extra.end());
  extra.erase(std::unique(extra.begin(), extra.end()), extra.end());
  // Each row's columns: its own and those sent to it, merged.
  std::vector<PetscInt> row_start(static_cast<std::size_t>(rows) + 1, 0), column;
  column.reserve(own.size() + extra.size());
  auto e = extra.begin();
  std::vector<PetscInt> sent;
  for (PetscInt I = 0; I < rows; ++I) {
    sent.clear();
    for (; e != extra.end() && e->first == I; ++e) sent.push_back(e->second);
    std::set_union(own.begin() + own_start[I], own.begin() + own_start[I + 1], sent.begin(), sent.end(),
                   std::back_inserter(column));
    row_start[I + 1] = static_cast<PetscInt>(column.size());
  }
  const PetscInt local = end_ - first_;
  check(MatCreate(PETSC_COMM_WORLD, &A_), "MatCreate");
  check(MatSetSizes(A_, local, local, n, n), "MatSetSizes");
  if (blocked) {
    check(MatSetType(A_, MATMPIBAIJ), "MatSetType");
    check(MatMPIBAIJSetPreallocationCSR(A_, b, row_start.data(), column.data(), nullptr),
          "MatMPIBAIJSetPreallocationCSR");
  } else {
    check(MatSetType(A_, MATMPIAIJ), "MatSetType");
    if (block > 1 && static_cast<int>(rank_nodes.size()) == parts + 1 &&
        static_cast<std::int64_t>(rank_nodes.back()) * block == n)  // all rows nodal
      check(MatSetBlockSize(A_, block), "MatSetBlockSize");
    check(MatMPIAIJSetPreallocationCSR(A_, row_start.data(), column.data(), nullptr), "MatMPIAIJSetPreallocationCSR");
  }
  check(MatSetOption(A_, MAT_NO_OFF_PROC_ENTRIES, PETSC_TRUE), "MatSetOption");
  check(MatSetOption(A_, MAT_NEW_NONZERO_LOCATION_ERR, PETSC_TRUE), "MatSetOption");
  // Where each value goes: into the values of PETSc's diagonal block (the
  // columns of this rank's rows) or, after them, of its off-diagonal block
  // (the others' columns, numbered by `garray`), each block column-major.
  const LocalBlocks blocks(A_, blocked);
  const ::Mat diagonal = blocks.diagonal, off = blocks.off;
  const PetscInt* garray = blocks.columns;
  PetscInt rows_d = 0, rows_o = 0, off_columns = 0;
  const PetscInt *ia = nullptr, *ja = nullptr, *ib = nullptr, *jb = nullptr;
  PetscBool done = PETSC_FALSE;
  // Block rows for BAIJ; plain rows for AIJ (not compressed by inodes).
  const PetscBool by_blocks = blocked ? PETSC_TRUE : PETSC_FALSE;
  check(MatGetRowIJ(diagonal, 0, PETSC_FALSE, by_blocks, &rows_d, &ia, &ja, &done), "MatGetRowIJ");
  check(MatGetRowIJ(off, 0, PETSC_FALSE, by_blocks, &rows_o, &ib, &jb, &done), "MatGetRowIJ");
  check(MatGetLocalSize(off, nullptr, &off_columns), "MatGetLocalSize");
  off_columns /= b;
  diagonal_values_ = ia[rows_d] * bb;
  off_values_ = ib[rows_o] * bb;
  const PetscInt first_column = first_ / b, end_column = end_ / b;
  const auto position = [&](PetscInt I, PetscInt J, int ii, int jj) -> PetscInt {
    if (J >= first_column && J < end_column) {
      const PetscInt k = std::lower_bound(ja + ia[I], ja + ia[I + 1], J - first_column) - ja;
      return k * bb + jj * b + ii;
    }
    const PetscInt L = std::lower_bound(garray, garray + off_columns, J) - garray;
    const PetscInt k = std::lower_bound(jb + ib[I], jb + ib[I + 1], L) - jb;
    return diagonal_values_ + k * bb + jj * b + ii;
  };
  std::vector<PetscInt> send_at(static_cast<std::size_t>(parts) + 1, 0);
  for (int r = 0; r < parts; ++r)
    send_at[r + 1] = send_at[r] + static_cast<PetscInt>(remote[static_cast<std::size_t>(r)].size()) * bb;
  to_.assign(inner_.size(), 0);
  for (int j = 0; j < n; ++j)
    for (int k = outer_[j]; k < outer_[j + 1]; ++k) {
      const int i = inner_[k];
      if (mine(i)) {
        to_[k] = position((i - first_) / b, j / b, (i - first_) % b, j % b);
        continue;
      }
      const int r = owner(i);
      const auto& list = remote[static_cast<std::size_t>(r)];
      const auto q = std::lower_bound(list.begin(), list.end(), BlockPair(i / b, j / b)) - list.begin();
      to_[k] = -1 - (send_at[r] + q * bb + (i % b) * b + j % b);
    }
  send_.assign(static_cast<std::size_t>(send_at[parts]), 0.0);
  send_counts_.assign(static_cast<std::size_t>(parts), 0);
  for (int r = 0; r < parts; ++r) send_counts_[r] = static_cast<int>(send_at[r + 1] - send_at[r]);
  receive_counts_.assign(static_cast<std::size_t>(parts), 0);
  for (int r = 0; r < parts; ++r) receive_counts_[r] = pairs_in_counts[r] / 2 * bb;  // two indices a block, bb values
  received_to_.clear();
  received_to_.reserve(incoming.size() * bb);
  for (const auto& [I, J] : incoming)
    for (int ii = 0; ii < b; ++ii)
      for (int jj = 0; jj < b; ++jj) received_to_.push_back(position(I, J, ii, jj));
  check(MatRestoreRowIJ(diagonal, 0, PETSC_FALSE, by_blocks, &rows_d, &ia, &ja, &done), "MatRestoreRowIJ");
  check(MatRestoreRowIJ(off, 0, PETSC_FALSE, by_blocks, &rows_o, &ib, &jb, &done), "MatRestoreRowIJ");
  check(MatCreateVecs(A_, &x_, &b_), "MatCreateVecs");
  check(VecScatterCreateToAll(x_, &gather_, &all_), "VecScatterCreateToAll");
}

void DistributedSystem::copy_values(const SparseMatrix& M) {
  const bool blocked = block_ > 1;
  const LocalBlocks blocks(A_, blocked);
  {
    const Values diagonal(blocks.diagonal, blocked), off(blocks.off, blocked);
    PetscScalar *d = diagonal.data(), *o = off.data();
    std::fill(d, d + diagonal_values_, 0.0);
    std::fill(o, o + off_values_, 0.0);
    const auto at = [&](PetscInt t) -> PetscScalar& { return t < diagonal_values_ ? d[t] : o[t - diagonal_values_]; };
    const double* v = M.valuePtr();
    const auto size = static_cast<std::ptrdiff_t>(to_.size());
    for (std::ptrdiff_t k = 0; k < size; ++k) {
      const PetscInt t = to_[static_cast<std::size_t>(k)];
      if (t >= 0)
        at(t) = v[k];
      else
        send_[static_cast<std::size_t>(-1 - t)] = v[k];
    }
    // The others' terms after this rank's own, in rank order: the same bits run after run.
    const std::vector<PetscScalar> received = exchange(send_, send_counts_, receive_counts_, MPI_DOUBLE);
    for (std::size_t q = 0; q < received.size(); ++q) at(received_to_[q]) += received[q];
  }
  // Assembly moves the matrix's state on, so the preconditioner rebuilds.
  check(MatAssemblyBegin(A_, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
  check(MatAssemblyEnd(A_, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
}

void DistributedSystem::local_entries(const double* full, PetscScalar* out) const {
  std::copy(full + first_, full + end_, out);
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
  std::copy(v, v + n, out.data());
  check(VecRestoreArrayRead(all_, &v), "VecRestoreArrayRead");
}

}  // namespace conserve::solver::petsc
