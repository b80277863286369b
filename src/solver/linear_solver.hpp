#pragma once
/// Sparse direct solve of the (non-symmetric) Newton systems with UMFPACK.
/// The symbolic analysis is kept and reused while the sparsity pattern does
/// not change; only the numeric factorisation is redone per iteration.
/// UMFPACK's 64-bit interface (umfpack_dl) is used: the 32-bit one fails on
/// 3D problems of about 200k unknowns, whose LU factors pass 2^31 entries.
#include <Eigen/UmfPackSupport>
#include <vector>

#include "core/types.hpp"
#include "solver/timings.hpp"

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
  /// Where time went; factorization, solve and the counts are filled here.
  void set_timings(Timings* timings) { timings_ = timings; }

 private:
  using LongMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, SuiteSparse_long>;
  [[nodiscard]] bool same_pattern(const SparseMatrix& A) const;
  LongMatrix A_;  ///< 64-bit-index copy of the matrix UMFPACK factorises (it keeps a reference)
  Eigen::UmfPackLU<LongMatrix> lu_;
  std::vector<int> outer_, inner_;
  int analyses_ = 0;
  Timings* timings_ = nullptr;
  mutable double unused_ = 0.0;  ///< timer sink when no Timings is set
};

}  // namespace conserve::solver
