#include "solver/ranks.hpp"

#include <mpi.h>
#include <petscsys.h>

#include <cstdlib>
#include <exception>
#include <string>

#include "core/error.hpp"
#include "solver/petsc_session.hpp"

namespace conserve::solver::ranks {
namespace {

/// Whether a launcher (mpiexec, srun) started this process: then MPI
/// starts at the first call here. A process started alone is rank 0 of 1
/// and starts MPI only if PETSc is used (as a singleton).
bool launched() {
  static const bool by_launcher =
      std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMI_SIZE") || std::getenv("PMIX_RANK");
  return by_launcher;
}

bool started() {
  int yes = 0;
  MPI_Initialized(&yes);
  return yes != 0;
}

MPI_Comm world() {
  petsc::ensure_initialized();
  return PETSC_COMM_WORLD;
}

/// The kinds of error that cross ranks, in the CLI's exit codes' order.
enum Kind : int { none = 0, input = 1, solver = 3, other = 4 };

}  // namespace

int rank() {
  if (!launched() && !started()) return 0;
  int r = 0;
  MPI_Comm_rank(world(), &r);
  return r;
}

int size() {
  if (!launched() && !started()) return 1;
  int n = 1;
  MPI_Comm_size(world(), &n);
  return n;
}

namespace {

/// `value` combined over the ranks by `op` (collective).
template <class T>
T reduce(T value, MPI_Datatype type, MPI_Op op) {
  if (size() == 1) return value;
  T out = value;
  MPI_Allreduce(&value, &out, 1, type, op, world());
  return out;
}

}  // namespace

int max(int value) { return reduce(value, MPI_INT, MPI_MAX); }
double max(double value) { return reduce(value, MPI_DOUBLE, MPI_MAX); }
double sum(double value) { return reduce(value, MPI_DOUBLE, MPI_SUM); }

std::vector<double> all(double value) {
  std::vector<double> out(static_cast<std::size_t>(size()), value);
  if (out.size() > 1) MPI_Allgather(&value, 1, MPI_DOUBLE, out.data(), 1, MPI_DOUBLE, world());
  return out;
}

void broadcast(Eigen::VectorXd& x, int from) {
  if (size() == 1) return;
  long n = static_cast<long>(x.size());
  MPI_Bcast(&n, 1, MPI_LONG, from, world());
  x.resize(n);
  MPI_Bcast(x.data(), static_cast<int>(n), MPI_DOUBLE, from, world());
}

void broadcast(std::vector<int>& x, int from) {
  if (size() == 1) return;
  long n = static_cast<long>(x.size());
  MPI_Bcast(&n, 1, MPI_LONG, from, world());
  x.resize(static_cast<std::size_t>(n));
  MPI_Bcast(x.data(), static_cast<int>(n), MPI_INT, from, world());
}

void gather_segments(double* data, const std::vector<int>& counts) {
  if (size() == 1) return;
  std::vector<int> starts(counts.size(), 0);
  for (std::size_t r = 1; r < counts.size(); ++r) starts[r] = starts[r - 1] + counts[r - 1];
  MPI_Allgatherv(MPI_IN_PLACE, 0, MPI_DATATYPE_NULL, data, counts.data(), starts.data(), MPI_DOUBLE, world());
}

void together(const std::function<void()>& body, bool root_only) {
  Kind kind = none;
  std::string message;
  if (!root_only || rank() == 0) {
    try {
      body();
    } catch (const InputError& e) {
      kind = input, message = e.what();
    } catch (const SolverError& e) {
      kind = solver, message = e.what();
    } catch (const std::exception& e) {
      kind = other, message = e.what();
    }
  }
  if (size() == 1) {
    if (kind == none) return;
  } else {
    // The lowest rank that failed tells the others what went wrong.
    const int mine = kind == none ? size() : rank();
    int first = mine;
    MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, world());
    if (first == size()) return;
    int header[2] = {kind, static_cast<int>(message.size())};
    MPI_Bcast(header, 2, MPI_INT, first, world());
    kind = static_cast<Kind>(header[0]);
    message.resize(static_cast<std::size_t>(header[1]));
    MPI_Bcast(message.data(), header[1], MPI_CHAR, first, world());
  }
  if (kind == input) throw InputError(message);
  if (kind == solver) throw SolverError(message);
  throw Error(message);
}

void finalize() {
  if (launched()) petsc::finalize();
}

}  // namespace conserve::solver::ranks
