#pragma once
/// Raw values to a byte buffer and back: the checkpoints and the contact
/// methods' saved state (contact/method.hpp) share this one format.
#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

#include "core/error.hpp"

namespace conserve {

/// Appends raw values to a byte buffer.
class ByteWriter {
 public:
  template <class T>
  void value(const T& v) {
    buffer_.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  void text(const std::string& s) {
    value(static_cast<std::uint64_t>(s.size()));
    buffer_.append(s);
  }
  void doubles(const double* data, std::size_t count) {
    value(static_cast<std::uint64_t>(count));
    if (count > 0) buffer_.append(reinterpret_cast<const char*>(data), count * sizeof(double));
  }
  [[nodiscard]] const std::string& bytes() const { return buffer_; }

 private:
  std::string buffer_;
};

/// Reads raw values back; throws InputError "WHERE: bad checkpoint: …"
/// (`where` names the file) when short or malformed.
class ByteReader {
 public:
  ByteReader(std::string bytes, std::string where) : bytes_(std::move(bytes)), where_(std::move(where)) {}
  template <class T>
  T value() {
    T v{};
    take(&v, sizeof v);
    return v;
  }
  void doubles(double* data, std::size_t count, std::string_view what) {
    const auto stored = value<std::uint64_t>();
    if (stored != count)
      fail(fmt::format("{} has {} values, this run has {} (not a checkpoint of this scenario)", what, stored, count));
    take(data, count * sizeof(double));
  }
  /// A string of at most `most` bytes; printable (no control characters)
  /// unless `binary`.
  std::string text(std::size_t most, bool binary = false) {
    const auto size = value<std::uint64_t>();
    if (size > most) fail("an entry is too long");
    std::string s(size, '\0');
    take(s.data(), size);
    if (!binary &&
        std::any_of(s.begin(), s.end(), [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; }))
      fail("a fingerprint entry holds a control character");
    return s;
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(fmt::format("{}: bad checkpoint: {}", where_, what));
  }
  [[nodiscard]] bool at_end() const { return at_ == bytes_.size(); }
  [[nodiscard]] const std::string& where() const { return where_; }

 private:
  void take(void* data, std::size_t size) {
    if (bytes_.size() - at_ < size) fail("the file is truncated");
    if (size == 0) return;  // data may be an empty vector's null pointer, which memcpy may not take
    std::memcpy(data, bytes_.data() + at_, size);
    at_ += size;
  }
  std::string bytes_;
  std::string where_;
  std::size_t at_ = 0;
};

}  // namespace conserve
