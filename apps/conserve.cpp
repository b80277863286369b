// conserve: energy–momentum conserving finite-element dynamics.
//   conserve run SCENARIO [-o DIR] [--quiet] [--steps N] [--restart CHECKPOINT] [--set SECTION.KEY=VALUE ...]
//   conserve check SCENARIO [--pairs] [--set SECTION.KEY=VALUE ...]
// Every failure is one line on stderr and a non-zero exit code:
// 1 bad input, 2 bad command line, 3 solver failure, 4 anything else;
// 5: stopped by SIGTERM or SIGUSR1 after the step under way, with a
// checkpoint to continue from and summary.json (a second signal ends the
// process at once).
// On several ranks (mpiexec -n N conserve run ...) every rank runs the
// same program; rank 0 alone prints, and every rank exits with the same code.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <CLI/CLI.hpp>

#include <signal.h>

#include <algorithm>
#include <csignal>
#include <sstream>
#include <string>
#include <vector>

#include "core/build_info.hpp"
#include "core/error.hpp"
#include "io/scenario.hpp"
#include "simulation/run.hpp"
#include "solver/blas_threads.hpp"
#include "solver/ranks.hpp"

namespace {

using conserve::simulation::CheckSummary;
using conserve::simulation::RunSummary;

/// "drift: E 1.2e-14, L_x 3.0e-15 (the largest deviation over the run's
/// scale: …); not conserved: L_z (gravity), J (stick contact)".
void print_drifts(const RunSummary& s) {
  using conserve::simulation::kQuantities;
  using conserve::simulation::kQuantityNames;
  std::vector<std::string> drifts;
  std::vector<std::pair<std::string, std::string>> others;  // (names, why), quantities of one reason merged
  for (int q = 0; q < kQuantities; ++q) {
    if (!s.conservation.present[q]) continue;
    const std::string name(kQuantityNames[q]);
    if (s.conservation.conserved(q)) {
      drifts.push_back(fmt::format("{} {:.2e}", name, s.drift[q]));
      continue;
    }
    const std::string& why = s.conservation.why_not[q];
    auto same = std::find_if(others.begin(), others.end(), [&](const auto& o) { return o.second == why; });
    if (same == others.end())
      others.emplace_back(name, why);
    else
      same->first += ", " + name;
  }
  fmt::print(
      "drift (largest deviation over the run's scale: E_ref = {:.3e} J, L_ref = {:.3e} kg m/s, J_ref = {:.3e} "
      "kg m²/s): {}",
      s.reference[0], s.reference[1], s.reference[4],
      drifts.empty() ? "none" : fmt::format("{}", fmt::join(drifts, ", ")));
  if (!others.empty()) {
    std::vector<std::string> parts;
    for (auto [names, why] : others) {
      // All of L's (J's) components alike: "L".
      for (const char* whole : {"L", "J"}) {
        const std::string all = s.conservation.present[3]   ? fmt::format("{0}_x, {0}_y, {0}_z", whole)
                                : std::string(whole) == "L" ? "L_x, L_y"
                                                            : "J_z";
        if (const auto at = names.find(all); at != std::string::npos && all.size() > 3)
          names.replace(at, all.size(), whole);
      }
      parts.push_back(fmt::format("{} ({})", names, why));
    }
    fmt::print("; not conserved: {}", fmt::join(parts, "; "));
  }
  fmt::print("\n");
}

void print_summary(const RunSummary& s) {
  fmt::print("finished {} steps in {:.2f} s ({:.2f} Newton iterations per step, at most {})\n", s.steps, s.wall_seconds,
             s.statistic("mean_newton_iterations"), s.statistic("max_newton_iterations"));
  print_drifts(s);
  fmt::print("smallest det F {:.4g}\n", s.statistic("min_det_F"));
  const auto& t = s.timings;
  fmt::print(
      "time: assembly {:.2f} s on {} thread{} ({}), contact {} {:.2f} s, linear set-up {:.2f} s ({} "
      "set-ups), linear solve {:.2f} s ({} solves, {:.1f} {} iterations each), contact search {:.2f} s, output "
      "{:.2f} s\n",
      t.assembly,
      s.fewest_threads == s.most_threads ? fmt::format("{}", s.most_threads)
                                         : fmt::format("{} to {}", s.fewest_threads, s.most_threads),
      s.most_threads == 1 ? "" : "s", s.thread_policy, s.contact_method.empty() ? "elimination" : s.contact_method,
      t.elimination, t.linear_setup, t.linear_setups, t.linear_solve, t.linear_solves,
      t.linear_solves ? static_cast<double>(t.linear_iterations) / static_cast<double>(t.linear_solves) : 0.0,
      s.linear_solver, t.contact_search, s.output_seconds);
  if (t.linear_fallbacks > 0)
    fmt::print(
        "linear solver: {} GMRES solves stagnated and were redone by the LU; {} matrices after them went to "
        "the LU first\n",
        t.linear_fallbacks, t.lu_first);
  if (s.cutbacks > 0)
    fmt::print("cutbacks: {} failed steps retried with a halved time step (smallest {:.3e} s), see steps.csv\n",
               s.cutbacks, s.min_dt);
  if (s.statistic("activations") + s.statistic("releases") > 0) {
    // The held methods' own statistics (contact/elimination/held_statistics.hpp), where the method has them.
    const std::string held = s.statistics.has("held")
                                 ? fmt::format(" ({} held after a release), largest gap at activation {:.3e} m",
                                               s.statistic("held"), s.statistic("max_activation_gap"))
                                 : std::string();
    fmt::print(
        "contact: {} activations, {} releases{}; active gaps {:.3e} to {:.3e} m; deepest penetration {:.3e} m "
        "(slave nodes behind master facets {:.3e} m, master nodes behind slave facets {:.3e} m)\n",
        s.statistic("activations"), s.statistic("releases"), held, s.statistic("min_active_gap"),
        s.statistic("max_active_gap"), s.statistic("max_penetration"), s.statistic("slave_penetration"),
        s.statistic("master_penetration"));
  }
  if (!s.active_pairs.empty()) {
    std::string names;
    for (std::size_t k = 0; k < s.active_pairs.size() && k < 6; ++k)
      names += fmt::format("{}{} on {} ({} step{})", k ? ", " : "", s.active_pairs[k].slave, s.active_pairs[k].master,
                           s.active_pairs[k].steps, s.active_pairs[k].steps == 1 ? "" : "s");
    fmt::print("contact: {} of the {} pairs searched (each pass counted) held contact: {}{}\n", s.active_pairs.size(),
               s.contact_pairs, names,
               s.active_pairs.size() > 6 ? ", … (summary.json's contact_pairs lists them)" : "");
  }
  if (!s.body_penetration.empty()) {
    auto deepest = s.body_penetration;
    auto depth = [](const auto& b) { return std::max(b.nodes_behind, b.behind_its_facets); };
    std::stable_sort(deepest.begin(), deepest.end(), [&](const auto& a, const auto& b) { return depth(a) > depth(b); });
    std::string rows;
    for (std::size_t k = 0; k < deepest.size() && k < 6 && depth(deepest[k]) > 0; ++k)
      rows += fmt::format("{}{} {:.3e} / {:.3e} m", k ? ", " : "", deepest[k].body, deepest[k].nodes_behind,
                          deepest[k].behind_its_facets);
    if (rows.empty())
      fmt::print("penetration at the end: none, either way, on any of the {} bodies in contact pairs\n",
                 deepest.size());
    else
      fmt::print(
          "penetration at the end, deepest first (a body's nodes behind facets / nodes behind its facets): {}{}\n",
          rows, deepest.size() > 6 ? " (summary.json's penetration_at_end has every body)" : "");
  }
  if (s.statistic("dissipated") > 0)
    fmt::print("friction: {:.6g} J dissipated (history.csv's dissipated; total + dissipated is what is conserved)\n",
               s.statistic("dissipated"));
  if (s.steps >= 20 && s.statistic("impact_splits") > 0.5 * static_cast<double>(s.steps))
    fmt::print(
        "contact: {} attempts of {} steps were cut short to locate impacts (an attempt given up and a shorter step "
        "each); a larger [active_set] gap_tolerance or cluster_tolerance, or scheme = \"paper\", takes fewer "
        "steps with the same conservation, at larger gaps held at activation\n",
        s.statistic("impact_splits"), s.steps);
  if (s.statistic_or_zero("velocity_update_failures") > 0)
    fmt::print(
        "contact: in {} step(s) the persistent-contact velocity update failed (its constraints' system singular, "
        "its velocities not finite, or the energy it removes more than the bodies' motion could take back) and "
        "the step kept the mid-point velocity (19), whose relative velocity at the active slaves reverses "
        "(chatter); E, L and J are kept either way. history.csv's velocity_update_failures says when.\n",
        s.statistic_or_zero("velocity_update_failures"));
  if (s.statistic_or_zero("pushes_given_up") > 0)
    fmt::print(
        "contact: {} push-out(s) given up: slaves found behind their master facet further than the step's motion "
        "could carry them out, and the work of pushing them out more than the bodies' vibration could give back, "
        "were held where they were (down to {:.3e} m; history.csv's pushes_given_up says when). Such slaves came "
        "in behind the master surface beyond its border or through a face that is not part of it: if that face "
        "should stop them, add it to the master surface.\n",
        s.statistic_or_zero("pushes_given_up"), s.statistic("min_active_gap"));
  fmt::print("output: {}/history.csv, {}/solution.pvd", s.output_directory.string(), s.output_directory.string());
  if (s.vtu_frames > 0)
    fmt::print(" ({} VTU frames, {:.1f} MB, {:.0f} kB a frame)", s.vtu_frames, static_cast<double>(s.vtu_bytes) / 1e6,
               static_cast<double>(s.vtu_bytes) / 1e3 / static_cast<double>(s.vtu_frames));
  if (s.earlier_files_removed > 0)
    fmt::print(" ({} files of an earlier run in that folder removed first)", s.earlier_files_removed);
  fmt::print("\n");
}

void print_check(const std::string& file, const CheckSummary& s, bool all_pairs) {
  fmt::print("{}: valid. {}D, {} bodies, {} nodes, {} cells, {} unknowns ({} prescribed), mass {:.6g} kg, {} steps\n",
             file, s.dimension, s.bodies, s.nodes, s.cells, s.dofs, s.prescribed_dofs, s.total_mass, s.steps);
  for (const std::string& surface : s.surfaces) fmt::print("  {}\n", surface);
  if (s.pairs.empty()) return;
  constexpr std::size_t kListed = 12;  // a [general_contact] of many bodies: the kinds, and the first pairs
  fmt::print("contact: {} pair(s): {} self-contact, {} in two passes, {} in one\n", s.pairs.size(), s.self_pairs,
             s.two_pass_pairs, s.pairs.size() - static_cast<std::size_t>(s.self_pairs + s.two_pass_pairs));
  const std::size_t listed = all_pairs ? s.pairs.size() : std::min(s.pairs.size(), kListed);
  for (std::size_t k = 0; k < listed; ++k) fmt::print("  {}\n", s.pairs[k]);
  if (listed < s.pairs.size()) fmt::print("  … {} more (--pairs lists them all)\n", s.pairs.size() - listed);
}

/// The signal that asked the run to stop (0: none).
volatile std::sig_atomic_t stop_signal = 0;

extern "C" void on_stop_signal(int signal) { stop_signal = signal; }

/// SIGTERM (a batch system's time limit) and SIGUSR1 end the run after the
/// step under way; the handler is reset, so that a second one ends it at once.
void catch_stop_signals() {
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  action.sa_flags = SA_RESETHAND;
  sigemptyset(&action.sa_mask);
  sigaction(SIGTERM, &action, nullptr);
  sigaction(SIGUSR1, &action, nullptr);
}

/// Collective: a signal to any rank stops every rank after the same step.
std::string stop_requested() {
  const int signal = conserve::solver::ranks::max(static_cast<int>(stop_signal));
  return signal == SIGTERM ? "SIGTERM" : signal == SIGUSR1 ? "SIGUSR1" : signal != 0 ? "a signal" : "";
}

/// Runs body, turning its errors into one line on stderr (from rank 0
/// alone: every rank has the same error, simulation/run.hpp) and the exit code.
template <class F>
int guarded(F&& body) {
  const bool root = conserve::solver::ranks::root();
  try {
    return body();
  } catch (const conserve::InputError& e) {
    if (root) fmt::print(stderr, "conserve: error: {}\n", e.what());
    return 1;
  } catch (const conserve::SolverError& e) {
    if (root) fmt::print(stderr, "conserve: solver failed: {}\n", e.what());
    return 3;
  } catch (const std::exception& e) {
    if (root) fmt::print(stderr, "conserve: error: {}\n", e.what());
    return 4;
  }
}

}  // namespace

int run_program(int argc, char** argv) {
  const bool root = conserve::solver::ranks::root();
  CLI::App app{"conserve: energy-momentum conserving finite-element dynamics with contact"};
  app.set_version_flag("--version", fmt::format("conserve {} (commit {})", conserve::build_info::version(),
                                                conserve::build_info::commit()));
  app.require_subcommand(1);
  std::string scenario_file, output_dir, restart_file;
  std::vector<std::string> overrides;
  const std::string set_help =
      "replace or add a key of the scenario, SECTION.KEY=VALUE (repeatable; VALUE in TOML, or a bare string), e.g. "
      "--set active_set.scheme=persistent";
  bool quiet = false;
  std::int64_t steps = -1;
  int blas_threads = 1;
  CLI::App* run = app.add_subcommand("run", "run a scenario, writing history.csv and ParaView output");
  run->add_option("scenario", scenario_file, "scenario file (TOML)")->required();
  run->add_option("-o,--output", output_dir, "output directory (overrides [output].directory)");
  run->add_flag("-q,--quiet", quiet, "no progress line");
  run->add_option("--steps", steps, "stop after this many steps")->check(CLI::NonNegativeNumber);
  run->add_option("--restart", restart_file,
                  "continue from a checkpoint (OUT/checkpoints/ckpt_NNNNNN.bin) of the same scenario");
  run->add_option("--blas-threads", blas_threads, "threads of the BLAS under UMFPACK (default 1)")
      ->check(CLI::PositiveNumber);
  run->add_option("--set", overrides, set_help)->allow_extra_args(false);
  CLI::App* check = app.add_subcommand("check", "validate a scenario (meshes included) without running it");
  check->add_option("scenario", scenario_file, "scenario file (TOML)")->required();
  check->add_option("--set", overrides, set_help)->allow_extra_args(false);
  bool all_pairs = false;
  check->add_flag("--pairs", all_pairs, "list every contact pair (else the first 12)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    std::ostringstream muted;
    const int code = root ? app.exit(e) : app.exit(e, muted, muted);
    return code == 0 ? 0 : 2;
  }
  return guarded([&] {
    const conserve::io::Scenario scenario = conserve::io::read_scenario(scenario_file, overrides);
    const auto warn = [root](const std::string& w) {
      if (root) fmt::print(stderr, "conserve: warning: {}\n", w);
    };
    if (*check) {
      const conserve::simulation::CheckSummary s = conserve::simulation::check(scenario);
      for (const std::string& w : s.warnings) warn(w);
      if (root) print_check(scenario_file, s, all_pairs);
      return 0;
    }
    conserve::solver::set_blas_threads(blas_threads);
    conserve::simulation::RunOptions options;
    if (!output_dir.empty()) options.output_directory = output_dir;
    if (quiet || !root) options.progress = nullptr;
    if (steps >= 0) options.max_steps = steps;
    if (!restart_file.empty()) options.restart = restart_file;
    options.warn = warn;
    options.stop = stop_requested;
    catch_stop_signals();
    const RunSummary summary = conserve::simulation::run(scenario, options);
    if (root) print_summary(summary);
    if (summary.stopped.empty()) return 0;
    if (root)
      fmt::print(stderr,
                 "conserve: stopped by {} at t = {:.9g} s; the state is in {} (continue with --restart {}), "
                 "summary.json is written\n",
                 summary.stopped, summary.end_time, summary.stop_checkpoint.string(), summary.stop_checkpoint.string());
    return 5;
  });
}

int main(int argc, char** argv) {
  const int code = run_program(argc, argv);
  conserve::solver::ranks::finalize();
  return code;
}
