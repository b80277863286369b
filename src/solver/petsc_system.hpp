#pragma once
/// A linear system A x = b distributed over the ranks (solver/ranks.hpp)
/// as PETSc objects, filled from the Eigen matrix every rank holds: rank r
/// owns the rows of the nodes of part r (solver/graph_partition.hpp), or
/// without parts a contiguous range of rows holding about 1/N of the
/// entries, and copies only those rows' entries (no communication). PETSc
/// numbers the rows rank by rank (the parts' nodes in turn, a node's D rows
/// together, rows that are no node's last). Node-block (MPIBAIJ) or scalar
/// (MPIAIJ) storage. The solution is gathered back to every rank.
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
  /// rows (a rank has all of a node's rows or none); `blocked` stores D × D
  /// blocks (MPIBAIJ, needs all rows nodal), else entries (MPIAIJ, with
  /// the block size noted when all rows are nodal). `node_part`: each
  /// node's rank (null, or not one per node: contiguous ranges).
  void make(const SparseMatrix& M, int block, int nodal_rows, bool blocked,
            const std::vector<int>* node_part = nullptr);
  /// Copies M's values into the matrix (M has the pattern of make()).
  void copy_values(const SparseMatrix& M);
  /// This rank's entries (in PETSc's numbering) of a full vector of the
  /// matrix's rows: out[p − first_row()] = full[row of PETSc row p].
  void local_entries(const double* full, PetscScalar* out) const;
  /// b's rows of this rank from the full right-hand side.
  void set_rhs(const Eigen::VectorXd& rhs);
  /// The full x on every rank (collective).
  void gather_solution(Eigen::VectorXd& out);

  [[nodiscard]] ::Mat matrix() const { return A_; }
  [[nodiscard]] ::Vec rhs() const { return b_; }
  [[nodiscard]] ::Vec solution() const { return x_; }
  /// This rank's rows [first_row, end_row) in PETSc's numbering.
  [[nodiscard]] PetscInt first_row() const { return first_; }
  [[nodiscard]] PetscInt end_row() const { return end_; }
  /// Every rank's first row in PETSc's numbering, and the number of rows last.
  [[nodiscard]] const std::vector<std::int64_t>& row_ranges() const { return ranges_; }

 private:
  void destroy();
  std::vector<int> outer_, inner_;  ///< the CSC pattern the matrix was made for
  PetscInt first_ = 0, end_ = 0;
  std::vector<std::int64_t> ranges_;
  std::vector<int> order_;                    ///< PETSc row → the matrix's row
  int block_ = 1;                             ///< rows per stored block (1: MPIAIJ)
  std::vector<PetscInt> row_start_, column_;  ///< this rank's (block) rows, global (block) columns
  std::vector<PetscInt> to_;                  ///< CSC position → position in values_, −1: another rank's
  std::vector<PetscScalar> values_;           ///< per (block) row, its values row-major (MatSetValues[Blocked])
  ::Mat A_ = nullptr;
  ::Vec b_ = nullptr, x_ = nullptr, all_ = nullptr;
  VecScatter gather_ = nullptr;
};

}  // namespace conserve::solver::petsc
