#include "solver/mumps_solver.hpp"

#include <algorithm>

#include <fmt/format.h>
#include <petscksp.h>

#include "core/error.hpp"
#include "solver/petsc_session.hpp"
#include "solver/petsc_system.hpp"
#include "solver/ranks.hpp"

namespace conserve::solver {

using petsc::check;

struct MumpsSolver::Petsc {
  petsc::DistributedSystem system;
  KSP ksp = nullptr;
  int dim = 1;                  ///< rows per node
  std::vector<int> rank_nodes;  ///< the ranks' nodes (set_layout)
  ~Petsc() {
    if (ksp) KSPDestroy(&ksp);
  }
};

MumpsSolver::MumpsSolver() : petsc_(std::make_unique<Petsc>()) {
  petsc::ensure_initialized();
  PetscBool has = PETSC_FALSE;
  check(PetscHasExternalPackage("mumps", &has), "PetscHasExternalPackage");
  if (!has)
    throw InputError(fmt::format(
        "[solver] method = \"direct\" on {} ranks needs PETSc with MUMPS, which this PETSc does not have: run on one "
        "rank or use method = \"krylov\"",
        ranks::size()));
}

MumpsSolver::~MumpsSolver() = default;

std::string MumpsSolver::name() const { return fmt::format("MUMPS LU on {} ranks", ranks::size()); }

std::vector<std::int64_t> MumpsSolver::row_ranges() const { return petsc_->system.row_ranges(); }

void MumpsSolver::set_coordinates(const Eigen::MatrixXd& X) { petsc_->dim = std::max(static_cast<int>(X.rows()), 1); }

void MumpsSolver::set_layout(const std::vector<int>& rank_nodes) { petsc_->rank_nodes = rank_nodes; }

void MumpsSolver::set_operator(const SparseMatrix& M) {
  Petsc& p = *petsc_;
  ScopedTimer timer(clock(&Timings::linear_setup));
  count(&Timings::linear_setups);
  if (ranks::max(p.ksp && p.system.same_pattern(M) ? 0 : 1) != 0) {  // collective: any rank's new pattern
    if (p.ksp) KSPDestroy(&p.ksp);
    p.system.make(M, p.dim, false, p.rank_nodes);
    check(KSPCreate(PETSC_COMM_WORLD, &p.ksp), "KSPCreate");
    check(KSPSetType(p.ksp, KSPPREONLY), "KSPSetType");
    PC pc = nullptr;
    check(KSPGetPC(p.ksp, &pc), "KSPGetPC");
    check(PCSetType(pc, PCLU), "PCSetType(lu)");
    check(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS), "PCFactorSetMatSolverType");
    check(KSPSetErrorIfNotConverged(p.ksp, PETSC_FALSE), "KSPSetErrorIfNotConverged");
    check(KSPSetOperators(p.ksp, p.system.matrix(), p.system.matrix()), "KSPSetOperators");
  }
  p.system.copy_values(M);
  if (KSPSetUp(p.ksp) != 0) throw SolverError("MUMPS could not factorize the matrix (singular?)");
  PC pc = nullptr;
  check(KSPGetPC(p.ksp, &pc), "KSPGetPC");
  PCFailedReason failed = PC_NOERROR;
  check(PCGetFailedReason(pc, &failed), "PCGetFailedReason");
  if (ranks::max(failed != PC_NOERROR ? 1 : 0) != 0) throw SolverError("MUMPS found the matrix singular");
}

LinearSolve MumpsSolver::solve(const Eigen::VectorXd& rhs, Eigen::VectorXd& out, double /*rtol*/) {
  Petsc& p = *petsc_;
  if (!p.ksp) throw Error("MumpsSolver::solve before set_operator");
  ScopedTimer timer(clock(&Timings::linear_solve));
  p.system.set_rhs(rhs);
  check(KSPSolve(p.ksp, p.system.rhs(), p.system.solution()), "the MUMPS solve");
  KSPConvergedReason reason;
  check(KSPGetConvergedReason(p.ksp, &reason), "KSPGetConvergedReason");
  if (reason < 0) throw SolverError(fmt::format("the MUMPS solve failed: {}", KSPConvergedReasons[reason]));
  p.system.gather_solution(out);
  if (timings_) ++timings_->linear_solves, ++timings_->linear_iterations;
  if (!out.allFinite()) throw SolverError("MUMPS gave a non-finite increment");
  return {1, 0.0};
}

}  // namespace conserve::solver
