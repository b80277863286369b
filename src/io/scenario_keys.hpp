#pragma once
/// The scenario keys, declared once: each TOML table of a scenario has a
/// SectionSpec listing its keys with type, default, unit, allowed range and
/// meaning. The parser validates against these tables and the reference in
/// docs/scenario.md is generated from them (a test keeps the two in sync).
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace conserve::io {

/// What a key's value must be.
enum class KeyType {
  string,            ///< a string
  boolean,           ///< true or false
  choice,            ///< a string out of KeySpec::choices
  integer,           ///< an integer (no floats)
  number,            ///< a finite float or integer
  vector,            ///< an array of `dimension` numbers
  angular_velocity,  ///< 3D: an array of 3 numbers; 2D: one number (about z)
  matrix,            ///< `dimension` rows, each an array of `dimension` numbers
  points,            ///< an array of [t, value] pairs, t strictly increasing
  components,        ///< a non-empty array of distinct "x", "y" (, "z" in 3D)
  names,             ///< an array of distinct strings
  table,             ///< a sub-table (its own SectionSpec)
  table_array,       ///< an array of tables, [[name]] (its own SectionSpec)
};

/// A bound of an allowed numeric range.
struct Bound {
  double value = 0.0;
  bool inclusive = false;  ///< ≥/≤ rather than >/<
};

/// One key of a scenario table.
struct KeySpec {
  std::string_view name{};
  KeyType type = KeyType::number;
  bool required = false;
  /// Default as shown in the docs. For string, choice, boolean, integer and
  /// number keys it is also the value the parser uses when the key is absent.
  std::string_view default_value{};
  std::string_view unit{};                  ///< SI unit, empty if dimensionless
  std::optional<Bound> min{};               ///< lower bound (integer and number keys)
  std::optional<Bound> max{};               ///< upper bound (integer and number keys)
  std::vector<std::string_view> choices{};  ///< allowed strings of a choice key
  std::string_view doc{};                   ///< one-line meaning
};

/// One TOML table of the scenario.
struct SectionSpec {
  std::string_view name{};  ///< dotted table name as written in TOML ("" = top level)
  std::string_view doc{};
  std::vector<KeySpec> keys{};
  /// Also accepts keys not listed (body.mesh: the generator's parameters,
  /// validated against mesh::generator_catalog()).
  bool open = false;
  /// Keys of earlier versions, with what to do instead (an error names it).
  std::vector<std::pair<std::string_view, std::string_view>> retired{};
};

/// All scenario tables, top level first, in documentation order.
const std::vector<SectionSpec>& scenario_sections();

/// The table called `name` ("" = top level, "time", "body.material", ...).
/// Throws std::out_of_range for an unknown name (a programming error).
const SectionSpec& scenario_section(std::string_view name);

/// The key reference of docs/scenario.md (Markdown), generated from
/// scenario_sections().
std::string scenario_key_reference();

/// The material model reference of docs/scenario.md (Markdown), generated
/// from material::law_catalog().
std::string material_reference();

/// The mesh generator reference of docs/scenario.md (Markdown), generated
/// from mesh::generator_catalog().
std::string generator_reference();

/// "> -1 and < 0.5": a key's allowed range ("" if unbounded).
std::string range_text(const KeySpec& key);

/// "a, b, c": the names of a section's keys, for messages.
std::string key_names(const SectionSpec& section);

}  // namespace conserve::io
