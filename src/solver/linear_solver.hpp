#pragma once
/// The linear solver Newton uses, as an interface with two back ends:
///   direct  UMFPACK LU (solver/direct_solver.hpp), exact, the reference;
///   krylov  PETSc GMRES, right-preconditioned by ILU(0) or by GAMG with the
///           rigid-body near-null space (solver/krylov_solver.hpp), solving
///           to the relative tolerance Newton asks for.
/// A solver is given a matrix (set_operator) and then solves with it any
/// number of times; what it derives from the matrix (a factorization, a
/// preconditioner) is its own business.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/types.hpp"
#include "solver/timings.hpp"

namespace conserve::solver {

enum class Method { krylov, direct };
enum class Preconditioner { automatic, ilu, gamg };

struct LinearSolverSettings {
  Method method = Method::krylov;
  /// automatic: ILU(0) (block Jacobi with ILU(0) on several ranks) below
  /// `gamg_from` unknowns, GAMG from there on; by default never GAMG.
  /// Measured on the §6.3 ball (RCM-ordered mesh, one thread per rank):
  /// a Newton iteration with ILU(0) took 9.7 s against 34.8 s with GAMG
  /// at 2.93M unknowns on one rank, 6.3 s against 15.1 s on two
  /// (bench/results/scaling_model.md), and 3.6–4.5× less at 320k and
  /// 1.18M (bench/results/size_sweep.md).
  Preconditioner preconditioner = Preconditioner::automatic;
  int gamg_from = 2147483647;
  /// GMRES iterations per solve; a solve that reaches them returns its
  /// best iterate and Newton judges the nonlinear residual.
  int max_iterations = 200;
  /// Extra PETSc options ("-ksp_monitor -pc_gamg_threshold 0.02"), applied
  /// process-wide before the solver reads its options.
  std::string petsc_options;
};

/// What a solve did.
struct LinearSolve {
  int iterations = 0;     ///< Krylov iterations (1 for a direct solve)
  double residual = 0.0;  ///< |b − A x| reached (0 for a direct solve: round-off)
};

class LinearSolver {
 public:
  virtual ~LinearSolver() = default;
  /// The matrix of the following solves. Throws SolverError if it cannot
  /// be used (a singular matrix for the direct solver).
  virtual void set_operator(const SparseMatrix& A) = 0;
  /// Solves A x = b with |b − A x| ≤ rtol·|b| (the direct solver ignores
  /// rtol: it is exact to round-off). A Krylov solve that runs out of
  /// iterations returns its best x. Throws SolverError on a non-finite x
  /// or a failed preconditioner.
  virtual LinearSolve solve(const Eigen::VectorXd& b, Eigen::VectorXd& x, double rtol) = 0;
  /// True for a direct solver: Newton then needs no forcing terms.
  [[nodiscard]] virtual bool exact() const = 0;
  /// True while a new operator costs about a few solves (an ILU or AMG
  /// set-up), not a factorization: Newton then takes fresh tangents
  /// readily (NewtonSettings::fresh_ratio).
  [[nodiscard]] virtual bool cheap_setup() const { return !exact(); }
  /// Forgets what is kept from earlier matrices beyond the present one
  /// (GAMG's interpolation).
  virtual void reset() {}
  /// Changes when the solver starts keeping something derived from the
  /// matrix it is set with for later matrices (GAMG builds its
  /// interpolation from the first matrix of a pattern, after a reset);
  /// constant for a solver that keeps nothing beyond the present matrix.
  /// With it a checkpoint knows which matrices to set again so that the
  /// solver is as it was (time/integrator.hpp).
  [[nodiscard]] virtual std::uint64_t generation() const { return 0; }
  /// The solver's own state beyond its matrices (which solver the next
  /// matrices go to), as bytes, and back: a checkpoint carries it.
  [[nodiscard]] virtual std::string save_state() const { return {}; }
  virtual void load_state(const std::string& /*bytes*/) {}
  /// Reference coordinates of the nodes (D × nodes) for preconditioners
  /// that use the rigid-body modes; ignored by the others.
  virtual void set_coordinates(const Eigen::MatrixXd& /*X*/) {}
  /// On several ranks, the ranks' nodes (model::Model::rank_nodes): rank r
  /// owns the rows of nodes [rank_nodes[r], rank_nodes[r+1]), the rows
  /// beyond the nodes' are the last rank's, and each rank's matrix holds
  /// its part of the system (petsc_system.hpp); ignored on one rank.
  virtual void set_layout(const std::vector<int>& /*rank_nodes*/) {}
  /// On several ranks, the present matrix's rows by rank: each rank's
  /// first row, then the number of rows (empty on one rank).
  [[nodiscard]] virtual std::vector<std::int64_t> row_ranges() const { return {}; }
  /// "UMFPACK LU", "GMRES + ILU(0)", ... for the run's report.
  [[nodiscard]] virtual std::string name() const = 0;
  /// Where time went (may be null).
  void set_timings(Timings* timings) { timings_ = timings; }

 protected:
  double& clock(double Timings::*phase) { return timings_ ? timings_->*phase : unused_; }
  void count(int Timings::*counter, int n = 1) {
    if (timings_) timings_->*counter += n;
  }
  Timings* timings_ = nullptr;

 private:
  double unused_ = 0.0;
};

/// The back end `settings` names, for systems of `unknowns` equations.
std::unique_ptr<LinearSolver> make_linear_solver(const LinearSolverSettings& settings, int unknowns);

}  // namespace conserve::solver
