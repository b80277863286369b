/// The per-step CSV history and its reader.
#include "io/history_writer.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>

#include "core/error.hpp"

namespace conserve::io {
namespace {

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> fields;
  std::size_t start = 0;
  for (std::size_t comma; (comma = line.find(',', start)) != std::string::npos; start = comma + 1) {
    fields.push_back(line.substr(start, comma - start));
  }
  fields.push_back(line.substr(start));
  return fields;
}

bool read_line(std::istream& in, std::string& line) {
  if (!std::getline(in, line)) return false;
  if (!line.empty() && line.back() == '\r') line.pop_back();
  return true;
}

/// The whole field as a double (also "nan", "inf", "-inf"; an empty field
/// is NaN, a value not there), or nothing.
std::optional<double> to_double(const std::string& field) {
  if (field.empty()) return std::numeric_limits<double>::quiet_NaN();
  double value = 0.0;
  const auto* end = field.data() + field.size();
  const auto [ptr, error] = std::from_chars(field.data(), end, value);
  if (error != std::errc() || ptr != end) return std::nullopt;
  return value;
}

std::vector<double> parse_row(const std::string& line, std::size_t columns, const std::string& where) {
  const auto fields = split(line);
  if (fields.size() != columns) {
    throw InputError(fmt::format("{}: malformed row: {} fields (expected {})", where, fields.size(), columns));
  }
  std::vector<double> row;
  for (const auto& field : fields) {
    const auto value = to_double(field);
    if (!value) {
      throw InputError(fmt::format("{}: malformed row: '{}' is not a number (expected a number)", where, field));
    }
    row.push_back(*value);
  }
  return row;
}

/// Files to resume rather than truncate, with the last step to keep.
std::map<std::filesystem::path, std::int64_t>& pending_resumes() {
  static std::map<std::filesystem::path, std::int64_t> pending;
  return pending;
}
std::mutex& resume_mutex() {
  static std::mutex m;
  return m;
}

std::optional<std::int64_t> take_resume(const std::filesystem::path& file) {
  const std::lock_guard lock(resume_mutex());
  const auto it = pending_resumes().find(file);
  if (it == pending_resumes().end()) return std::nullopt;
  const std::int64_t step = it->second;
  pending_resumes().erase(it);
  return step;
}

/// The header and the rows up to `last_step` of an existing history, as text.
std::string kept_prefix(const std::filesystem::path& file, const std::string& header, std::int64_t last_step) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return header + '\n';  // a restart into a new folder: the rows start after the restart step
  std::string line, kept;
  if (!read_line(in, line) || line != header)
    throw InputError(fmt::format("{}: cannot resume: its header differs from this run's columns", file.string()));
  kept = line + '\n';
  bool found = false;
  while (read_line(in, line)) {
    const auto step = to_double(line.substr(0, line.find(',')));
    if (!step || std::isnan(*step) || *step > static_cast<double>(last_step)) break;
    found = found || *step == static_cast<double>(last_step);
    kept += line + '\n';
  }
  if (!found) throw InputError(fmt::format("{}: cannot resume: it has no row of step {}", file.string(), last_step));
  return kept;
}

/// Writes `text` to FILE.tmp and renames it onto `file`.
void replace_file(const std::filesystem::path& file, const std::string& text) {
  auto temporary = file;
  temporary += ".tmp";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out << text;
    if (!out.flush()) throw Error(fmt::format("{}: write failed", temporary.string()));
  }
  std::error_code error;
  std::filesystem::rename(temporary, file, error);
  if (error) throw Error(fmt::format("{}: cannot rename into place: {}", file.string(), error.message()));
}

}  // namespace

void resume_history(const std::filesystem::path& file, std::int64_t last_step) {
  const std::lock_guard lock(resume_mutex());
  pending_resumes()[file] = last_step;
}

HistoryWriter::HistoryWriter(const std::filesystem::path& file, std::vector<std::string> columns)
    : columns_(columns.size()), file_(file) {
  for (const auto& name : columns) {
    if (name.empty() || name.find_first_of(",\r\n") != std::string::npos) {
      throw Error(
          fmt::format("{}: bad history column name '{}' (empty or with a comma or line break)", file.string(), name));
    }
  }
  const std::string header = fmt::format("{}", fmt::join(columns, ","));
  if (const auto step = take_resume(file)) {
    replace_file(file, kept_prefix(file, header, *step));
    out_.open(file, std::ios::binary | std::ios::app);
  } else {
    out_.open(file, std::ios::trunc);
    out_ << header << '\n' << std::flush;
  }
  if (!out_) throw Error(fmt::format("{}: cannot open for writing", file.string()));
}

void HistoryWriter::write_row(const std::vector<double>& values) {
  if (values.size() != columns_) {
    throw Error(fmt::format("{}: row of {} values for {} columns", file_.string(), values.size(), columns_));
  }
  std::string line;
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (i > 0) line += ',';
    if (!std::isnan(values[i])) line += fmt::format("{:.17g}", values[i]);  // NaN: an empty field
  }
  out_ << line << '\n' << std::flush;
  if (!out_) throw Error(fmt::format("{}: write failed", file_.string()));
}

std::vector<double> History::column(const std::string& name) const {
  for (std::size_t j = 0; j < columns.size(); ++j) {
    if (columns[j] != name) continue;
    std::vector<double> values;
    for (const auto& row : rows) values.push_back(row[j]);
    return values;
  }
  throw InputError(fmt::format("history has no column '{}' (expected one of: {})", name, fmt::join(columns, ", ")));
}

History read_history(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw InputError(fmt::format("{}: cannot open the history file", file.string()));
  History history;
  std::string line;
  if (!read_line(in, line) || line.empty()) {
    throw InputError(fmt::format("{}:1: no header line (expected comma-separated column names)", file.string()));
  }
  history.columns = split(line);
  for (int number = 2; read_line(in, line); ++number) {
    history.rows.push_back(parse_row(line, history.columns.size(), fmt::format("{}:{}", file.string(), number)));
  }
  return history;
}

}  // namespace conserve::io
