/// Section: construction checks, scalar getters and sub-tables.
#include "io/toml_section.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>

#include "core/error.hpp"

namespace conserve::io::detail {
namespace {

/// Parses a declared default ("20", "1e-12"); 0 if empty.
template <typename T>
T parse_default(const KeySpec& key) {
  T value{};
  const auto text = key.default_value;
  std::from_chars(text.data(), text.data() + text.size(), value);
  return value;
}

std::string unit_text(const KeySpec& key) { return key.unit.empty() ? std::string() : fmt::format(" [{}]", key.unit); }

std::string with_range(std::string text, const KeySpec& key) {
  const auto range = range_text(key);
  return range.empty() ? text : text + " " + range;
}

}  // namespace

std::vector<std::string> Section::keys_in_file_order() const {
  std::vector<std::pair<std::uint32_t, std::string>> keys;
  for (const auto& [key, node] : *table_) keys.emplace_back(line_of(node), std::string(key.str()));
  std::sort(keys.begin(), keys.end());
  std::vector<std::string> names;
  for (auto& key : keys) names.push_back(std::move(key.second));
  return names;
}

void fail(const Context& ctx, const toml::node& node, std::string_view key, std::string_view what,
          std::string_view expected) {
  if (const auto& source = node.source().path; source && *source == kOverrideSource)
    throw InputError(fmt::format("{} {}: {} (expected {})", kOverrideSource, key, what, expected));
  throw InputError(fmt::format("{}:{}: {}: {} (expected {})", ctx.file, line_of(node), key, what, expected));
}

std::uint32_t line_of(const toml::node& node) { return std::max<std::uint32_t>(node.source().begin.line, 1); }

std::string_view type_of(const toml::node& node) {
  switch (node.type()) {
    case toml::node_type::table:
      return "a table";
    case toml::node_type::array:
      return "an array";
    case toml::node_type::string:
      return "a string";
    case toml::node_type::integer:
      return "an integer";
    case toml::node_type::floating_point:
      return "a float";
    case toml::node_type::boolean:
      return "a boolean";
    case toml::node_type::date:
      return "a date";
    case toml::node_type::time:
      return "a time";
    case toml::node_type::date_time:
      return "a date-time";
    case toml::node_type::none:
      break;
  }
  return "nothing";
}

std::optional<double> number_value(const toml::node& node) {
  if (const auto* integer = node.as_integer()) return static_cast<double>(integer->get());
  if (const auto* floating = node.as_floating_point()) return floating->get();
  return std::nullopt;
}

std::string describe(const KeySpec& key, int dimension) {
  const auto unit = unit_text(key);
  switch (key.type) {
    case KeyType::string:
      return "a string";
    case KeyType::choice:
      return fmt::format("one of: {}", fmt::join(key.choices, ", "));
    case KeyType::boolean:
      return "true or false";
    case KeyType::integer:
      return with_range("an integer", key);
    case KeyType::number:
      return with_range("a finite number" + unit, key);
    case KeyType::vector:
      return fmt::format("an array of {} numbers{}", dimension, unit);
    case KeyType::angular_velocity:
      return dimension == 3 ? "an array of 3 numbers" + unit : "one number" + unit + ", the rotation about z in 2D";
    case KeyType::matrix:
      return fmt::format("{0} rows, each an array of {0} numbers", dimension);
    case KeyType::points:
      return "an array of at least two [t, value] pairs of numbers, t [s] strictly increasing";
    case KeyType::components:
      return dimension == 3 ? "a non-empty array of distinct strings out of x, y, z"
                            : "a non-empty array of distinct strings out of x, y";
    case KeyType::names:
      return "an array of distinct strings";
    case KeyType::table:
      return fmt::format("a table [{}]", key.name);
    case KeyType::table_array:
      return fmt::format("one or more [[{}]] tables", key.name);
  }
  return "?";
}

Section::Section(const toml::table& table, const SectionSpec& spec, std::string path, const Context& ctx)
    : table_(&table), spec_(&spec), path_(std::move(path)), ctx_(&ctx) {
  check_unknown_keys();
  check_required_keys();
}

const toml::node* Section::find(std::string_view key) const { return table_->get(key); }

std::string Section::path(std::string_view key) const {
  return path_.empty() ? std::string(key) : fmt::format("{}.{}", path_, key);
}

void Section::fail(std::string_view key, std::string_view what, std::string_view expected) const {
  const auto* node = find(key);
  detail::fail(*ctx_, node ? *node : *table_, path(key), what, expected);
}

void Section::fail_table(std::string_view what, std::string_view expected) const {
  detail::fail(*ctx_, *table_, path_, what, expected);
}

const KeySpec& Section::spec_of(std::string_view key) const {
  for (const auto& spec : spec_->keys) {
    if (spec.name == key) return spec;
  }
  throw std::logic_error(fmt::format("key '{}' is not declared in section '{}'", key, spec_->name));
}

const SectionSpec& Section::child_spec(std::string_view key) const {
  return scenario_section(spec_->name.empty() ? std::string(key) : fmt::format("{}.{}", spec_->name, key));
}

void Section::check_unknown_keys() const {
  if (spec_->open) return;
  const toml::key* first = nullptr;  // the first unknown key in the file
  for (const auto& [key, node] : *table_) {
    const std::string_view name = key.str();  // clang 14 cannot capture a structured binding
    const bool known =
        std::any_of(spec_->keys.begin(), spec_->keys.end(), [&](const KeySpec& spec) { return spec.name == name; });
    if (!known && (!first || line_of(node) < line_of(*find(first->str())))) first = &key;
  }
  if (!first) return;
  for (const auto& [name, instead] : spec_->retired)
    if (name == first->str()) fail(first->str(), fmt::format("'{}' is no longer a key", name), instead);
  fail(first->str(), fmt::format("unknown key '{}'", first->str()), "one of: " + key_names(*spec_));
}

void Section::check_required_keys() const {
  for (const auto& spec : spec_->keys) {
    if (spec.required && !has(spec.name)) fail(spec.name, "missing key", describe(spec, ctx_->dimension));
  }
}

void Section::check_range(std::string_view key, const toml::node& node, double value) const {
  const auto& spec = spec_of(key);
  const bool low = spec.min && (spec.min->inclusive ? value < spec.min->value : value <= spec.min->value);
  const bool high = spec.max && (spec.max->inclusive ? value > spec.max->value : value >= spec.max->value);
  if (low || high) {
    detail::fail(*ctx_, node, path(key), fmt::format("{} is out of range", value), describe(spec, ctx_->dimension));
  }
}

std::string Section::string(std::string_view key) const {
  const auto& spec = spec_of(key);
  const auto* node = find(key);
  if (!node) return std::string(spec.default_value);
  if (!node->is_string()) fail(key, fmt::format("got {}", type_of(*node)), describe(spec, ctx_->dimension));
  auto text = node->as_string()->get();
  const bool allowed =
      spec.type != KeyType::choice || std::find(spec.choices.begin(), spec.choices.end(), text) != spec.choices.end();
  if (!allowed) fail(key, fmt::format("'{}' is not allowed", text), describe(spec, ctx_->dimension));
  return text;
}

bool Section::boolean(std::string_view key) const {
  const auto& spec = spec_of(key);
  const auto* node = find(key);
  if (!node) return spec.default_value == "true";
  if (!node->is_boolean()) fail(key, fmt::format("got {}", type_of(*node)), describe(spec, ctx_->dimension));
  return node->as_boolean()->get();
}

int Section::integer(std::string_view key) const {
  const auto& spec = spec_of(key);
  const auto* node = find(key);
  if (!node) return parse_default<int>(spec);
  if (!node->is_integer()) fail(key, fmt::format("got {}", type_of(*node)), describe(spec, ctx_->dimension));
  const auto value = node->as_integer()->get();
  check_range(key, *node, static_cast<double>(value));
  if (value < std::numeric_limits<int>::min() || value > std::numeric_limits<int>::max()) {
    fail(key, fmt::format("{} is too large", value), describe(spec, ctx_->dimension));
  }
  return static_cast<int>(value);
}

double Section::number(std::string_view key) const {
  const auto& spec = spec_of(key);
  const auto* node = find(key);
  if (!node) return parse_default<double>(spec);
  const auto value = number_value(*node);
  if (!value) fail(key, fmt::format("got {}", type_of(*node)), describe(spec, ctx_->dimension));
  if (!std::isfinite(*value)) fail(key, fmt::format("{} is not finite", *value), describe(spec, ctx_->dimension));
  check_range(key, *node, *value);
  return *value;
}

Section Section::table(std::string_view key) const {
  static const toml::table empty;
  const auto* node = find(key);
  if (!node) return Section(empty, child_spec(key), path(key), *ctx_);
  if (!node->is_table()) fail(key, fmt::format("got {}", type_of(*node)), describe(spec_of(key), ctx_->dimension));
  return Section(*node->as_table(), child_spec(key), path(key), *ctx_);
}

std::vector<Section> Section::table_array(std::string_view key) const {
  const auto& spec = spec_of(key);
  const auto* node = find(key);
  if (!node) return {};
  const auto* array = node->as_array();
  if (!array) fail(key, fmt::format("got {}", type_of(*node)), describe(spec, ctx_->dimension));
  if (array->empty()) fail(key, "is empty", describe(spec, ctx_->dimension));
  std::vector<Section> sections;
  for (std::size_t i = 0; i < array->size(); ++i) {
    const auto& element = *array->get(i);
    const auto element_path = fmt::format("{}[{}]", path(key), i);
    if (!element.is_table()) {
      detail::fail(*ctx_, element, element_path, fmt::format("got {}", type_of(element)), "a table");
    }
    sections.emplace_back(*element.as_table(), child_spec(key), element_path, *ctx_);
  }
  return sections;
}

}  // namespace conserve::io::detail
