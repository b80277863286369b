#pragma once
/// What a finished run measured and where it came from, and summary.json,
/// the file that records both (read by bench/ and scripts).
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/types.hpp"
#include "io/scenario.hpp"
#include "solver/timings.hpp"

namespace conserve::simulation {

/// What a finished run measured.
struct RunSummary {
  std::int64_t steps = 0;  ///< steps taken by this invocation
  double wall_seconds = 0.0;
  double energy_drift = 0.0;          ///< max |E − E0| / |E0| (or / max(K+W) if E0 = 0)
  Vec3 linear_drift = Vec3::Zero();   ///< per component, max |L_i − L_i0| / max(|L|, p_ref)
  Vec3 angular_drift = Vec3::Zero();  ///< per component, max |J_i − J_i0| / max(|J|, j_ref)
  double mean_newton_iterations = 0.0;
  int max_newton_iterations = 0;
  std::int64_t activations = 0;     ///< contact activations over the run
  std::int64_t releases = 0;        ///< contact releases over the run
  double max_activation_gap = 0.0;  ///< largest gap of a slave at activation [m]
  std::filesystem::path output_directory;
  solver::Timings timings;      ///< where the wall time went
  double output_seconds = 0.0;  ///< writing history and VTU files
  std::int64_t cutbacks = 0;    ///< failed step attempts retried with Δt halved
  double min_dt = 0.0;          ///< smallest step size used [s]
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

}  // namespace conserve::simulation
