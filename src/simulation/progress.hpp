#pragma once
/// The progress line of a long run: step, time, energy drift, Newton
/// iterations, elapsed time and ETA, about once a second (or every N steps).
/// On a terminal it rewrites one line; otherwise it prints lines.
#include <chrono>
#include <cstdio>

namespace conserve::simulation {

/// Where a run stands, as the progress line shows it.
struct ProgressPoint {
  int step = 0;              ///< steps done since t = 0
  int expected_steps = 0;    ///< step number the run is expected to end at (grows after cutbacks)
  double time = 0.0;         ///< simulated time [s]
  double fraction = 0.0;     ///< share of this invocation's work done, in [0, 1]
  double energy_drift = 0.0; ///< running max of |ΔE|/E
  int newton_iterations = 0; ///< of the last step
  bool last = false;         ///< the last step of the run: always printed
};

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
