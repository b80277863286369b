#pragma once
/// The progress line of a long run: step, time, energy drift, Newton
/// iterations, elapsed time and ETA, about once a second (or every N steps).
/// On a terminal it rewrites one line; otherwise it prints lines.
#include <chrono>
#include <cstdint>
#include <cstdio>

namespace conserve::simulation {

/// Where a run stands, as the progress line shows it.
struct ProgressPoint {
  std::int64_t step = 0;            ///< steps done since t = 0
  std::int64_t expected_steps = 0;  ///< step number the run is expected to end at (grows after cutbacks)
  double time = 0.0;                ///< simulated time [s]
  double fraction = 0.0;            ///< share of this invocation's work done, in [0, 1]
  double energy_drift = 0.0;        ///< |E − E0|/E_ref of this step (simulation/drift.hpp)
  int newton_iterations = 0;        ///< of the last step
  bool last = false;                ///< the last step of the run: always printed
};

/// Steps an invocation still has to take after `taken` of its own, the
/// last of which reached `time` [s]: to the end time `end` [s] at the
/// current step size `dt` [s] (the last one may be shorter), but at most
/// `max_steps` − `taken`; at least 1 unless `last`, 0 if `last`. Saturates
/// at 2^62 instead of overflowing (a step size far below end/2^62).
std::int64_t steps_left(double time, double end, double dt, std::int64_t taken, std::int64_t max_steps, bool last);

class ProgressLine {
 public:
  /// `every` > 0: print every that many steps; 0: about once a second.
  ProgressLine(std::FILE* out, int every);
  /// Prints the line if due; the ETA extrapolates the elapsed time by
  /// `fraction`, so it stays right when cutbacks add steps.
  void update(const ProgressPoint& p);
  /// Ends the line (on a terminal).
  void finish();
  [[nodiscard]] double elapsed() const;

 private:
  std::FILE* out_;
  int every_;
  bool tty_;
  std::chrono::steady_clock::time_point start_, last_;
  bool printed_ = false;
};

}  // namespace conserve::simulation
