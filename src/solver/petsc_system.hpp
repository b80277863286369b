#pragma once
/// A linear system A x = b distributed over the ranks (solver/ranks.hpp)
/// as PETSc objects, filled from the Eigen matrix every rank holds: rank r
/// owns a contiguous range of rows, cut so that the ranges hold about
/// equal numbers of entries (a node's D rows stay together), and copies
/// only those rows' entries (no communication). Node-block (MPIBAIJ) or
/// scalar (MPIAIJ) storage. The solution is gathered back to every rank.
/// Private to the solver layer (it includes PETSc).
#include <petscksp.h>

#include <cstdint>
#include <vector>

#include "core/types.hpp"

namespace conserve::solver::petsc {

class DistributedSystem {
 public:
  DistributedSystem() = default;
  ~DistributedSystem();
  DistributedSystem(const DistributedSystem&) = delete;
  DistributedSystem& operator=(const DistributedSystem&) = delete;

  /// Whether M has the pattern the matrix was made for.
  [[nodiscard]] bool same_pattern(const SparseMatrix& M) const;
  /// A new matrix (and vectors) for M's pattern, without values:
  /// `block` > 1 groups the first `nodal_rows` rows in nodes of `block`
  /// rows (their ranges never split a node); `blocked` stores D × D
  /// blocks (MPIBAIJ, needs all rows nodal), else entries (MPIAIJ, with
  /// the block size noted when all rows are nodal).
  void make(const SparseMatrix& M, int block, int nodal_rows, bool blocked);
  /// Copies M's values into the matrix (M has the pattern of make()).
  void copy_values(const SparseMatrix& M);
  /// b's rows of this rank from the full right-hand side.
  void set_rhs(const Eigen::VectorXd& rhs);
  /// The full x on every rank (collective).
  void gather_solution(Eigen::VectorXd& out);

  [[nodiscard]] ::Mat matrix() const { return A_; }
  [[nodiscard]] ::Vec rhs() const { return b_; }
  [[nodiscard]] ::Vec solution() const { return x_; }
  /// This rank's rows [first_row, end_row).
  [[nodiscard]] PetscInt first_row() const { return first_; }
  [[nodiscard]] PetscInt end_row() const { return end_; }
  /// Every rank's first row, and the number of rows last.
  [[nodiscard]] const std::vector<std::int64_t>& row_ranges() const { return ranges_; }

 private:
  void destroy();
  std::vector<int> outer_, inner_;  ///< the CSC pattern the matrix was made for
  PetscInt first_ = 0, end_ = 0;
  std::vector<std::int64_t> ranges_;
  int block_ = 1;                             ///< rows per stored block (1: MPIAIJ)
  std::vector<PetscInt> row_start_, column_;  ///< this rank's (block) rows, global (block) columns
  std::vector<PetscInt> to_;                  ///< CSC position → position in values_, −1: another rank's
  std::vector<PetscScalar> values_;           ///< per (block) row, its values row-major (MatSetValues[Blocked])
  ::Mat A_ = nullptr;
  ::Vec b_ = nullptr, x_ = nullptr, all_ = nullptr;
  VecScatter gather_ = nullptr;
};

}  // namespace conserve::solver::petsc
