/// Section: array-valued keys (vectors, matrices, component lists).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "io/toml_section.hpp"

namespace conserve::io::detail {

std::vector<double> Section::numbers(const toml::node& node, const std::string& path, int count,
                                     std::string_view expected) const {
  const auto* array = node.as_array();
  if (!array) detail::fail(*ctx_, node, path, fmt::format("got {}", type_of(node)), expected);
  if (array->size() != static_cast<std::size_t>(count)) {
    detail::fail(*ctx_, node, path, fmt::format("has {} elements", array->size()), expected);
  }
  std::vector<double> values;
  for (std::size_t i = 0; i < array->size(); ++i) {
    const auto& element = *array->get(i);
    const auto value = number_value(element);
    const auto element_path = fmt::format("{}[{}]", path, i);
    if (!value) {
      detail::fail(*ctx_, element, element_path, fmt::format("got {}", type_of(element)), "a number");
    }
    if (!std::isfinite(*value)) {
      detail::fail(*ctx_, element, element_path, fmt::format("{} is not finite", *value), "a finite number");
    }
    values.push_back(*value);
  }
  return values;
}

Eigen::Vector3d Section::vector(std::string_view key) const {
  Eigen::Vector3d result = Eigen::Vector3d::Zero();
  const auto* node = find(key);
  if (!node) return result;
  const int dim = ctx_->dimension;
  const auto values = numbers(*node, path(key), dim, describe(spec_of(key), dim));
  for (int i = 0; i < dim; ++i) result(i) = values[static_cast<std::size_t>(i)];
  return result;
}

Eigen::Vector3d Section::angular_velocity(std::string_view key) const {
  Eigen::Vector3d result = Eigen::Vector3d::Zero();
  const auto* node = find(key);
  if (!node) return result;
  const auto expected = describe(spec_of(key), ctx_->dimension);
  if (ctx_->dimension == 3) {
    const auto values = numbers(*node, path(key), 3, expected);
    return {values[0], values[1], values[2]};
  }
  const auto value = number_value(*node);
  if (!value) fail(key, fmt::format("got {}", type_of(*node)), expected);
  if (!std::isfinite(*value)) fail(key, fmt::format("{} is not finite", *value), expected);
  result.z() = *value;
  return result;
}

Eigen::Matrix3d Section::matrix(std::string_view key) const {
  Eigen::Matrix3d result = Eigen::Matrix3d::Identity();
  const auto* node = find(key);
  if (!node) return result;
  const int dim = ctx_->dimension;
  const auto expected = describe(spec_of(key), dim);
  const auto* rows = node->as_array();
  if (!rows) fail(key, fmt::format("got {}", type_of(*node)), expected);
  if (rows->size() != static_cast<std::size_t>(dim)) fail(key, fmt::format("has {} rows", rows->size()), expected);
  for (int i = 0; i < dim; ++i) {
    const auto row_path = fmt::format("{}[{}]", path(key), i);
    const auto row =
        numbers(*rows->get(static_cast<std::size_t>(i)), row_path, dim, fmt::format("an array of {} numbers", dim));
    for (int j = 0; j < dim; ++j) result(i, j) = row[static_cast<std::size_t>(j)];
  }
  return result;
}

std::vector<std::pair<double, double>> Section::points(std::string_view key) const {
  std::vector<std::pair<double, double>> result;
  const auto* node = find(key);
  if (!node) return result;
  const auto expected = describe(spec_of(key), ctx_->dimension);
  const auto* rows = node->as_array();
  if (!rows) fail(key, fmt::format("got {}", type_of(*node)), expected);
  if (rows->size() < 2) fail(key, fmt::format("has {} point(s)", rows->size()), expected);
  for (std::size_t i = 0; i < rows->size(); ++i) {
    const auto row_path = fmt::format("{}[{}]", path(key), i);
    const auto pair = numbers(*rows->get(i), row_path, 2, "an array of 2 numbers [t, value]");
    if (!result.empty() && !(pair[0] > result.back().first))
      detail::fail(*ctx_, *rows->get(i), row_path,
                   fmt::format("time {} does not come after {} (point {})", pair[0], result.back().first, i - 1),
                   "times that strictly increase");
    result.emplace_back(pair[0], pair[1]);
  }
  return result;
}

std::vector<int> Section::components(std::string_view key) const {
  const int dim = ctx_->dimension;
  const auto* node = find(key);
  std::vector<int> result;
  if (!node) {
    for (int i = 0; i < dim; ++i) result.push_back(i);
    return result;
  }
  const auto expected = describe(spec_of(key), dim);
  const auto* array = node->as_array();
  if (!array) fail(key, fmt::format("got {}", type_of(*node)), expected);
  if (array->empty()) fail(key, "is empty", expected);
  for (std::size_t i = 0; i < array->size(); ++i) {
    const auto& element = *array->get(i);
    const auto element_path = fmt::format("{}[{}]", path(key), i);
    const int index = component_index(element, element_path, expected);
    if (std::find(result.begin(), result.end(), index) != result.end()) {
      detail::fail(*ctx_, element, element_path, fmt::format("'{}' is repeated", "xyz"[index]), expected);
    }
    result.push_back(index);
  }
  std::sort(result.begin(), result.end());
  return result;
}

std::vector<std::string> Section::names(std::string_view key) const {
  const auto* node = find(key);
  std::vector<std::string> result;
  if (!node) return result;
  const auto expected = describe(spec_of(key), ctx_->dimension);
  const auto* array = node->as_array();
  if (!array) fail(key, fmt::format("got {}", type_of(*node)), expected);
  for (std::size_t i = 0; i < array->size(); ++i) {
    const auto& element = *array->get(i);
    const auto element_path = fmt::format("{}[{}]", path(key), i);
    const auto* name = element.as_string();
    if (!name) detail::fail(*ctx_, element, element_path, fmt::format("got {}", type_of(element)), expected);
    if (std::find(result.begin(), result.end(), name->get()) != result.end())
      detail::fail(*ctx_, element, element_path, fmt::format("'{}' is repeated", name->get()), expected);
    result.push_back(name->get());
  }
  return result;
}

int Section::component_index(const toml::node& node, const std::string& path, std::string_view expected) const {
  const auto* name = node.as_string();
  if (!name) detail::fail(*ctx_, node, path, fmt::format("got {}", type_of(node)), expected);
  const auto& text = name->get();
  const int index = text.size() == 1 ? text[0] - 'x' : -1;
  if (index < 0 || index >= ctx_->dimension) {
    detail::fail(*ctx_, node, path, fmt::format("'{}' is not a component in {}D", text, ctx_->dimension), expected);
  }
  return index;
}

}  // namespace conserve::io::detail
