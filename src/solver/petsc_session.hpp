#pragma once
/// MPI and PETSc initialised once per process, on first use; PETSc is
/// finalised at exit (or by finalize()), MPI by finalize() only: a process
/// of a parallel run must end it, a single one may leave it to the
/// process's end. PETSc's own signal handler is switched off, and
/// its errors come back as return codes that check() turns into
/// SolverError with PETSc's message.
namespace conserve::solver::petsc {

/// Initialises PETSc if it is not yet (idempotent, not thread-safe).
void ensure_initialized();

/// Ends PETSc, and MPI if this process started it (idempotent).
void finalize();

/// Throws SolverError "`what`: <PETSc's message>" if `code` is an error.
void check(int code, const char* what);

}  // namespace conserve::solver::petsc
