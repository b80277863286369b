#include "solver/linear_solver.hpp"

#include "solver/direct_solver.hpp"
#include "solver/krylov_solver.hpp"

namespace conserve::solver {

std::unique_ptr<LinearSolver> make_linear_solver(const LinearSolverSettings& settings, int unknowns) {
  if (settings.method == Method::direct) return std::make_unique<DirectSolver>();
  Preconditioner pc = settings.preconditioner;
  if (pc == Preconditioner::automatic) pc = unknowns < settings.gamg_from ? Preconditioner::ilu : Preconditioner::gamg;
  return std::make_unique<KrylovSolver>(pc, settings);
}

}  // namespace conserve::solver
