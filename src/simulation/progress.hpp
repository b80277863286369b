#pragma once
/// The progress line of a long run: step, time, energy drift, Newton
/// iterations, elapsed time and ETA, about once a second (or every N steps).
/// On a terminal it rewrites one line; otherwise it prints lines.
#include <chrono>
#include <cstdio>

namespace conserve::simulation {

class ProgressLine {
 public:
  /// `every` > 0: print every that many steps; 0: about once a second.
  ProgressLine(std::FILE* out, int total_steps, int every);
  void update(int step, double time, double energy_drift, int newton_iterations);
  /// Ends the line (on a terminal) and prints the wall time.
  void finish();
  [[nodiscard]] double elapsed() const;

 private:
  std::FILE* out_;
  int total_;
  int every_;
  bool tty_;
  std::chrono::steady_clock::time_point start_, last_;
  bool printed_ = false;
};

}  // namespace conserve::simulation
