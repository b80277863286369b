#pragma once
/// Threads of the BLAS behind UMFPACK. OpenBLAS threads spin while they
/// wait; on the Newton systems of this program (fronts of a few hundred
/// rows) they cost more than they give, measured in bench/. The default of
/// the command line is one thread.

namespace conserve::solver {

/// Sets the number of BLAS threads if the BLAS is OpenBLAS; returns false
/// (and does nothing) with another BLAS.
bool set_blas_threads(int threads);

}  // namespace conserve::solver
