#pragma once
/// Sparse direct solve of the (non-symmetric) Newton systems with UMFPACK.
/// The symbolic analysis is kept and reused while the sparsity pattern does
/// not change; only the numeric factorisation is redone per iteration.
#include <Eigen/UmfPackSupport>
#include <vector>

#include "core/types.hpp"

namespace conserve::solver {

class LinearSolver {
 public:
  LinearSolver();
  /// Factorises A (re-analysing only if its pattern differs from the last
  /// one). Throws SolverError if A is singular.
  void factorize(const SparseMatrix& A);
  /// Solves A x = b with the last factorisation.
  void solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) const;
  /// Number of symbolic analyses done (for tests of the reuse).
  [[nodiscard]] int analyses() const { return analyses_; }

 private:
  [[nodiscard]] bool same_pattern(const SparseMatrix& A) const;
  Eigen::UmfPackLU<SparseMatrix> lu_;
  std::vector<int> outer_, inner_;
  int analyses_ = 0;
};

}  // namespace conserve::solver
