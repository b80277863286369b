/// Scenario parsing: the file, the top level, [time], [newton], [loads] and
/// [output]. Bodies and boundaries are in scenario_body.cpp, contact pairs
/// and [active_set] in scenario_contact.cpp.
#include "io/scenario.hpp"

#include <fmt/format.h>

#include <fstream>
#include <sstream>

#include "core/error.hpp"
#include "io/scenario_parts.hpp"

namespace conserve::io {
namespace {

using detail::Section;

toml::table parse_toml(std::string_view text, const std::string& file) {
  try {
    return toml::parse(text, std::string_view(file));
  } catch (const toml::parse_error& e) {
    std::string description(e.description());
    for (auto& c : description) {
      if (c == '\n' || c == '\r') c = ' ';
    }
    const auto& where = e.source().begin;
    throw InputError(fmt::format("{}:{}:{}: TOML syntax error: {}", file, where.line, where.column, description));
  }
}

TimeSpec parse_time(const Section& s) {
  TimeSpec time;
  time.step = s.number("step");
  time.end = s.number("end");
  if (time.end < time.step) {
    s.fail("end", fmt::format("{} is smaller than step = {}", time.end, time.step), "end ≥ step");
  }
  // Step numbers are 64-bit, and history.csv writes them as doubles: exact
  // up to 2^53, which no run will reach.
  if (constexpr double kMostSteps = 9007199254740992.0; time.end / time.step > kMostSteps) {
    s.fail("end", fmt::format("{:g} steps (end / step) are more than the output can number", time.end / time.step),
           "end / step ≤ 2^53");
  }
  time.scheme = s.string("scheme") == "midpoint" ? StressScheme::midpoint : StressScheme::conserving;
  time.mass = s.string("mass") == "lumped" ? MassKind::lumped : MassKind::consistent;
  time.min_step = s.number("min_step");
  if (time.min_step == 0.0) time.min_step = time.step / 1024.0;
  if (time.min_step > time.step) {
    s.fail("min_step", fmt::format("{} is larger than step = {}", time.min_step, time.step), "min_step ≤ step");
  }
  return time;
}

NewtonSpec parse_newton(const Section& s) {
  NewtonSpec newton;
  newton.max_iterations = s.integer("max_iterations");
  newton.residual_tolerance = s.number("residual_tolerance");
  newton.predictor = s.string("predictor") == "velocity" ? PredictorKind::velocity : PredictorKind::rigid;
  return newton;
}

SolverSpec parse_solver(const Section& s) {
  SolverSpec solver;
  solver.method = s.string("method");
  solver.preconditioner = s.string("preconditioner");
  solver.gamg_from = s.integer("gamg_from");
  solver.max_linear_iterations = s.integer("max_linear_iterations");
  solver.forcing_max = s.number("forcing_max");
  solver.modified_newton = s.boolean("modified_newton");
  solver.petsc_options = s.string("petsc_options");
  if (solver.method == "direct" && solver.preconditioner != "auto")
    s.fail("preconditioner", fmt::format("'{}' is for method = \"krylov\"; this scenario has method = \"direct\"",
                                         solver.preconditioner),
           "no preconditioner with the direct solver");
  return solver;
}

OutputSpec parse_output(const Section& s) {
  OutputSpec output;
  const auto directory = s.string("directory");
  if (directory.empty()) s.fail("directory", "is empty", "a folder name");
  output.directory = directory;
  output.vtu_every = s.integer("vtu_every");
  output.progress_every = s.integer("progress_every");
  output.contact_state = s.boolean("contact_state");
  output.checkpoint_every = s.integer("checkpoint_every");
  output.checkpoint_keep = s.integer("checkpoint_keep");
  return output;
}

}  // namespace

Scenario parse_scenario(std::string_view text, const std::filesystem::path& file) {
  detail::Context ctx{file.string()};
  const auto root = parse_toml(text, ctx.file);
  const Section top(root, scenario_section(""), "", ctx);
  Scenario scenario;
  scenario.file = file;
  scenario.text = text;
  scenario.title = top.string("title");
  scenario.dimension = ctx.dimension = top.integer("dimension");
  scenario.time = parse_time(top.table("time"));
  scenario.newton = parse_newton(top.table("newton"));
  scenario.solver = parse_solver(top.table("solver"));
  scenario.gravity = top.table("loads").vector("gravity");
  scenario.output = parse_output(top.table("output"));
  scenario.bodies = detail::parse_bodies(top, file);
  scenario.boundaries = detail::parse_boundaries(top, scenario.bodies);
  scenario.contacts = detail::parse_contacts(top, scenario.bodies);
  scenario.active_set = detail::parse_active_set(top.table("active_set"));
  return scenario;
}

Scenario read_scenario(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    throw InputError(fmt::format("{}: cannot open the scenario file (expected a readable TOML file)", file.string()));
  }
  std::ostringstream text;
  text << in.rdbuf();
  return parse_scenario(text.str(), file);
}

}  // namespace conserve::io
