#pragma once
/// The direct back end on several ranks: PETSc's interface to MUMPS, a
/// distributed LU (the system's rows split over the ranks as for the
/// Krylov solver, solver/petsc_system.hpp). The symbolic analysis is kept
/// while the pattern stays. One rank uses UMFPACK (solver/direct_solver.hpp).
#include <memory>

#include "solver/linear_solver.hpp"

namespace conserve::solver {

class MumpsSolver final : public LinearSolver {
 public:
  /// Throws InputError if this PETSc has no MUMPS.
  MumpsSolver();
  ~MumpsSolver() override;
  MumpsSolver(const MumpsSolver&) = delete;
  MumpsSolver& operator=(const MumpsSolver&) = delete;
  /// Factorizes A; throws SolverError if it is singular.
  void set_operator(const SparseMatrix& A) override;
  LinearSolve solve(const Eigen::VectorXd& b, Eigen::VectorXd& x, double rtol) override;
  [[nodiscard]] bool exact() const override { return true; }
  [[nodiscard]] std::string name() const override;
  [[nodiscard]] std::vector<std::int64_t> row_ranges() const override;
  /// The nodes' dimension (rows per node) from the coordinates' rows.
  void set_coordinates(const Eigen::MatrixXd& X) override;
  void set_layout(const std::vector<int>& rank_nodes) override;

 private:
  struct Petsc;
  std::unique_ptr<Petsc> petsc_;
};

}  // namespace conserve::solver
