#include "mesh/msh_cursor.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>

#include "core/error.hpp"

namespace conserve::mesh::detail {

namespace {

bool is_space(char c) { return c == ' ' || c == '\n' || c == '\r' || c == '\t' || c == '\v' || c == '\f'; }

/// Parses the whole token as a T; false if it is not exactly one number.
template <typename T>
bool parse_whole(std::string_view token, T& value) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  const char* end = token.data() + token.size();
  const auto result = std::from_chars(token.data(), end, value);
  return result.ec == std::errc() && result.ptr == end;
}

}  // namespace

std::string printable(std::string_view token) {
  std::string out;
  for (const char c : token.substr(0, 24)) {
    const auto u = static_cast<unsigned char>(c);
    out += (u >= 32 && u < 127) ? std::string(1, c) : fmt::format("\\x{:02x}", u);
  }
  if (token.size() > 24) out += "...";
  return out;
}

MshCursor::MshCursor(std::string_view bytes, std::string name) : bytes_(bytes), name_(std::move(name)) {}

bool MshCursor::at_end() {
  while (pos_ < bytes_.size() && is_space(bytes_[pos_])) ++pos_;
  return pos_ == bytes_.size();
}

std::string_view MshCursor::word() {
  if (at_end()) fail_eof();
  const std::size_t start = pos_;
  while (pos_ < bytes_.size() && !is_space(bytes_[pos_])) ++pos_;
  return bytes_.substr(start, pos_ - start);
}

void MshCursor::skip_line() {
  const std::size_t newline = bytes_.find('\n', pos_);
  if (newline == std::string_view::npos) fail_eof();
  pos_ = newline + 1;
}

std::string MshCursor::quoted() {
  if (at_end()) fail_eof();
  const std::size_t start = pos_;
  if (bytes_[pos_] != '"') fail(start, fmt::format("expected a quoted name but found '{}'", printable(word())));
  const std::size_t close = bytes_.find_first_of("\"\n", pos_ + 1);
  if (close == std::string_view::npos) fail_eof();
  if (bytes_[close] != '"') fail(start, "unterminated quoted name (expected a closing '\"' on the same line)");
  pos_ = close + 1;
  return std::string(bytes_.substr(start + 1, close - start - 1));
}

std::string_view MshCursor::take_bytes(std::size_t n) {
  if (remaining() < n) fail_eof();
  const std::string_view out = bytes_.substr(pos_, n);
  pos_ += n;
  return out;
}

std::size_t MshCursor::value_start() {
  if (!binary_values()) at_end();
  return pos_;
}

std::string_view MshCursor::number_token(std::string_view what) {
  if (at_end()) fail_eof();
  const std::size_t start = pos_;
  const std::string_view token = word();
  if (token.front() == '$')
    fail(start, fmt::format("found '{}' where {} was expected (section ended early or counts are wrong)",
                            printable(token), what));
  return token;
}

int MshCursor::read_int(std::string_view what) {
  if (binary_values()) {
    std::int32_t value = 0;
    std::memcpy(&value, take_bytes(4).data(), 4);
    return value;
  }
  const std::size_t start = value_start();
  const std::string_view token = number_token(what);
  long long value = 0;
  if (!parse_whole(token, value))
    fail(start, fmt::format("non-numeric token '{}' (expected {}, an integer)", printable(token), what));
  if (value < std::numeric_limits<int>::min() || value > std::numeric_limits<int>::max())
    fail(start, fmt::format("{} {} is out of range (expected a 32-bit integer)", what, value));
  return static_cast<int>(value);
}

std::uint64_t MshCursor::read_size(std::string_view what) {
  if (binary_values()) {
    std::uint64_t value = 0;
    std::memcpy(&value, take_bytes(8).data(), 8);
    return value;
  }
  const std::size_t start = value_start();
  const std::string_view token = number_token(what);
  unsigned long long value = 0;
  long long negative = 0;
  if (parse_whole(token, negative) && negative < 0)
    fail(start, fmt::format("{} {} is negative (expected a non-negative integer)", what, negative));
  if (!parse_whole(token, value))
    fail(start, fmt::format("non-numeric token '{}' (expected {}, a non-negative integer)", printable(token), what));
  return value;
}

double MshCursor::read_double(std::string_view what) {
  double value = 0.0;
  const std::size_t start = value_start();
  if (binary_values()) {
    std::memcpy(&value, take_bytes(8).data(), 8);
  } else {
    const std::string_view token = number_token(what);
    if (!parse_whole(token, value))
      fail(start, fmt::format("non-numeric token '{}' (expected {}, a number)", printable(token), what));
  }
  if (!std::isfinite(value)) fail(start, fmt::format("{} is not a finite number", what));
  return value;
}

std::uint64_t MshCursor::read_count(std::string_view what, std::size_t tokens, std::size_t bytes) {
  const std::size_t start = value_start();
  const std::uint64_t count = read_size(what);
  const std::size_t each = binary_values() ? bytes : 2 * tokens;
  if (each > 0 && count > remaining() / each)
    fail(start, fmt::format("section {}: {} {} does not fit in the {} bytes left (truncated or corrupt file)", section_,
                            what, count, remaining()));
  return count;
}

std::int32_t MshCursor::read_raw_int32() {
  std::int32_t value = 0;
  std::memcpy(&value, take_bytes(4).data(), 4);
  return value;
}

void MshCursor::expect_section_end() {
  const std::string expected = "$End" + section_.substr(std::min<std::size_t>(1, section_.size()));
  at_end();
  const std::size_t start = pos_;
  const std::string_view token = word();
  if (token != expected && pos_ == bytes_.size() && std::string_view(expected).starts_with(token)) fail_eof();
  if (token != expected)
    fail(start, fmt::format("found '{}' (expected {}: the counts of section {} do not match its contents)",
                            printable(token), expected, section_));
  section_.clear();
}

void MshCursor::skip_section() {
  const std::string end = "$End" + section_.substr(std::min<std::size_t>(1, section_.size()));
  const std::size_t found = bytes_.find(end, pos_);
  if (found == std::string_view::npos) {
    pos_ = bytes_.size();
    fail_eof();
  }
  pos_ = found + end.size();
  section_.clear();
}

std::string MshCursor::location(std::size_t at) const {
  at = std::min(at, bytes_.size());
  if (binary_) return fmt::format("{}: byte {}", name_, at);
  const auto line = 1 + std::count(bytes_.begin(), bytes_.begin() + static_cast<std::ptrdiff_t>(at), '\n');
  return fmt::format("{}:{}", name_, line);
}

void MshCursor::fail(std::size_t at, std::string_view what) const {
  throw InputError(fmt::format("{}: {}", location(at), what));
}

void MshCursor::fail_eof() const {
  if (section_.empty()) fail(bytes_.size(), "unexpected end of file (expected a section such as $Nodes)");
  fail(bytes_.size(), fmt::format("unexpected end of file inside section {} (truncated file? expected $End{})",
                                  section_, section_.substr(1)));
}

}  // namespace conserve::mesh::detail
