#pragma once
/// PETSc GMRES on the (non-symmetric, not always definite) Newton systems,
/// right-preconditioned so that its tolerance is on the true residual
/// |b − A x|. Preconditioners:
///   ILU(0) in the nodes' order, rebuilt for every matrix (a
///     stale one costs more GMRES iterations than a new one costs to make);
///   GAMG (smoothed aggregation) with the rigid-body modes of the nodes as
///     near-null space; its interpolation is kept while the pattern stays
///     and only the coarse operators are recomputed.
/// A solve whose GMRES stagnates far from its tolerance falls back to the
/// UMFPACK LU for that matrix (Timings::linear_fallbacks counts them). It
/// is found at the end of a restart cycle: if the cycle's reduction of the
/// residual, kept up, would not reach the tolerance within the iteration
/// limit, the solve ends there instead of running to the limit. After
/// such a matrix the next one goes to the LU without a GMRES attempt
/// (Timings::lu_first counts them), then after each attempt that
/// stagnates again twice as many, up to 32; an attempt that converges
/// ends the run.
/// PETSc objects are hidden here (pimpl): nothing above this layer sees a
/// PETSc header. One process for now (PETSC_COMM_SELF).
#include <memory>

#include "solver/linear_solver.hpp"

namespace conserve::solver {

class KrylovSolver final : public LinearSolver {
 public:
  /// `preconditioner` is ilu or gamg (automatic is resolved by the caller).
  KrylovSolver(Preconditioner preconditioner, const LinearSolverSettings& settings);
  ~KrylovSolver() override;
  KrylovSolver(const KrylovSolver&) = delete;
  KrylovSolver& operator=(const KrylovSolver&) = delete;

  void set_operator(const SparseMatrix& A) override;
  LinearSolve solve(const Eigen::VectorXd& b, Eigen::VectorXd& x, double rtol) override;
  [[nodiscard]] bool exact() const override { return false; }
  /// False while the matrices go to the LU (after a stagnated GMRES).
  [[nodiscard]] bool cheap_setup() const override;
  void reset() override;
  /// GAMG: a new KSP (pattern or reset) builds a new interpolation.
  [[nodiscard]] std::uint64_t generation() const override;
  /// Whether the present matrix went to the LU, and the LU-first counters.
  [[nodiscard]] std::string save_state() const override;
  /// After the present matrix is set again: the counters, and its LU if it had one.
  void load_state(const std::string& bytes) override;
  void set_coordinates(const Eigen::MatrixXd& X) override;
  void set_layout(const std::vector<int>& rank_nodes) override;
  [[nodiscard]] std::string name() const override;
  [[nodiscard]] std::vector<std::int64_t> row_ranges() const override;

 private:
  LinearSolve fallback(const Eigen::VectorXd& b, Eigen::VectorXd& x);
  struct Petsc;
  std::unique_ptr<Petsc> petsc_;
};

}  // namespace conserve::solver
