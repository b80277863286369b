#pragma once
/// Sparse direct solve of the (non-symmetric) Newton systems with UMFPACK,
/// the reference back end. The symbolic analysis is kept and reused while
/// the sparsity pattern does not change; only the numeric factorization is
/// redone per matrix. UMFPACK's 64-bit interface (umfpack_dl) is used: the
/// 32-bit one fails on 3D problems of about 200k unknowns, whose LU factors
/// pass 2^31 entries.
#include <Eigen/UmfPackSupport>
#include <vector>

#include "solver/linear_solver.hpp"

namespace conserve::solver {

class DirectSolver final : public LinearSolver {
 public:
  DirectSolver();
  /// Factorizes A (re-analysing only if its pattern differs from the last
  /// one). Throws SolverError if A is singular.
  void set_operator(const SparseMatrix& A) override;
  LinearSolve solve(const Eigen::VectorXd& b, Eigen::VectorXd& x, double rtol) override;
  [[nodiscard]] bool exact() const override { return true; }
  [[nodiscard]] std::string name() const override { return "UMFPACK LU"; }
  /// Number of symbolic analyses done (for tests of the reuse).
  [[nodiscard]] int analyses() const { return analyses_; }

 private:
  using LongMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, SuiteSparse_long>;
  [[nodiscard]] bool same_pattern(const SparseMatrix& A) const;
  LongMatrix A_;  ///< 64-bit-index copy of the matrix UMFPACK factorizes (it keeps a reference)
  Eigen::UmfPackLU<LongMatrix> lu_;
  std::vector<int> outer_, inner_;
  int analyses_ = 0;
};

}  // namespace conserve::solver
