#pragma once
/// Private to the scenario parser: typed, validated access to one TOML table
/// against its declared SectionSpec. Every error is an InputError with one
/// line "FILE:LINE: KEY: what is wrong (what was expected)".
#include <toml++/toml.h>

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "io/scenario_keys.hpp"

namespace conserve::io::detail {

/// What every section needs to know about the whole file.
struct Context {
  std::string file;   ///< the scenario file, as given (for messages)
  int dimension = 3;  ///< sizes of vectors and matrices
};

/// The source name of values given on the command line (`conserve run
/// --set`): messages about them say "--set KEY" instead of FILE:LINE.
inline constexpr std::string_view kOverrideSource = "--set";

/// Throws InputError "FILE:LINE: KEY: WHAT (EXPECTED)", LINE that of
/// `node`; "--set KEY: WHAT (EXPECTED)" if `node` came from the command line.
[[noreturn]] void fail(const Context& ctx, const toml::node& node, std::string_view key, std::string_view what,
                       std::string_view expected);

/// The source line of a node (1 when unknown).
std::uint32_t line_of(const toml::node& node);

/// "a string", "an integer", ...: the type of a node, for messages.
std::string_view type_of(const toml::node& node);

/// The value of an integer or float node; nothing for other types.
std::optional<double> number_value(const toml::node& node);

/// One TOML table checked against its SectionSpec. Construction rejects
/// unknown keys (unless the spec is open) and missing required keys; the
/// getters check type and range and apply the declared defaults.
class Section {
 public:
  /// `path` is the dotted key path of the table for messages ("" = top
  /// level, "body[0].mesh"); `ctx` must outlive the section.
  Section(const toml::table& table, const SectionSpec& spec, std::string path, const Context& ctx);

  [[nodiscard]] const toml::node* find(std::string_view key) const;
  [[nodiscard]] bool has(std::string_view key) const { return find(key) != nullptr; }
  /// The table's keys in the order of their lines in the file.
  [[nodiscard]] std::vector<std::string> keys_in_file_order() const;
  /// Dotted path of a key of this table, e.g. "body[0].material.young".
  [[nodiscard]] std::string path(std::string_view key) const;
  [[nodiscard]] const toml::table& table() const { return *table_; }
  [[nodiscard]] const Context& context() const { return *ctx_; }
  [[nodiscard]] const SectionSpec& spec() const { return *spec_; }
  [[nodiscard]] int dimension() const { return ctx_->dimension; }

  /// Fails at the key's line (the table's line if the key is absent).
  [[noreturn]] void fail(std::string_view key, std::string_view what, std::string_view expected) const;
  /// Fails at the table's own line, naming the table's path.
  [[noreturn]] void fail_table(std::string_view what, std::string_view expected) const;

  [[nodiscard]] std::string string(std::string_view key) const;
  /// The declared default ("true"/"false") if absent.
  [[nodiscard]] bool boolean(std::string_view key) const;
  [[nodiscard]] int integer(std::string_view key) const;
  [[nodiscard]] double number(std::string_view key) const;
  /// `dimension` numbers, padded with zeros; zeros if absent.
  [[nodiscard]] Eigen::Vector3d vector(std::string_view key) const;
  /// 3 numbers in 3D, one number stored in z in 2D; zeros if absent.
  [[nodiscard]] Eigen::Vector3d angular_velocity(std::string_view key) const;
  /// dimension × dimension rows, embedded in the identity; identity if absent.
  [[nodiscard]] Eigen::Matrix3d matrix(std::string_view key) const;
  /// The [t, value] pairs of a points key, t strictly increasing; empty if absent.
  [[nodiscard]] std::vector<std::pair<double, double>> points(std::string_view key) const;
  /// Sorted component indices; all of the dimension if absent.
  [[nodiscard]] std::vector<int> components(std::string_view key) const;
  /// The distinct strings of a names key, in order; empty if absent.
  [[nodiscard]] std::vector<std::string> names(std::string_view key) const;
  /// The sub-table `key`; an empty one if absent, so that the declared
  /// defaults of its keys apply.
  [[nodiscard]] Section table(std::string_view key) const;
  /// The tables of the array of tables `key` (empty if absent).
  [[nodiscard]] std::vector<Section> table_array(std::string_view key) const;

 private:
  [[nodiscard]] const KeySpec& spec_of(std::string_view key) const;
  [[nodiscard]] const SectionSpec& child_spec(std::string_view key) const;
  void check_unknown_keys() const;
  void check_required_keys() const;
  void check_range(std::string_view key, const toml::node& node, double value) const;
  /// Exactly `count` finite numbers; `expected` describes the whole array.
  [[nodiscard]] std::vector<double> numbers(const toml::node& node, const std::string& path, int count,
                                            std::string_view expected) const;
  /// 0, 1, 2 for the string "x", "y", "z" (within the dimension).
  [[nodiscard]] int component_index(const toml::node& node, const std::string& path, std::string_view expected) const;

  const toml::table* table_;
  const SectionSpec* spec_;
  std::string path_;
  const Context* ctx_;
};

/// "a number [Pa] > 0", "one of: x, y", ...: what a key expects, for messages.
std::string describe(const KeySpec& key, int dimension);

}  // namespace conserve::io::detail
