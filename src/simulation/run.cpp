#include "simulation/run.hpp"

#include <fmt/format.h>
#include <cmath>
#include <fstream>

#include "core/error.hpp"
#include "simulation/contact_setup.hpp"
#include "simulation/output.hpp"
#include "simulation/progress.hpp"
#include "simulation/setup.hpp"
#include "time/diagnostics.hpp"
#include "time/integrator.hpp"

namespace conserve::simulation {
namespace {

int step_count(const io::TimeSpec& t) {
  const double n = t.end / t.step;
  return static_cast<int>(std::abs(n - std::round(n)) < 1e-9 * n ? std::round(n) : std::ceil(n));
}

/// Running maxima of the relative drifts against the initial values.
class DriftTracker {
 public:
  explicit DriftTracker(const time::Diagnostics& d0) : d0_(d0) {
    const double e = std::abs(d0.total);
    energy_scale_ = e > 0.0 ? e : std::max(d0.kinetic + d0.strain + std::abs(d0.potential), 1e-300);
    linear_scale_ = std::max(d0.linear.norm(), 1e-300);
    angular_scale_ = std::max(d0.angular.norm(), 1e-300);
  }
  double add(const time::Diagnostics& d, RunSummary& s) const {
    const double e = std::abs(d.total - d0_.total) / energy_scale_;
    s.energy_drift = std::max(s.energy_drift, e);
    s.linear_drift = s.linear_drift.cwiseMax((d.linear - d0_.linear).cwiseAbs() / linear_scale_);
    s.angular_drift = s.angular_drift.cwiseMax((d.angular - d0_.angular).cwiseAbs() / angular_scale_);
    return e;
  }

 private:
  time::Diagnostics d0_;
  double energy_scale_, linear_scale_, angular_scale_;
};

/// The run's figures as JSON (for bench/ and scripts).
void write_summary(const RunSummary& s, int dofs, const std::filesystem::path& file) {
  const auto& t = s.timings;
  std::ofstream out(file);
  out << fmt::format(
      "{{\n  \"steps\": {},\n  \"unknowns\": {},\n  \"wall_seconds\": {:.6g},\n"
      "  \"mean_newton_iterations\": {:.6g},\n  \"max_newton_iterations\": {},\n"
      "  \"energy_drift\": {:.6e},\n  \"linear_drift\": [{:.6e}, {:.6e}, {:.6e}],\n"
      "  \"angular_drift\": [{:.6e}, {:.6e}, {:.6e}],\n  \"activations\": {},\n  \"releases\": {},\n"
      "  \"max_activation_gap\": {:.6e},\n  \"seconds\": {{\"assembly\": {:.6g}, \"elimination\": {:.6g}, "
      "\"factorization\": {:.6g}, \"solve\": {:.6g}, \"contact_search\": {:.6g}, \"output\": {:.6g}}},\n"
      "  \"factorizations\": {},\n  \"symbolic_analyses\": {}\n}}\n",
      s.steps, dofs, s.wall_seconds, s.mean_newton_iterations, s.max_newton_iterations, s.energy_drift,
      s.linear_drift.x(), s.linear_drift.y(), s.linear_drift.z(), s.angular_drift.x(), s.angular_drift.y(),
      s.angular_drift.z(), s.activations, s.releases, s.max_activation_gap, t.assembly, t.elimination,
      t.factorization, t.solve, t.contact_search, s.output_seconds, t.factorizations, t.analyses);
}

fem::StressScheme stress_scheme(io::StressScheme s) {
  return s == io::StressScheme::midpoint ? fem::StressScheme::midpoint : fem::StressScheme::conserving;
}

template <int D>
RunSummary run_dim(const io::Scenario& sc, const RunOptions& options) {
  const Problem<D> problem = setup<D>(sc);
  const assembly::Assembler<D> assembler(problem.model, sc.time.mass == io::MassKind::lumped);
  contact::ActiveSet<D> contacts(problem.model, make_contact_pairs<D>(sc, problem.model));
  time::Integrator<D> integrator(
      assembler, stress_scheme(sc.time.scheme),
      {sc.newton.max_iterations, sc.newton.residual_tolerance, sc.newton.increment_tolerance}, &contacts,
      sc.active_set.max_passes);
  RunSummary summary;
  summary.output_directory = options.output_directory.value_or(sc.output.directory);
  OutputWriter<D> output(assembler, summary.output_directory, sc.output.vtu_every,
                         contacts.empty() ? nullptr : &contacts, sc.output.contact_state);
  model::State state = problem.initial;
  const time::Diagnostics d0 = time::diagnostics<D>(assembler, state);
  const DriftTracker drift(d0);
  const int steps = std::min(step_count(sc.time), options.max_steps.value_or(1 << 30));
  output.write(state, d0, StepRecord{}, steps == 0);
  ProgressLine progress(options.progress, steps, sc.output.progress_every);
  for (int n = 1; n <= steps; ++n) {
    const StepRecord record{integrator.step(state, sc.time.step), integrator.contact_stats()};
    const time::Diagnostics d = time::diagnostics<D>(assembler, state);
    const double e = drift.add(d, summary);
    {
      solver::ScopedTimer timer(summary.output_seconds);
      output.write(state, d, record, n == steps);
    }
    summary.mean_newton_iterations += record.newton.iterations;
    summary.max_newton_iterations = std::max(summary.max_newton_iterations, record.newton.iterations);
    summary.activations += record.contact.activations;
    summary.releases += record.contact.releases;
    summary.max_activation_gap = std::max(summary.max_activation_gap, record.contact.max_activation_gap);
    progress.update(n, state.time, e, record.newton.iterations);
  }
  progress.finish();
  summary.steps = steps;
  summary.mean_newton_iterations /= std::max(steps, 1);
  summary.wall_seconds = progress.elapsed();
  summary.timings = integrator.timings();
  write_summary(summary, problem.model.num_dofs(), summary.output_directory / "summary.json");
  return summary;
}

template <int D>
CheckSummary check_dim(const io::Scenario& sc) {
  const Problem<D> p = setup<D>(sc);
  make_contact_pairs<D>(sc, p.model);  // resolves the contact surfaces
  CheckSummary s{D,
                 static_cast<int>(p.model.bodies.size()),
                 p.model.num_nodes(),
                 p.model.num_cells(),
                 p.model.num_dofs(),
                 static_cast<int>(p.model.prescribed.dofs.size()),
                 step_count(sc.time),
                 0.0};
  for (int c = 0; c < p.model.num_cells(); ++c)
    s.total_mass += p.model.bodies[p.model.cell_body[c]].density * p.model.geometry[c].volume;
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
