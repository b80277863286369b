#pragma once
/// Where each table and key of a scenario was given, so that errors found
/// after parsing (while the model is built) name the file and line, as the
/// parser's own errors do. Paths are those of the parser's messages:
/// "time.step", "body[0].mesh", "contact[1].slave".
#include <map>
#include <string>
#include <string_view>

namespace conserve::io {

class SourceMap {
 public:
  SourceMap() = default;
  explicit SourceMap(std::string file) : file_(std::move(file)) {}

  /// Records `path` as given on line `line` of the file, or on the command
  /// line (`conserve run --set`) when `line` is 0.
  void add(std::string path, int line) { lines_[std::move(path)] = line; }

  /// "FILE:LINE: PATH" (LINE that of PATH, or of the nearest enclosing table
  /// given in the file when PATH is absent, e.g. a key left to its default),
  /// or "--set PATH" when PATH was given on the command line. The prefix
  /// of a one-line error about PATH.
  [[nodiscard]] std::string locate(std::string_view path) const;

 private:
  std::string file_;
  std::map<std::string, int, std::less<>> lines_;
};

}  // namespace conserve::io
