#pragma once
/// What a finished run measured and where it came from, and summary.json,
/// the file that records both (read by bench/ and scripts).
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/types.hpp"
#include "io/scenario.hpp"
#include "simulation/drift.hpp"
#include "simulation/statistics.hpp"
#include "solver/timings.hpp"

namespace conserve::simulation {

/// What a finished run measured.
struct RunSummary {
  std::int64_t steps = 0;     ///< steps taken by this invocation
  double wall_seconds = 0.0;  ///< the time loop's
  /// From the scenario to the first step: meshes read or generated, the
  /// model, its pattern and solver, the output folder and step 0 written.
  double setup_seconds = 0.0;
  /// Per quantity (simulation/drift.hpp: E, L_x … J_z) its drift over the
  /// run (NaN where not conserved or not present) and its scale.
  std::array<double, kQuantities> drift{};
  std::array<double, kQuantities> reference{};
  Conservation conservation;  ///< which are conserved, and why not
  /// The run statistics (simulation/statistics.hpp): Newton iterations,
  /// contact counts, gaps, penetrations, smallest det F.
  RunStatistics statistics;
  /// The run value of statistic key `key` (summary.json's).
  [[nodiscard]] double statistic(std::string_view key) const { return statistics.value(key); }
  /// The same, 0 where the run has no such statistic (another contact method's own).
  [[nodiscard]] double statistic_or_zero(std::string_view key) const {
    return statistics.has(key) ? statistics.value(key) : 0.0;
  }
  std::filesystem::path output_directory;
  int earlier_files_removed = 0;  ///< files of an earlier run removed from it (simulation/output_folder.hpp)
  solver::Timings timings;        ///< where the wall time went
  std::string linear_solver;      ///< the back end's name, e.g. "GMRES + ILU(0)"
  /// The contact method's name ("" without contact) and its settings as
  /// the run used them (contact::Method::settings).
  std::string contact_method;
  std::vector<std::pair<std::string, double>> contact_settings;
  double output_seconds = 0.0;   ///< writing history and VTU files
  std::int64_t vtu_frames = 0;   ///< VTU files written by this invocation
  std::uintmax_t vtu_bytes = 0;  ///< their size [bytes]
  /// The MPI ranks the run used (solver/ranks.hpp), and the largest of
  /// their peak resident memories [bytes] (0: this process's, read when
  /// summary.json is written).
  int ranks = 1;
  std::vector<std::int64_t> row_ranges;  ///< LinearSolver::row_ranges() of the last matrix
  double peak_memory_bytes = 0.0;
  std::vector<double> rank_peak_memory_bytes;  ///< each rank's, in rank order (empty: one rank)
  /// Each rank's ghost nodes (other ranks' nodes sharing a cell with its
  /// own: the columns of its rows held elsewhere), in rank order.
  std::vector<double> rank_ghost_nodes;
  std::int64_t cutbacks = 0;  ///< failed step attempts retried with Δt halved
  /// The assembly's threads: why (assembly::ThreadGovernor::policy), and
  /// the fewest and most used.
  std::string thread_policy;
  int fewest_threads = 1, most_threads = 1;
  double min_dt = 0.0;  ///< smallest step size used [s]
  /// Why the run stopped before its end (RunOptions::stop: "SIGTERM"),
  /// empty if it did not, and the checkpoint it wrote then.
  std::string stopped;
  std::filesystem::path stop_checkpoint;
  double end_time = 0.0;  ///< the time the run reached [s]
  /// Contact pairs (the search's, each pass and [general_contact]'s
  /// included): how many, and those that held contact in a step of this
  /// invocation, with those steps.
  struct ActivePair {
    std::string slave, master;  ///< surfaces, "body:group"
    bool self = false, second_pass = false;
    std::int64_t steps = 0;
  };
  int contact_pairs = 0;
  std::vector<ActivePair> active_pairs;
  /// Per body with a contact surface, at the run's end, both ways: the
  /// deepest of its nodes behind a facet it is searched against (its own
  /// too, with self-contact) and the deepest node behind its facets [m].
  struct BodyPenetration {
    std::string body;
    double nodes_behind = 0.0;
    double behind_its_facets = 0.0;
  };
  std::vector<BodyPenetration> body_penetration;
};

/// An input file of a run and its SHA-256.
struct InputFile {
  std::string body;  ///< the body whose mesh it is; empty for the scenario
  std::filesystem::path path;
  std::string sha256;  ///< 64 hex digits
};

/// Where a run came from: what makes its output traceable.
struct RunOrigin {
  std::string title;    ///< the scenario's title
  std::string started;  ///< start of the run, ISO-8601 UTC (utc_timestamp)
  InputFile scenario;
  std::vector<InputFile> meshes;  ///< the mesh files of bodies with `mesh.file`, in body order
};

/// The origin of a run of `scenario` started at `started`: its title, its
/// text's SHA-256 and its mesh files' (read now). Paths are made absolute.
/// Throws InputError if a mesh file cannot be read.
RunOrigin run_origin(const io::Scenario& scenario, std::chrono::system_clock::time_point started);

/// `t` as ISO-8601 UTC to the second, "2026-11-21T10:00:00Z".
std::string utc_timestamp(std::chrono::system_clock::time_point t);

/// summary.json's text: the figures of `s` (`unknowns`: the model's degrees
/// of freedom), `program` (name, version, commit), `started`, `title`,
/// `host` (cores) and `inputs` (scenario and meshes with their SHA-256).
/// Always valid JSON: strings are escaped (bytes that are not UTF-8
/// become U+FFFD), non-finite numbers are null.
std::string summary_json(const RunSummary& s, int unknowns, const RunOrigin& origin);

/// This process's peak resident memory so far [bytes].
double peak_memory_bytes();

}  // namespace conserve::simulation
