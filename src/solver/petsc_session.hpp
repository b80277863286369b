#pragma once
/// MPI and PETSc initialised once per process, on first use; PETSc is
/// finalised at exit, MPI is left to the process's end. PETSc's own signal handler is switched off, and
/// its errors come back as return codes that check() turns into
/// SolverError with PETSc's message.
namespace conserve::solver::petsc {

/// Initialises PETSc if it is not yet (idempotent, not thread-safe).
void ensure_initialized();

/// Throws SolverError "`what`: <PETSc's message>" if `code` is an error.
void check(int code, const char* what);

}  // namespace conserve::solver::petsc
