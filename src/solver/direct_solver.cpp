#include "solver/direct_solver.hpp"

#include <fmt/format.h>
#include <algorithm>

#include "core/error.hpp"

namespace conserve::solver {

bool DirectSolver::same_pattern(const SparseMatrix& A) const {
  return static_cast<Eigen::Index>(outer_.size()) == A.outerSize() + 1 &&
         static_cast<Eigen::Index>(inner_.size()) == A.nonZeros() &&
         std::equal(outer_.begin(), outer_.end(), A.outerIndexPtr()) &&
         std::equal(inner_.begin(), inner_.end(), A.innerIndexPtr());
}

DirectSolver::DirectSolver() {
  // Newton corrects the solution itself: UMFPACK's iterative refinement
  // (two extra solves and products per solve by default) is wasted work.
  lu_.umfpackControl()(UMFPACK_IRSTEP) = 0;
  lu_.umfpackControl()(UMFPACK_ORDERING) = UMFPACK_ORDERING_METIS;
  lu_.umfpackControl()(UMFPACK_STRATEGY) = UMFPACK_STRATEGY_SYMMETRIC;
}

namespace {
std::string umfpack_status(int code) {
  switch (code) {
    case UMFPACK_WARNING_singular_matrix: return "singular matrix";
    case UMFPACK_ERROR_out_of_memory: return "out of memory";
    case UMFPACK_ERROR_invalid_matrix: return "invalid matrix";
    default: return fmt::format("UMFPACK status {}", code);
  }
}
}  // namespace

void DirectSolver::set_operator(const SparseMatrix& A) {
  ScopedTimer timer(clock(&Timings::linear_setup));
  count(&Timings::linear_setups);
  const bool analyse = !same_pattern(A);
  if (analyse) {
    A_ = A.cast<double>();  // copies the pattern into 64-bit indices
    count(&Timings::analyses);
    outer_.assign(A.outerIndexPtr(), A.outerIndexPtr() + A.outerSize() + 1);
    inner_.assign(A.innerIndexPtr(), A.innerIndexPtr() + A.nonZeros());
    lu_.analyzePattern(A_);
    ++analyses_;
  } else {
    std::copy(A.valuePtr(), A.valuePtr() + A.nonZeros(), A_.valuePtr());
  }
  lu_.factorize(A_);
  if (lu_.info() != Eigen::Success)
    throw SolverError(fmt::format("UMFPACK could not factorise the tangent matrix ({} equations): {}", A.rows(),
                                  umfpack_status(lu_.umfpackFactorizeReturncode())));
}

LinearSolve DirectSolver::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x, double /*rtol*/) {
  ScopedTimer timer(clock(&Timings::linear_solve));
  if (timings_) ++timings_->linear_solves, ++timings_->linear_iterations;
  x = lu_.solve(b);
  if (lu_.info() != Eigen::Success) throw SolverError("UMFPACK solve failed");
  if (!x.allFinite()) throw SolverError("the LU solve gave a non-finite increment");
  return {1, 0.0};
}

}  // namespace conserve::solver
