#pragma once
/// A linear system A x = b distributed over the ranks (solver/ranks.hpp)
/// as PETSc objects. Rank r owns the rows of the nodes [rank_nodes[r],
/// rank_nodes[r+1]) (a node's rows together; the rows beyond the nodes'
/// are the last rank's), numbered as the model numbers them. Each rank
/// passes its part of the system as an Eigen matrix of the full size: its
/// own rows, and in other rows the terms it adds there (a slave's
/// elimination into its master's rows); those are sent to the rows' owner
/// and summed after the owner's own, in rank order, so the same ranks give
/// the same bits. Node-block (MPIBAIJ) or scalar (MPIAIJ) storage. The
/// solution is gathered back to every rank. Private to the solver layer
/// (it includes PETSc).
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

  /// Whether M has the pattern the matrix was made for (this rank's part).
  [[nodiscard]] bool same_pattern(const SparseMatrix& M) const;
  /// A new matrix (and vectors) for the pattern of this rank's part M,
  /// merged with the parts the others send, without values. `block` rows
  /// make a node; `blocked` stores block × block blocks (MPIBAIJ, needs
  /// all rows nodal), else entries (MPIAIJ, with the block size noted when
  /// all rows are nodal). `rank_nodes`: the ranks' node ranges (empty:
  /// about equal numbers of nodes). Collective.
  void make(const SparseMatrix& M, int block, bool blocked, const std::vector<int>& rank_nodes);
  /// Sets the matrix from this rank's part M (the pattern of make()):
  /// collective.
  void copy_values(const SparseMatrix& M);
  /// This rank's entries of a full vector of the matrix's rows:
  /// out[p − first_row()] = full[p].
  void local_entries(const double* full, PetscScalar* out) const;
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
  std::vector<int> outer_, inner_;  ///< the CSC pattern of this rank's part the matrix was made for
  PetscInt first_ = 0, end_ = 0;
  std::vector<std::int64_t> ranges_;
  int block_ = 1;                             ///< rows per stored block (1: MPIAIJ)
  /// CSC position → its value's position in PETSc's diagonal block, or
  /// diagonal_values_ + its position in the off-diagonal block (≥ 0), or
  /// −1 − its position in send_.
  std::vector<PetscInt> to_;
  PetscInt diagonal_values_ = 0, off_values_ = 0;  ///< the two blocks' values
  std::vector<PetscScalar> send_;                  ///< the values for other ranks' rows, by rank
  std::vector<int> send_counts_, receive_counts_;  ///< per rank, the values sent to it and received from it
  std::vector<PetscInt> received_to_;              ///< per received value: its position, as to_'s
  ::Mat A_ = nullptr;
  ::Vec b_ = nullptr, x_ = nullptr, all_ = nullptr;
  VecScatter gather_ = nullptr;
};

}  // namespace conserve::solver::petsc
