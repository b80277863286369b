#include "assembly/threads.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace conserve::assembly {

int threads() {
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

bool set_threads(int threads) {
#ifdef _OPENMP
  omp_set_num_threads(threads < 1 ? 1 : threads);
  return true;
#else
  (void)threads;
  return false;
#endif
}

}  // namespace conserve::assembly
