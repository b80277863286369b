#pragma once
/// Threads of the assembly loops (OpenMP). Results do not depend on them:
/// every sum is taken in one fixed order (assembly/partition.hpp).
/// Without OpenMP there is one thread and setting them does nothing.

namespace conserve::assembly {

/// Models with fewer cells are assembled on one thread: starting threads
/// would cost more than they give.
inline constexpr int kMinParallelCells = 2048;

/// Threads the next assembly uses (OMP_NUM_THREADS or the cores by default).
int threads();

/// Sets the threads of later assemblies (≥ 1); false without OpenMP.
bool set_threads(int threads);

}  // namespace conserve::assembly
