#pragma once
/// Checkpoints: everything a run needs to continue bit-identically from a
/// step (state, step size and cutback state, active contact constraints,
/// the kept tangent's origin and the solver's state, running drift maxima), tied to the scenario by its fingerprint
/// (simulation/fingerprint.hpp). Binary (raw doubles), written atomically.
#include <cstdint>
#include <limits>
#include <filesystem>
#include <vector>

#include <string>
#include "io/scenario.hpp"
#include "model/model.hpp"
#include "model/state.hpp"
#include "simulation/drift.hpp"
#include "simulation/fingerprint.hpp"
#include "simulation/statistics.hpp"

namespace conserve::simulation {

/// The run's accumulators that summary.json reports.
struct RunTotals {
  DriftState drift;          ///< simulation/drift.hpp
  RunStatistics statistics;  ///< simulation/statistics.hpp
};

/// The adaptive step size: halved on a failed step, doubled back (up to
/// the scenario's Δt) after `kGrowAfter` good steps in a row.
struct StepControl {
  static constexpr int kGrowAfter = 4;
  double dt = 0.0;            ///< the step size to try next [s]
  int good_steps = 0;         ///< converged steps since the last change of dt
  std::int64_t cutbacks = 0;  ///< failed attempts over the run
  /// The lengths of the last two steps taken [s] (0 before there are
  /// any): with releases located, the rate a slave's force falls at
  /// (contact::ActiveSet::release_step).
  double last_dt = 0.0;
  double previous_dt = 0.0;
};

template <int D>
struct Checkpoint {
  Fingerprint fingerprint;  ///< of the scenario that wrote it
  model::State state;
  StepControl control;
  RunTotals totals;
  std::string contact;  ///< the contact method's state (contact::Method::save; load() checks it)
  std::string integrator;  ///< the integrator's kept tangent and solver state (time::Integrator::save)
};

/// "DIR/checkpoints/ckpt_NNNNNN.bin" (six digits or more).
std::filesystem::path checkpoint_path(const std::filesystem::path& output_directory, std::int64_t step);

/// Deletes the checkpoints DIR/checkpoints/ckpt_NNNNNN.bin of steps below
/// `current_step` except the newest `keep` - 1 of them, so that with the one
/// of `current_step` `keep` remain. Checkpoints of later steps (left by an
/// earlier, longer run) and other files are not touched. keep = 0: none is
/// deleted. Returns how many were deleted.
int prune_checkpoints(const std::filesystem::path& output_directory, std::int64_t current_step, int keep);

/// Writes the checkpoint atomically (temporary file, then rename), creating
/// the folder. Throws Error.
template <int D>
void write_checkpoint(const std::filesystem::path& file, const Checkpoint<D>& checkpoint);

/// Reads a checkpoint for a run of `model` whose fingerprint is `expected`.
/// Throws InputError naming the file if it is not a checkpoint (or one of
/// another format version), is truncated, or belongs to another dimension
/// or scenario: then the message names the first setting that differs.
/// `statistics`: the run's (RunStatistics with its contact method's own),
/// whose accumulations the checkpoint holds.
template <int D>
Checkpoint<D> read_checkpoint(const std::filesystem::path& file, const Fingerprint& expected,
                              const model::Model<D>& model, RunStatistics statistics = RunStatistics());

}  // namespace conserve::simulation
