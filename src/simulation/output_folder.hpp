#pragma once
/// A run owns its output folder: before it writes, the files of an earlier
/// run there that it would not rewrite are removed, so that the folder
/// holds this run's output only (a .pvd and the frames it lists, one
/// history). Only names that conserve and its plotting scripts write are
/// touched; any other file in the folder stays.
#include <cstdint>
#include <filesystem>
#include <optional>

namespace conserve::simulation {

/// Removes, from output folder `dir`, the files of an earlier run:
/// - a fresh run (`restart_step` empty): every file conserve writes there
///   (history.csv, steps.csv, cutbacks.log, scenario.toml, summary.json,
///   solution.pvd, vtu/step_*.vtu, vtu/contact_*.vtu,
///   checkpoints/ckpt_*.bin) and the plots of scripts/plot_history.py and
///   scripts/render_snapshots.py (*.png of their names);
/// - a run restarted at step N: summary.json, the plots, and the per-step
///   files (frames, checkpoints, snapshots) of steps after N; the history,
///   steps.csv and solution.pvd are cut back to step N by the run itself.
/// Returns how many files were removed. Throws Error if one cannot be.
int clear_earlier_run(const std::filesystem::path& dir, std::optional<std::int64_t> restart_step);

}  // namespace conserve::simulation
