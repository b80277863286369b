#pragma once
/// Running a scenario end to end, and checking one without running it.
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/types.hpp"
#include "io/scenario.hpp"
#include "simulation/summary.hpp"

namespace conserve::simulation {

struct RunOptions {
  std::optional<std::filesystem::path> output_directory;  ///< overrides [output].directory
  std::FILE* progress = stderr;                           ///< nullptr: silent
  std::optional<std::int64_t> max_steps;                  ///< stop after this many steps of this invocation
  /// Continue from this checkpoint (simulation/checkpoint.hpp): the state,
  /// step size and active set are restored, history.csv and steps.csv keep
  /// their rows up to the checkpoint's step and continue after it.
  std::optional<std::filesystem::path> restart;
  /// Called with each plausibility warning (simulation/plausibility.hpp)
  /// once the model is built, before anything is written; none if empty.
  std::function<void(const std::string&)> warn;
  /// Asked after each step: a non-empty answer (why, e.g. "SIGTERM") ends
  /// the run there with a checkpoint of that step and summary.json
  /// (RunSummary::stopped); none if empty.
  std::function<std::string()> stop;
};

/// Runs the scenario, writing history.csv, steps.csv (step, time, dt,
/// cutbacks), cutbacks.log (why each cut back step failed), VTU/PVD output
/// and checkpoints. A step that fails is retried
/// from the same state with Δt halved, down to [time].min_step; Δt grows
/// back after StepControl::kGrowAfter good steps. Throws InputError on bad
/// input and SolverError when a step fails at the floor: the output up to
/// the last converged step stays, and that state is saved as a checkpoint
/// (named in the message). Asked to stop (RunOptions::stop), it ends after
/// the step under way with a checkpoint and summary.json.
RunSummary run(const io::Scenario& scenario, const RunOptions& options);

/// The model a scenario describes, without running it.
struct CheckSummary {
  int dimension = 3;
  int bodies = 0, nodes = 0, cells = 0, dofs = 0, prescribed_dofs = 0;
  std::int64_t steps = 0;   ///< end / step, rounded up
  double total_mass = 0.0;  ///< [kg]
  std::vector<std::string> warnings;  ///< plausibility warnings (simulation/plausibility.hpp)
  /// Per rigid bare surface read from a file: "body 'NAME': " and which
  /// way its normals point (mesh::describe_surface).
  std::vector<std::string> surfaces;
  /// Per contact pair (the search's, [general_contact]'s included): "SLAVE
  /// on MASTER", its facets and how it is held (two passes, self-contact).
  std::vector<std::string> pairs;
  int self_pairs = 0, two_pass_pairs = 0;  ///< of `pairs`: self-contact, and contacts searched both ways
};

/// Validates the scenario fully (meshes made or read, groups resolved).
CheckSummary check(const io::Scenario& scenario);

}  // namespace conserve::simulation
