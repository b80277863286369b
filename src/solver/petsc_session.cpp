#include "solver/petsc_session.hpp"

#include <fmt/format.h>
#include <mpi.h>
#include <petscsys.h>

#include <cstdlib>

#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/lsan_interface.h>
#endif

#include "core/error.hpp"

namespace conserve::solver::petsc {
namespace {

struct Session {
  Session() {
    // OpenMPI refuses to start as root unless told; a singleton process
    // (no mpirun) is what a plain run is. Only set when absent.
    setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 0);
    setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 0);
    // Errors must reach the caller as exceptions, not as PETSc's
    // traceback on stderr or its signal handler.
    PetscOptionsSetValue(nullptr, "-no_signal_handler", nullptr);
    // MPI is started here, not by PETSc; finalize() ends it (a parallel
    // run must), else it is left to the process's exit.
    // What MPI and PETSc allocate while starting lives as long as the
    // process, partly in plug-ins OpenMPI unloads again; under the
    // sanitizers it is not counted as leaked (scripts/sanitize.sh).
#if defined(__SANITIZE_ADDRESS__)
    __lsan::ScopedDisabler process_lifetime;
#endif
    int started = 0;
    MPI_Initialized(&started);
    if (!started && MPI_Init(nullptr, nullptr) != MPI_SUCCESS) throw SolverError("MPI could not be initialised");
    owns_mpi = !started;
    if (PetscInitializeNoArguments() != 0) throw SolverError("PETSc could not be initialised");
    PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
  }
  ~Session() { end(); }
  void end() {
    PetscBool done = PETSC_TRUE;
    PetscFinalized(&done);
    if (!done) PetscFinalize();
    int finalized = 1;
    MPI_Finalized(&finalized);
    if (owns_mpi && !finalized && ending) MPI_Finalize();
  }
  bool owns_mpi = false;
  bool ending = false;  ///< finalize() was called: MPI ends too
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;
};

Session& session() {
  static Session instance;
  return instance;
}

}  // namespace

void ensure_initialized() { session(); }

void finalize() {
  int started = 0;
  MPI_Initialized(&started);
  if (!started) return;
  Session& s = session();
  s.ending = true;
  s.end();
}

void check(int code, const char* what) {
  if (code == 0) return;
  const char* text = nullptr;
  PetscErrorMessage(static_cast<PetscErrorCode>(code), &text, nullptr);
  throw SolverError(fmt::format("{}: PETSc error {} ({})", what, code, text ? text : "no message"));
}

}  // namespace conserve::solver::petsc
