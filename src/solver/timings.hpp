#pragma once
/// Wall-clock accounting of where a run's time goes (bench/ and the run
/// summary): accumulated seconds per phase.
#include <chrono>

namespace conserve::solver {

struct Timings {
  double assembly = 0.0;        ///< residual and tangent assembly [s]
  double elimination = 0.0;     ///< contact reduction (Wᵀ K T, Wᵀ g) and slave updates [s]
  double linear_setup = 0.0;    ///< factorization (symbolic + numeric) or preconditioner set-up [s]
  double linear_solve = 0.0;    ///< triangular solves or Krylov iterations [s]
  double contact_search = 0.0;  ///< active-set updates: broad and narrow phase [s]
  int linear_setups = 0;        ///< factorizations or preconditioner set-ups
  int analyses = 0;             ///< symbolic analyses of the direct solver (pattern changes)
  long long linear_iterations = 0;  ///< Krylov iterations (direct: one per solve)
  long long linear_solves = 0;
  int linear_fallbacks = 0;     ///< Krylov solves that stagnated and were redone by the LU
  int lu_first = 0;             ///< matrices sent to the LU without a Krylov attempt, after a stagnation
};

/// Adds the lifetime of the scope to a counter.
class ScopedTimer {
 public:
  explicit ScopedTimer(double& seconds) : seconds_(seconds), start_(std::chrono::steady_clock::now()) {}
  ~ScopedTimer() { seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }
  ScopedTimer(const ScopedTimer&) = delete;
  ScopedTimer& operator=(const ScopedTimer&) = delete;

 private:
  double& seconds_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace conserve::solver
