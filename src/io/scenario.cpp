/// Scenario parsing: the file, the top level, [time], [newton], [loads] and
/// [output]. Bodies and boundaries are in scenario_body.cpp, contact pairs
/// and [active_set] in scenario_contact.cpp.
#include "io/scenario.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
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

/// A dotted path's parts, each a TOML bare key (letters, digits, '_', '-').
std::vector<std::string> override_path(std::string_view path, const std::string& item) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (true) {
    const std::size_t dot = path.find('.', start);
    const std::string_view part = path.substr(start, dot == std::string_view::npos ? path.npos : dot - start);
    const bool bare = !part.empty() && std::all_of(part.begin(), part.end(), [](char c) {
      return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
    });
    if (!bare)
      throw InputError(
          fmt::format("--set '{}': '{}' is not a key path (expected SECTION.KEY=VALUE, keys of letters, "
                      "digits, '_' and '-', e.g. active_set.scheme=persistent)",
                      item, path));
    parts.emplace_back(part);
    if (dot == std::string_view::npos) return parts;
    start = dot + 1;
  }
}

/// VALUE as a TOML value if it is one, else as a string; parsed under the
/// source name "--set" so that messages about it name the override.
toml::table override_value(const std::string& value) {
  const std::string source(detail::kOverrideSource);
  try {
    toml::table t = toml::parse("v = " + value, std::string_view(source));
    if (t.size() == 1 && t.contains("v")) return t;
  } catch (const toml::parse_error&) {
  }
  std::string quoted;
  for (char c : value) {
    if (c == '"' || c == '\\') quoted += '\\';
    quoted += c;
  }
  return toml::parse("v = \"" + quoted + "\"", std::string_view(source));
}

/// The entry of the array of tables `array` (at `prefix`, e.g. "body")
/// that override part `part` selects: an index ("0") or the value of an
/// entry's `name` key ("ball").
toml::table& select_entry(toml::array& array, const std::string& part, const std::string& prefix,
                          const std::string& item) {
  const bool index = std::all_of(part.begin(), part.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); });
  std::string names;
  for (std::size_t k = 0; k < array.size(); ++k) {
    toml::table& entry = *array.get(k)->as_table();
    const auto* name = entry.get_as<std::string>("name");
    if (index ? std::to_string(k) == part : name && name->get() == part) return entry;
    if (name) names += fmt::format("{}'{}'", names.empty() ? "" : ", ", name->get());
  }
  throw InputError(fmt::format(
      "--set '{}': {} has no entry {} (expected an index 0 to {}{}{})", item, prefix,
      index ? "number " + part : "named '" + part + "'", array.size() - 1, names.empty() ? "" : " or a name: ", names));
}

/// Applies the `--set` overrides to the parsed file (read_scenario). A part
/// after an array of tables selects one of its entries (select_entry).
void apply_overrides(toml::table& root, const std::vector<std::string>& overrides) {
  for (const std::string& item : overrides) {
    if (item.find_first_of("\n\r") != std::string::npos)
      throw InputError("--set: an override has a line break (expected SECTION.KEY=VALUE on one line)");
    const std::size_t eq = item.find('=');
    if (eq == std::string::npos)
      throw InputError(
          fmt::format("--set '{}': no '=' (expected SECTION.KEY=VALUE, e.g. active_set.scheme=persistent)", item));
    const std::vector<std::string> parts = override_path(std::string_view(item).substr(0, eq), item);
    toml::table* table = &root;
    std::string prefix;
    for (std::size_t k = 0; k + 1 < parts.size(); ++k) {
      prefix += (k ? "." : "") + parts[k];
      if (!table->contains(parts[k])) {  // a new table, marked as the override's so that messages name it
        toml::table made = override_value("{}");
        made.get("v")->as_table()->is_inline(false);
        made.get("v")->visit([&](auto&& v) { table->insert(parts[k], std::move(v)); });
      }
      toml::node& node = *table->get(parts[k]);
      if (node.is_array_of_tables()) {
        if (k + 2 >= parts.size())
          throw InputError(fmt::format(
              "--set '{}': {} is an array of tables [[{}]] (expected {}.NAME.KEY=VALUE or {}.INDEX.KEY=VALUE, "
              "e.g. body.ball.material.young=1e7, contact.0.kind=stick)",
              item, prefix, parts[k], parts[k], parts[k]));
        table = &select_entry(*node.as_array(), parts[k + 1], prefix, item);
        prefix += "." + parts[++k];
        continue;
      }
      if (!node.is_table())
        throw InputError(fmt::format("--set '{}': {} is {}, not a table (--set reaches the keys of tables)", item,
                                     prefix, detail::type_of(node)));
      table = node.as_table();
    }
    toml::table value = override_value(item.substr(eq + 1));
    if (toml::node* old = table->get(parts.back()); old && old->is_array_of_tables())
      throw InputError(fmt::format("--set '{}': {} is an array of tables [[{}]]; --set changes the keys of its "
                                   "entries (e.g. {}.0.KEY=VALUE), not the array",
                                   item, prefix.empty() ? parts.back() : prefix + "." + parts.back(), parts.back(),
                                   parts.back()));
    value.get("v")->visit([&](auto&& v) { table->insert_or_assign(parts.back(), std::move(v)); });
  }
}

/// Records where every table and key under `table` (at `prefix`) was
/// given; arrays of tables' entries as "name[i]".
void map_sources(const toml::table& table, const std::string& prefix, SourceMap& map) {
  const auto add = [&map](const std::string& path, const toml::node& node) {
    if (const auto& source = node.source().path; source && *source == detail::kOverrideSource)
      map.add(path, 0);
    else if (node.source().begin.line > 0)
      map.add(path, static_cast<int>(node.source().begin.line));
  };
  for (const auto& [key, node] : table) {
    const std::string path = prefix.empty() ? std::string(key.str()) : prefix + "." + std::string(key.str());
    if (node.is_array_of_tables()) {
      const toml::array& entries = *node.as_array();
      for (std::size_t i = 0; i < entries.size(); ++i) {
        if (i == 0) add(path, *entries.get(0));
        add(fmt::format("{}[{}]", path, i), *entries.get(i));
        map_sources(*entries.get(i)->as_table(), fmt::format("{}[{}]", path, i), map);
      }
      continue;
    }
    add(path, node);
    if (node.is_table()) map_sources(*node.as_table(), path, map);
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
  solver.graph_partition = s.string("partition") == "graph";
  solver.max_linear_iterations = s.integer("max_linear_iterations");
  solver.forcing_max = s.number("forcing_max");
  solver.modified_newton = s.boolean("modified_newton");
  solver.petsc_options = s.string("petsc_options");
  solver.threads = s.integer("threads");
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
  output.compress = s.boolean("compress");
  output.single_precision = s.string("precision") == "single";
  output.progress_every = s.integer("progress_every");
  output.contact_state = s.boolean("contact_state");
  output.checkpoint_every = s.integer("checkpoint_every");
  output.checkpoint_keep = s.integer("checkpoint_keep");
  return output;
}

}  // namespace

Scenario parse_scenario(std::string_view text, const std::filesystem::path& file,
                        const std::vector<std::string>& overrides) {
  detail::Context ctx{file.string()};
  auto root = parse_toml(text, ctx.file);
  apply_overrides(root, overrides);
  const Section top(root, scenario_section(""), "", ctx);
  Scenario scenario;
  scenario.file = file;
  scenario.text = text;
  if (!overrides.empty()) {
    std::ostringstream effective;
    effective << "# " << file.string();
    for (const std::string& item : overrides) effective << " --set '" << item << "'";
    effective << "\n# (written by conserve with the overrides applied; the file's comments are not kept)\n"
              << toml::toml_formatter{root} << "\n";
    scenario.text = effective.str();
  }
  scenario.sources = SourceMap(ctx.file);
  map_sources(root, "", scenario.sources);
  scenario.title = top.string("title");
  scenario.dimension = ctx.dimension = top.integer("dimension");
  scenario.time = parse_time(top.table("time"));
  scenario.newton = parse_newton(top.table("newton"));
  scenario.solver = parse_solver(top.table("solver"));
  scenario.gravity = top.table("loads").vector("gravity");
  scenario.output = parse_output(top.table("output"));
  scenario.curves = detail::parse_curves(top);
  scenario.bodies = detail::parse_bodies(top, file, scenario.curves);
  scenario.boundaries = detail::parse_boundaries(top, scenario.bodies, scenario.curves);
  scenario.gravity_curve = detail::curve_name(top.table("loads"), "gravity_curve", scenario.curves);
  scenario.loads = detail::parse_loads(top, scenario.bodies, scenario.curves);
  scenario.contacts = detail::parse_contacts(top, scenario.bodies);
  if (auto general = detail::parse_general_contact(top, scenario.bodies, !scenario.contacts.empty());
      !general.empty())
    scenario.contacts = std::move(general);
  scenario.active_set = detail::parse_active_set(top.table("active_set"));
  return scenario;
}

Scenario read_scenario(const std::filesystem::path& file, const std::vector<std::string>& overrides) {
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    throw InputError(fmt::format("{}: cannot open the scenario file (expected a readable TOML file)", file.string()));
  }
  std::ostringstream text;
  text << in.rdbuf();
  return parse_scenario(text.str(), file, overrides);
}

}  // namespace conserve::io
