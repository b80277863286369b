#include "solver/blas_threads.hpp"

// Weak: resolved only when the BLAS linked in is OpenBLAS.
extern "C" void openblas_set_num_threads(int) __attribute__((weak));

namespace conserve::solver {

bool set_blas_threads(int threads) {
  if (!openblas_set_num_threads) return false;
  openblas_set_num_threads(threads);
  return true;
}

}  // namespace conserve::solver
