#pragma once
/// Wall-clock accounting of where a run's time goes (bench/ and the run
/// summary): accumulated seconds per phase.
#include <chrono>

namespace conserve::solver {

struct Timings {
  double assembly = 0.0;        ///< residual and tangent assembly [s]
  double elimination = 0.0;     ///< contact reduction (Tᵀ K T′, Tᵀ g) and slave updates [s]
  double factorization = 0.0;   ///< UMFPACK symbolic + numeric [s]
  double solve = 0.0;           ///< triangular solves [s]
  double contact_search = 0.0;  ///< active-set updates: broad and narrow phase [s]
  int factorizations = 0;
  int analyses = 0;             ///< symbolic analyses (pattern changes)
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
