#pragma once
/// The per-step CSV history: one header line, one row per step, flushed
/// after every row so that a killed run leaves complete rows behind.
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace conserve::io {

class HistoryWriter {
 public:
  /// Creates (truncates) `file` and writes the header. Throws Error. If
  /// resume_history(file, step) was called before, keeps the existing rows
  /// up to that step instead (restarts).
  HistoryWriter(const std::filesystem::path& file, std::vector<std::string> columns);
  /// Writes one row; values.size() must equal the number of columns.
  /// Doubles are written with 17 significant digits (round-trip exact);
  /// NaN as an empty field (a value that is not there).
  void write_row(const std::vector<double>& values);

 private:
  std::ofstream out_;
  std::size_t columns_;
  std::filesystem::path file_{};  ///< for messages
};

/// Restarts: the next HistoryWriter opened on `file` keeps the existing
/// file's rows whose first column (the step) is ≤ `last_step` and appends
/// after them, rather than truncating it (a missing file is started anew).
/// That writer throws InputError if the file has another header or lacks
/// the row of `last_step`.
void resume_history(const std::filesystem::path& file, std::int64_t last_step);

/// Reads a history written by HistoryWriter (for tests and plotting):
/// header names and rows. Throws InputError on a malformed file.
struct History {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  [[nodiscard]] std::vector<double> column(const std::string& name) const;
};
History read_history(const std::filesystem::path& file);

}  // namespace conserve::io
