#include "simulation/run.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <vector>

#include "core/error.hpp"
#include "io/atomic_file.hpp"
#include "io/history_writer.hpp"
#include "mesh/surface_mesh.hpp"
#include "simulation/checkpoint.hpp"
#include "simulation/contact_setup.hpp"
#include "simulation/drift.hpp"
#include "simulation/output.hpp"
#include "simulation/output_folder.hpp"
#include "simulation/plausibility.hpp"
#include "simulation/progress.hpp"
#include "simulation/setup.hpp"
#include "simulation/stepper.hpp"
#include "solver/ranks.hpp"
#include "time/diagnostics.hpp"
#include "time/integrator.hpp"

namespace conserve::simulation {
namespace {

/// end / step, rounded up (unless within round-off of an integer); the
/// parser keeps it at most 2^53.
std::int64_t step_count(const io::TimeSpec& t) {
  const double n = t.end / t.step;
  return static_cast<std::int64_t>(std::abs(n - std::round(n)) < 1e-9 * n ? std::round(n) : std::ceil(n));
}

/// True once `state` has reached the end time (the stepper ends the last
/// step there; within 1e-6 Δt counts as reached).
bool finished(const io::TimeSpec& t, const model::State& state) { return state.time >= t.end - 1e-6 * t.step; }

/// This rank's ghost nodes: the corners of its cells (those with a
/// corner among its nodes, model::keep_cells) that other ranks own.
template <int D>
long ghost_nodes(const model::Model<D>& model) {
  std::vector<int> corners(model.cells.data(), model.cells.data() + model.cells.size());
  std::sort(corners.begin(), corners.end());
  corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
  return static_cast<long>(std::count_if(corners.begin(), corners.end(), [&](int B) { return !model.owns(B); }));
}

/// What step `record` (ending in diagnostics `d`, the contact method
/// `contact`, may be null) gives the statistics.
template <int D>
StepFigures figures_of(const StepRecord& record, const time::Diagnostics& d, const contact::Method<D>* contact) {
  double force = 0.0;
  int count = 0;
  if (contact)
    for (const auto& f : contact->contact_forces()) force += f.normal, ++count;
  return {record, d, count, force};
}

/// Per body with a contact surface, its penetration both ways at
/// displacement u, the step from u_n (RunSummary::body_penetration), from
/// each pair's.
template <int D>
std::vector<RunSummary::BodyPenetration> body_penetration(contact::Method<D>& contact, const model::Model<D>& model,
                                                          const Eigen::VectorXd& u_n, const Eigen::VectorXd& u) {
  const contact::Positions<D> x_n = model.X + u_n.reshaped(D, model.num_nodes());
  const contact::Positions<D> x = model.X + u.reshaped(D, model.num_nodes());
  const auto depths = contact.collisions().pair_penetrations(x, &x_n);
  std::map<int, RunSummary::BodyPenetration> by_body;
  for (std::size_t p = 0; p < depths.size(); ++p) {
    const contact::ContactPair<D>& pair = contact.pairs()[p];
    RunSummary::BodyPenetration& slave = by_body[pair.slave.body];
    RunSummary::BodyPenetration& master = by_body[pair.master.body];
    slave.nodes_behind = std::max(slave.nodes_behind, depths[p].slave.depth);
    master.behind_its_facets = std::max(master.behind_its_facets, depths[p].slave.depth);
    master.nodes_behind = std::max(master.nodes_behind, depths[p].master.depth);
    slave.behind_its_facets = std::max(slave.behind_its_facets, depths[p].master.depth);
  }
  std::vector<RunSummary::BodyPenetration> out;
  for (auto& [b, pen] : by_body) {
    pen.body = model.bodies[static_cast<std::size_t>(b)].name;
    out.push_back(pen);
  }
  return out;
}

/// On several ranks every rank runs all of this alike (solver/ranks.hpp):
/// rank 0 writes the folder's files, each rank its VTU pieces, and every
/// write is wrapped in ranks::together() or ranks::on_root(), so that a
/// failure on one rank ends all of them with the same error.
template <int D>
RunSummary run_dim(const io::Scenario& sc, const RunOptions& options) {
  namespace ranks = solver::ranks;
  const bool root = ranks::root();
  const auto started = std::chrono::system_clock::now();
  const auto setup_start = std::chrono::steady_clock::now();
  Stepper<D> stepper(sc);
  const Problem<D>& problem = stepper.problem();
  if (options.warn)
    for (const std::string& w : stepper.warnings()) options.warn(w);
  const assembly::Assembler<D>& assembler = stepper.assembler();
  contact::Method<D>* contact = stepper.contact();
  time::Integrator<D>& integrator = stepper.integrator();
  StepControl& control = stepper.control();
  RunSummary summary;
  summary.output_directory = options.output_directory.value_or(sc.output.directory);
  const std::filesystem::path& dir = summary.output_directory;
  const Fingerprint& fingerprint = stepper.fingerprint();
  model::State state = problem.initial;
  const time::Diagnostics d0 = time::diagnostics<D>(assembler, state);
  const DriftTracker drift(problem.model.size(), d0, conservation(sc));
  RunTotals totals{
      .drift = {},
      .statistics = RunStatistics(contact ? contact->statistics() : std::vector<contact::MethodStatistic>())};
  if (options.restart) {
    Checkpoint<D> c = read_checkpoint<D>(*options.restart, fingerprint, problem.model, totals.statistics);
    state = std::move(c.state);
    control = c.control;
    totals = c.totals;
    if (contact) contact->load(c.contact, options.restart->string());
    integrator.load(c.integrator, options.restart->string());
    ranks::on_root([&] {
      io::resume_history(dir / "history.csv", state.step);
      io::resume_history(dir / "steps.csv", state.step);
    });
  }
  const RunOrigin origin = run_origin(sc, started);  // reads the mesh files: before anything is written
  std::optional<OutputWriter<D>> writer;
  std::optional<io::HistoryWriter> steps_csv;  // rank 0's, as the log
  std::ofstream cutback_log;
  ranks::on_root([&] {
    summary.earlier_files_removed =
        clear_earlier_run(dir, options.restart ? std::optional<std::int64_t>(state.step) : std::nullopt);
  });
  ranks::together([&] {
    writer.emplace(assembler, dir, sc.output, contact,
                   options.restart ? std::optional<double>(state.time) : std::nullopt);
    if (!root) return;
    io::write_atomically(dir / "scenario.toml", sc.text);
    steps_csv.emplace(dir / "steps.csv", std::vector<std::string>{"step", "time", "dt", "cutbacks"});
    cutback_log.open(dir / "cutbacks.log", state.step > 0 ? std::ios::app : std::ios::trunc);
  });
  OutputWriter<D>& output = *writer;
  const std::int64_t max_steps = options.max_steps.value_or(std::numeric_limits<std::int64_t>::max());
  if (!options.restart) {
    const StepRecord none;
    const StepFigures figures = figures_of<D>(none, d0, contact);
    const Drifts drifts = drift.add(d0, totals.drift);
    ranks::together([&] {
      output.write(state, figures, drifts, finished(sc.time, state) || max_steps == 0);
      if (steps_csv) steps_csv->write_row({0.0, state.time, 0.0, 0.0});
    });
    totals.statistics.add(figures, false);
  }
  auto save = [&](const model::State& s) {
    const auto file = checkpoint_path(dir, s.step);
    ranks::on_root([&] {
      write_checkpoint<D>(
          file, {fingerprint, s, control, totals, contact ? contact->save() : std::string(), integrator.save()});
    });
    return file;
  };
  summary.setup_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - setup_start).count();
  ProgressLine progress(options.progress, sc.output.progress_every);
  const double start_time = state.time;
  summary.min_dt = control.dt;
  const std::int64_t first_cutbacks = control.cutbacks;
  std::int64_t taken = 0;
  std::vector<std::int64_t> pair_steps(contact ? contact->pairs().size() : 0);  // steps each pair held contact in
  std::vector<int> held_in_step(pair_steps.size(), -1);
  Eigen::VectorXd u_last_start = state.u;  // the last step's start (self-contact's search needs it)
  for (; taken < max_steps && !finished(sc.time, state); ++taken) {
    double dt = 0.0;
    int failures = 0;
    u_last_start = state.u;
    StepRecord record;
    try {
      record = stepper.advance(state, dt, failures);
    } catch (const FloorReached& f) {
      progress.finish();
      ranks::together([&] { output.write_snapshot(state); });
      const auto file = save(state);
      throw SolverError(fmt::format(
          "step {} failed even with Δt = {:.6g} s ([time].min_step = {:.6g} s): {}; the last converged state "
          "(step {}, t = {:.9g} s) is in {} and {} (continue with --restart)",
          state.step + 1, f.dt(), sc.time.min_step, f.what(), state.step, state.time, (dir / "history.csv").string(),
          file.string()));
    }
    summary.min_dt = std::min(summary.min_dt, dt);
    if (failures > 0) {  // why, for the user and in the output folder
      const std::string line =
          fmt::format("step {}: {} failed attempt(s), the last: {}\n", state.step, failures, stepper.last_failure());
      if (root) cutback_log << line << std::flush;
      if (options.progress) fmt::print(options.progress, "\ncutback at {}", line);
    }
    time::Diagnostics d = time::diagnostics<D>(assembler, state);
    d.contact = record.contact.contact_energy;  // the springs' stored energy counts in the total
    d.total += d.contact;
    const Drifts drifts = drift.add(d, totals.drift);
    const StepFigures figures = figures_of<D>(record, d, contact);
    if (contact)
      for (const auto& f : contact->contact_forces())
        if (auto& held = held_in_step[static_cast<std::size_t>(f.pair)]; held != static_cast<int>(taken)) {
          held = static_cast<int>(taken);
          ++pair_steps[static_cast<std::size_t>(f.pair)];
        }
    const bool last = taken + 1 == max_steps || finished(sc.time, state);  // of this invocation
    {
      solver::ScopedTimer timer(summary.output_seconds);
      ranks::together([&] {
        output.write(state, figures, drifts, last);
        if (steps_csv)
          steps_csv->write_row({static_cast<double>(state.step), state.time, dt, static_cast<double>(failures)});
      });
    }
    totals.statistics.add(figures, true);
    const bool due = sc.output.checkpoint_every > 0 && state.step % sc.output.checkpoint_every == 0;
    if (options.stop && !last) summary.stopped = options.stop();
    if (due || !summary.stopped.empty()) {
      solver::ScopedTimer timer(summary.output_seconds);
      summary.stop_checkpoint = save(state);
      ranks::on_root([&] { prune_checkpoints(dir, state.step, sc.output.checkpoint_keep); });
    }
    // This invocation ends at the end time or after max_steps, whichever
    // comes first; the steps left are estimated at the current Δt.
    const double by_time = (state.time - start_time) / (sc.time.end - start_time);
    const double by_steps = static_cast<double>(taken + 1) / static_cast<double>(max_steps);
    progress.update(
        {.step = state.step,
         .expected_steps = state.step + steps_left(state.time, sc.time.end, control.dt, taken + 1, max_steps, last),
         .time = state.time,
         .fraction = last ? 1.0 : std::clamp(std::max(by_time, by_steps), 0.0, 1.0),
         .energy_drift = drifts.energy,
         .newton_iterations = record.newton.iterations,
         .last = last});
    if (!summary.stopped.empty()) {
      ++taken;
      break;
    }
  }
  progress.finish();
  summary.steps = taken;
  summary.end_time = state.time;
  for (int q = 0; q < kQuantities; ++q) {
    summary.drift[q] = drift.drift(q, totals.drift);
    summary.reference[q] = drift.reference(q, totals.drift);
  }
  summary.conservation = drift.conservation();
  summary.statistics = totals.statistics;
  summary.cutbacks = control.cutbacks - first_cutbacks;
  summary.thread_policy = stepper.threads().policy();
  summary.fewest_threads = stepper.threads().fewest();
  summary.most_threads = stepper.threads().most();
  summary.wall_seconds = progress.elapsed();
  summary.vtu_frames = output.frames();
  summary.vtu_bytes = static_cast<std::uintmax_t>(ranks::sum(static_cast<double>(output.frame_bytes())));
  summary.ranks = ranks::size();
  summary.row_ranges = integrator.linear_solver().row_ranges();
  summary.peak_memory_bytes = ranks::max(peak_memory_bytes());
  if (ranks::size() > 1) {
    summary.rank_peak_memory_bytes = ranks::all(peak_memory_bytes());
    summary.rank_ghost_nodes = ranks::all(static_cast<double>(ghost_nodes(problem.model)));
  }
  summary.timings = integrator.timings();
  summary.linear_solver = integrator.linear_solver().name();
  if (contact) {
    summary.contact_method = std::string(contact->name());
    summary.contact_settings = contact->settings();
    summary.contact_pairs = static_cast<int>(pair_steps.size());
    for (std::size_t p = 0; p < pair_steps.size(); ++p)
      if (pair_steps[p] > 0) {
        const contact::ContactPair<D>& pair = contact->pairs()[p];
        summary.active_pairs.push_back({pair.slave.name, pair.master.name, pair.self, pair.second_pass, pair_steps[p]});
      }
    summary.body_penetration = body_penetration<D>(*contact, problem.model, u_last_start, state.u);
  }
  ranks::on_root(
      [&] { io::write_atomically(dir / "summary.json", summary_json(summary, problem.model.num_dofs(), origin)); });
  return summary;
}

template <int D>
CheckSummary check_dim(const io::Scenario& sc) {
  const Problem<D> p = setup<D>(sc);
  const auto pairs = make_contact_pairs<D>(sc, p.model);  // resolves the contact surfaces
  CheckSummary s{D,
                 static_cast<int>(p.model.bodies.size()),
                 p.model.num_nodes(),
                 p.model.num_cells(),
                 p.model.num_dofs(),
                 static_cast<int>(p.model.prescribed.dofs.size()),
                 step_count(sc.time),
                 0.0,
                 {},
                 {},
                 {},
                 0,
                 0};
  for (int c = 0; c < p.model.num_cells(); ++c)
    s.total_mass += p.model.bodies[p.model.cell_body[c]].density * p.model.cell_volume(c);
  s.warnings = plausibility_warnings<D>(sc, p.model, pairs);
  for (const contact::ContactPair<D>& pair : pairs) {
    if (pair.second_pass) continue;
    s.self_pairs += pair.self ? 1 : 0;
    s.two_pass_pairs += pair.passes > 1 ? 1 : 0;
    s.pairs.push_back(fmt::format("{} on {} ({} slave nodes, {} master facets){}", pair.slave.name, pair.master.name,
                                  pair.slave.nodes.size(), pair.master.num_facets(),
                                  pair.self         ? ", self-contact"
                                  : pair.passes > 1 ? ", two passes"
                                                    : ""));
  }
  for (std::size_t b = 0; b < sc.bodies.size(); ++b) {
    const model::Body& body = p.model.bodies[b];
    if (body.num_cells > 0 || !sc.bodies[b].mesh.generator.empty()) continue;
    const Eigen::MatrixXd X = p.model.X;
    const auto summary = mesh::summarize_surface(X, model::distinct_facets(body));
    s.surfaces.push_back(fmt::format("body '{}': {}", body.name, mesh::describe_surface(summary)));
  }
  return s;
}

}  // namespace

RunSummary run(const io::Scenario& scenario, const RunOptions& options) {
  return scenario.dimension == 2 ? run_dim<2>(scenario, options) : run_dim<3>(scenario, options);
}

CheckSummary check(const io::Scenario& scenario) {
  return scenario.dimension == 2 ? check_dim<2>(scenario) : check_dim<3>(scenario);
}

}  // namespace conserve::simulation
