#include "io/names.hpp"

#include <fmt/format.h>

namespace conserve::io {

std::string name_problem(std::string_view name) {
  if (name.empty()) return "is empty";
  for (const char c : name) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20 || byte == 0x7f) return fmt::format("contains U+{:04X} (a control character)", byte);
  }
  for (const auto& [c, what] :
       {std::pair{',', "a comma"}, std::pair{'"', "a double quote"}, std::pair{':', "a colon"}}) {
    if (name.find(c) != std::string_view::npos) return fmt::format("'{}' contains '{}' ({})", name, c, what);
  }
  if (name.front() == ' ') return fmt::format("'{}' starts with a space", name);
  if (name.back() == ' ') return fmt::format("'{}' ends with a space", name);
  return {};
}

}  // namespace conserve::io
