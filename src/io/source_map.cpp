#include "io/source_map.hpp"

#include <fmt/format.h>

namespace conserve::io {

std::string SourceMap::locate(std::string_view path) const {
  for (std::string_view p = path;;) {
    if (const auto it = lines_.find(p); it != lines_.end()) {
      if (it->second == 0 && p == path) return fmt::format("--set {}", path);
      if (it->second > 0) return fmt::format("{}:{}: {}", file_, it->second, path);
    }
    const std::size_t cut = p.find_last_of(".[");  // "body[0].mesh" → "body[0]" → "body"
    if (cut == std::string_view::npos || cut == 0) return fmt::format("{}: {}", file_, path);
    p = p.substr(0, cut);
  }
}

}  // namespace conserve::io
