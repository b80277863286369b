#pragma once
/// The MPI ranks of a run (PETSc's world communicator). Each rank holds
/// the whole model's nodes and state and takes the same decisions from
/// the same bits; what is distributed is the assembly and the tangent
/// (each rank owns a range of the nodes and their rows, with the cells
/// around them: model::Model::rank_nodes), the linear solve
/// (solver/petsc_system.hpp) and the VTU pieces.
/// Without a launcher there is one rank. Functions marked collective must
/// be called by every rank, in the same order.
#include <Eigen/Core>
#include <functional>
#include <vector>

namespace conserve::solver::ranks {

/// This process's rank and the number of ranks. Under a launcher MPI
/// starts on first use; a process started alone is rank 0 of 1.
[[nodiscard]] int rank();
[[nodiscard]] int size();
[[nodiscard]] inline bool root() { return rank() == 0; }

/// The largest of the ranks' values (collective).
[[nodiscard]] int max(int value);
[[nodiscard]] double max(double value);

/// The sum of the ranks' values (collective).
[[nodiscard]] double sum(double value);

/// Every rank's value in rank order (collective): what a sum that must
/// give the same bits run after run adds up in that order.
[[nodiscard]] std::vector<double> all(double value);

/// Rank `from`'s x on every rank, resized there (collective).
void broadcast(Eigen::VectorXd& x, int from = 0);
void broadcast(std::vector<int>& x, int from = 0);

/// Every rank's segment of `data` from that rank: data holds the ranks'
/// segments in rank order, counts[r] values each (collective).
void gather_segments(double* data, const std::vector<int>& counts);

/// Runs `body` on every rank (`root_only`: on rank 0 alone) and makes its
/// failure collective: if it throws on any rank, every rank throws the
/// error of the lowest rank that failed, of the same kind (InputError,
/// SolverError, Error) with the same message. So what one rank does alone
/// (write a file) cannot leave the others waiting in the next collective
/// call (collective).
void together(const std::function<void()>& body, bool root_only = false);
inline void on_root(const std::function<void()>& body) { together(body, true); }

/// Ends MPI (and PETSc) in a process a launcher started (mpiexec requires
/// it of every rank): the last call of the program.
void finalize();

}  // namespace conserve::solver::ranks
