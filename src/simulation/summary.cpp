#include "simulation/summary.hpp"

#include <sys/resource.h>
#include <cmath>
#include <ctime>
#include <nlohmann/json.hpp>
#include <thread>

#include "core/build_info.hpp"
#include "io/sha256.hpp"

namespace conserve::simulation {

double peak_memory_bytes() {
  rusage own{};
  getrusage(RUSAGE_SELF, &own);
  return 1024.0 * static_cast<double>(own.ru_maxrss);  // Linux reports kB
}

namespace {

using Json = nlohmann::ordered_json;  // keys in the order written

Json input(const InputFile& f, bool with_body) {
  Json j;
  if (with_body) j["body"] = f.body;
  j["path"] = f.path.string();
  j["sha256"] = f.sha256;
  return j;
}

Json drifts(const RunSummary& s);
Json not_conserved(const RunSummary& s);

/// The figures summary.json has always had (bench/make_table.py reads them).
Json figures(const RunSummary& s, int unknowns) {
  const auto& t = s.timings;
  const double peak = s.peak_memory_bytes > 0.0 ? s.peak_memory_bytes : peak_memory_bytes();
  Json settings = Json::object();
  for (const auto& [name, value] : s.contact_settings) settings[name] = value;
  return Json{{"steps", s.steps},
              {"unknowns", unknowns},
              {"wall_seconds", s.wall_seconds},
              {"setup_seconds", s.setup_seconds},
              {"ranks", s.ranks},
              {"row_ranges", s.row_ranges},
              {"peak_memory_bytes", peak},
              {"rank_peak_memory_bytes", s.rank_peak_memory_bytes},
              {"rank_ghost_nodes", s.rank_ghost_nodes},
              {"bytes_per_unknown", unknowns > 0 ? peak / unknowns : 0.0},
              {"drift", drifts(s)},
              {"not_conserved", not_conserved(s)},
              {"seconds",
               {{"assembly", t.assembly},
                {"elimination", t.elimination},
                {"linear_setup", t.linear_setup},
                {"linear_solve", t.linear_solve},
                {"contact_search", t.contact_search},
                {"output", s.output_seconds}}},
              {"linear_solver", s.linear_solver},
              {"contact_method", s.contact_method},
              {"contact_settings", settings},
              {"linear_setups", t.linear_setups},
              {"linear_solves", t.linear_solves},
              {"linear_iterations", t.linear_iterations},
              {"linear_fallbacks", t.linear_fallbacks},
              {"lu_first", t.lu_first},
              {"symbolic_analyses", t.analyses},
              {"threads", {{"policy", s.thread_policy}, {"fewest", s.fewest_threads}, {"most", s.most_threads}}},
              {"cutbacks", s.cutbacks},
              {"vtu_frames", s.vtu_frames},
              {"vtu_bytes", s.vtu_bytes},
              {"min_dt", s.min_dt},
              {"end_time", s.end_time},
              {"stopped", s.stopped.empty() ? Json(nullptr) : Json(s.stopped)},
              {"drift_reference",
               {{"energy", s.reference[0]},
                {"momentum", s.reference[1]},
                {"angular_momentum", s.reference[4]},
                {"definition",
                 "drift = the largest |X - X0| over the run / X_ref; E = total + released + dissipated; E_ref = the "
                 "largest K + W "
                 "[J], L_ref = the largest sum over nodes of |(M V)_A| [kg m/s], J_ref = L_ref times the model's "
                 "bounding-box diagonal [kg m^2/s]"}}}};
}

/// The conserved quantities' drifts, by name.
Json drifts(const RunSummary& s) {
  Json j = Json::object();
  for (int q = 0; q < kQuantities; ++q)
    if (s.conservation.conserved(q)) j[std::string(kQuantityNames[q])] = s.drift[q];
  return j;
}

/// The quantities present that are not conserved, with why.
Json not_conserved(const RunSummary& s) {
  Json j = Json::object();
  for (int q = 0; q < kQuantities; ++q)
    if (s.conservation.present[q] && !s.conservation.conserved(q))
      j[std::string(kQuantityNames[q])] = s.conservation.why_not[q];
  return j;
}

}  // namespace

RunOrigin run_origin(const io::Scenario& scenario, std::chrono::system_clock::time_point started) {
  const auto absolute = [](const std::filesystem::path& p) { return std::filesystem::weakly_canonical(p); };
  RunOrigin origin{.title = scenario.title,
                   .started = utc_timestamp(started),
                   .scenario = {.body = "", .path = absolute(scenario.file), .sha256 = io::sha256_hex(scenario.text)},
                   .meshes = {}};
  for (const auto& body : scenario.bodies) {
    if (body.mesh.file.empty()) continue;
    origin.meshes.push_back({body.name, absolute(body.mesh.file), io::file_sha256(body.mesh.file)});
  }
  return origin;
}

std::string utc_timestamp(std::chrono::system_clock::time_point t) {
  const std::time_t seconds = std::chrono::system_clock::to_time_t(t);
  std::tm tm{};
  gmtime_r(&seconds, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return text;
}

std::string summary_json(const RunSummary& s, int unknowns, const RunOrigin& origin) {
  Json j{{"program",
          {{"name", "conserve"},
           {"version", std::string(build_info::version())},
           {"commit", std::string(build_info::commit())}}},
         {"started", origin.started},
         {"title", origin.title},
         {"host", {{"cores", std::thread::hardware_concurrency()}}}};
  Json meshes = Json::array();
  for (const auto& mesh : origin.meshes) meshes.push_back(input(mesh, true));
  j["inputs"] = {{"scenario", input(origin.scenario, false)}, {"meshes", std::move(meshes)}};
  j.update(figures(s, unknowns));
  for (const auto& [key, value, count] : s.statistics.summary()) {
    if (count && std::isfinite(value))
      j[key] = static_cast<std::int64_t>(value);
    else
      j[key] = value;
  }
  if (s.contact_pairs > 0) {
    Json active = Json::array(), bodies = Json::array();
    for (const auto& p : s.active_pairs)
      active.push_back({{"slave", p.slave},
                        {"master", p.master},
                        {"self", p.self},
                        {"second_pass", p.second_pass},
                        {"steps", p.steps}});
    for (const auto& b : s.body_penetration)
      bodies.push_back(
          {{"body", b.body}, {"nodes_behind", b.nodes_behind}, {"behind_its_facets", b.behind_its_facets}});
    j["contact_pairs"] = {{"count", s.contact_pairs}, {"active", std::move(active)}};
    j["penetration_at_end"] = std::move(bodies);
  }
  // NaN and ±inf are written as null; bytes that are not UTF-8 (a path)
  // as U+FFFD rather than an exception.
  return j.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
}

}  // namespace conserve::simulation
