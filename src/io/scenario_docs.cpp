/// Markdown reference of the scenario keys and mesh generators, generated
/// from the declared tables (docs/scenario.md embeds it; a test compares).
#include <fmt/format.h>

#include <limits>

#include "io/scenario_keys.hpp"
#include "material/law.hpp"
#include "mesh/generators.hpp"

namespace conserve::io {
namespace {

std::string escape_cell(std::string_view text) {
  std::string out;
  for (char c : text) {
    if (c == '|') out += '\\';
    out += c;
  }
  return out;
}

std::string_view type_name(KeyType type) {
  switch (type) {
    case KeyType::string:
      return "string";
    case KeyType::choice:
      return "string";
    case KeyType::boolean:
      return "boolean";
    case KeyType::integer:
      return "integer";
    case KeyType::number:
      return "number";
    case KeyType::vector:
      return "array of numbers";
    case KeyType::angular_velocity:
      return "number (2D) or array of 3 numbers (3D)";
    case KeyType::matrix:
      return "array of arrays of numbers";
    case KeyType::points:
      return "array of [t, value] pairs";
    case KeyType::components:
    case KeyType::names:
      return "array of strings";
    case KeyType::table:
      return "table";
    case KeyType::table_array:
      return "array of tables";
  }
  return "?";
}

std::string default_cell(const KeySpec& key) {
  if (key.required) return "required";
  if (key.default_value.empty()) return "—";
  const bool literal = key.type == KeyType::string || key.type == KeyType::choice;
  if (literal) return fmt::format("`\"{}\"`", key.default_value);
  const bool scalar = key.type == KeyType::boolean || key.type == KeyType::integer || key.type == KeyType::number;
  if (scalar) return fmt::format("`{}`", key.default_value);
  return std::string(key.default_value);
}

std::string allowed_cell(const KeySpec& key) {
  std::string text = range_text(key);
  for (auto choice : key.choices) {
    text += fmt::format("{}`{}`", text.empty() ? "" : ", ", choice);
  }
  return text;
}

/// "Top level", "`[time]`" or "`[[body]]`".
std::string heading(const SectionSpec& section) {
  if (section.name.empty()) return "Top level";
  const auto dot = section.name.rfind('.');
  const auto parent = dot == std::string_view::npos ? std::string_view{} : section.name.substr(0, dot);
  const auto own = dot == std::string_view::npos ? section.name : section.name.substr(dot + 1);
  for (const auto& key : scenario_section(parent).keys) {
    if (key.name == own && key.type == KeyType::table_array) return fmt::format("`[[{}]]`", section.name);
  }
  return fmt::format("`[{}]`", section.name);
}

std::string section_reference(const SectionSpec& section) {
  std::string out = fmt::format("### {}\n\n{}\n\n", heading(section), section.doc);
  out += "| key | type | default | unit | allowed | meaning |\n";
  out += "|---|---|---|---|---|---|\n";
  for (const auto& key : section.keys) {
    out += fmt::format("| `{}` | {} | {} | {} | {} | {} |\n", key.name, type_name(key.type), default_cell(key),
                       key.unit, allowed_cell(key), escape_cell(key.doc));
  }
  return out;
}

std::string generator_section(const std::string& name, const mesh::GeneratorInfo& info) {
  std::string out = fmt::format("### `{}` ({}D)\n\n{}\n\n", name, info.dim, escape_cell(info.doc));
  out += "| parameter | default | unit | meaning |\n";
  out += "|---|---|---|---|\n";
  for (const auto& p : info.parameters) {
    const auto def = p.required ? std::string("required") : fmt::format("`{}`", p.default_value);
    out += fmt::format("| `{}` | {} | {} | {} |\n", p.name, def, p.unit, escape_cell(p.doc));
  }
  return out;
}

std::string material_section(const std::string& name, const material::LawInfo& info) {
  std::string out = fmt::format("### `model = \"{}\"`\n\n{}\n\n", name, escape_cell(info.doc));
  out += "| parameter | unit | allowed | meaning |\n";
  out += "|---|---|---|---|\n";
  for (const auto& p : info.parameters) {
    std::string range;
    if (p.min > -std::numeric_limits<double>::infinity())
      range = fmt::format("{} {:g}", p.min_inclusive ? "≥" : ">", p.min);
    if (p.max < std::numeric_limits<double>::infinity())
      range += fmt::format("{}< {:g}", range.empty() ? "" : " and ", p.max);
    out += fmt::format("| `{}` | {} | {} | {} |\n", p.name, p.unit, range, escape_cell(p.doc));
  }
  return out;
}

}  // namespace

std::string range_text(const KeySpec& key) {
  std::string text;
  if (key.min) text = fmt::format("{} {}", key.min->inclusive ? "≥" : ">", key.min->value);
  if (key.min && key.max) text += " and ";
  if (key.max) text += fmt::format("{} {}", key.max->inclusive ? "≤" : "<", key.max->value);
  return text;
}

std::string scenario_key_reference() {
  std::string out;
  for (const auto& section : scenario_sections()) {
    if (!out.empty()) out += '\n';
    out += section_reference(section);
  }
  return out;
}

std::string material_reference() {
  std::string out;
  for (const auto& [name, info] : material::law_catalog()) {
    if (!out.empty()) out += '\n';
    out += material_section(name, info);
  }
  return out;
}

std::string generator_reference() {
  std::string out;
  for (const auto& [name, info] : mesh::generator_catalog()) {
    if (!out.empty()) out += '\n';
    out += generator_section(name, info);
  }
  return out;
}

}  // namespace conserve::io
