#include "solver/linear_solver.hpp"

#include "solver/direct_solver.hpp"
#include "solver/krylov_solver.hpp"
#include "solver/mumps_solver.hpp"
#include "solver/ranks.hpp"

namespace conserve::solver {

std::unique_ptr<LinearSolver> make_linear_solver(const LinearSolverSettings& settings, int unknowns) {
  if (settings.method == Method::direct) {
    if (ranks::size() > 1) return std::make_unique<MumpsSolver>();
    return std::make_unique<DirectSolver>();
  }
  Preconditioner pc = settings.preconditioner;
  if (pc == Preconditioner::automatic) pc = unknowns < settings.gamg_from ? Preconditioner::ilu : Preconditioner::gamg;
  return std::make_unique<KrylovSolver>(pc, settings);
}

}  // namespace conserve::solver
