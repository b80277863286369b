#pragma once
/// Threads of the assembly loops (OpenMP). Results do not depend on them:
/// every sum is taken in one fixed order (assembly/partition.hpp), so the
/// count may change between steps. Without OpenMP there is one thread and
/// setting them does nothing.
#include <chrono>
#include <optional>

namespace conserve::assembly {

/// Models with fewer cells are assembled on one thread: starting threads
/// would cost more than they give.
inline constexpr int kMinParallelCells = 2048;

/// Threads the next assembly uses (OMP_NUM_THREADS or the cores by default).
int threads();

/// Sets the threads of later assemblies (≥ 1); false without OpenMP.
bool set_threads(int threads);

/// The processors this process may run on (OpenMP's count; 1 without it).
int processors();

/// The cores other processes keep busy, measured between successive calls
/// as the machine's busy time (Linux /proc/stat) less this process's own
/// CPU time (getrusage), over the wall time between them.
class OtherLoad {
 public:
  OtherLoad();
  /// Cores busy with other processes since the last sample (or
  /// construction), and a new sample; nothing where /proc/stat cannot be
  /// read or less than `min_seconds` of wall time passed (no new sample).
  std::optional<double> sample(double min_seconds);
  /// Whether the load can be measured here.
  [[nodiscard]] bool available() const { return last_.has_value(); }

 private:
  struct Reading {
    std::chrono::steady_clock::time_point wall;
    double busy = 0.0;  ///< all cores' busy time since boot [s]
    double own = 0.0;   ///< this process's CPU time [s]
  };
  static std::optional<Reading> read();
  std::optional<Reading> last_;
};

/// Chooses the assembly's threads. A fixed count if one was asked for
/// ([solver] threads, else OMP_NUM_THREADS); otherwise (automatic) as
/// many as the cores other processes leave free, re-measured about every
/// kThreadCheckSeconds: a thread that shares a core with another busy
/// process makes every parallel loop wait for it, and two threads were
/// measured up to 5.6× slower than one on a loaded 2-core machine. An
/// automatic run starts on one thread and takes more once a measurement
/// shows the cores free. Models below kMinParallelCells cells keep one.
class ThreadGovernor {
 public:
  static constexpr double kThreadCheckSeconds = 1.0;
  /// The first measurement, after this much wall time on one thread.
  static constexpr double kFirstCheckSeconds = 0.25;
  /// A core counts as free while other processes use less than this of it.
  static constexpr double kFreeCoreSlack = 0.25;

  /// `requested` ≥ 1: that many threads; 0: automatic (unless
  /// OMP_NUM_THREADS is set, which then fixes the count). `cells`: the
  /// model's cells.
  ThreadGovernor(int requested, int cells);

  /// Automatic: re-measures when due and sets the threads. Call between steps.
  void update();

  [[nodiscard]] bool automatic() const { return automatic_; }
  /// Why the count is what it is: "automatic", "[solver] threads",
  /// "OMP_NUM_THREADS", "small model" (below kMinParallelCells cells),
  /// "one processor", "load not measurable" (all processors).
  [[nodiscard]] const char* policy() const { return policy_; }
  [[nodiscard]] int threads() const { return threads_; }
  /// The fewest and most threads used so far.
  [[nodiscard]] int fewest() const { return fewest_; }
  [[nodiscard]] int most() const { return most_; }

  /// The threads for `cores` processors with `others` of them busy with
  /// other processes: the free cores, at least one.
  [[nodiscard]] static int free_cores(int cores, double others);

 private:
  void use(int threads);
  bool automatic_ = false;
  const char* policy_ = "automatic";
  int threads_ = 1;
  int fewest_ = 1;
  int most_ = 1;
  double wait_ = kFirstCheckSeconds;
  OtherLoad load_;
};

}  // namespace conserve::assembly
