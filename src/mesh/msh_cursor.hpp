#pragma once
/// Internal to the msh reader: a read position in the bytes of a Gmsh .msh
/// file that reads ASCII tokens or binary values (the same calls serve both
/// modes) and words its errors as "FILE:LINE: ..." (ASCII) or
/// "FILE: byte OFFSET: ..." (binary). Never reads past the end of the bytes.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace conserve::mesh::detail {

class MshCursor {
 public:
  MshCursor(std::string_view bytes, std::string name);

  /// Binary mode: values are read as binary and messages give byte offsets.
  void set_binary(bool binary) { binary_ = binary; }
  /// Reads values as ASCII tokens even in a binary file ($PhysicalNames).
  void set_text_values(bool text) { text_ = text; }
  [[nodiscard]] bool binary() const { return binary_; }
  [[nodiscard]] bool binary_values() const { return binary_ && !text_; }
  /// Section being read ("$Nodes"), for "unexpected end of file" messages;
  /// empty between sections.
  void set_section(std::string_view section) { section_ = section; }
  [[nodiscard]] std::size_t offset() const { return pos_; }
  [[nodiscard]] std::size_t remaining() const { return bytes_.size() - pos_; }

  /// Skips white space; true when nothing is left.
  bool at_end();
  /// The next white-space delimited token; fails at the end of the file.
  std::string_view word();
  /// Consumes the rest of the current line, including its '\n'.
  void skip_line();
  /// A double-quoted string on the current line (physical names).
  std::string quoted();

  /// A value of the file's mode: an ASCII token, or a little-endian binary
  /// int (4 bytes), size_t (8 bytes) or double (8 bytes). `what` names the
  /// value in messages ("node tag").
  int read_int(std::string_view what);
  std::uint64_t read_size(std::string_view what);
  double read_double(std::string_view what);
  /// read_size() for a number of items that each take at least `tokens`
  /// ASCII tokens or `bytes` binary bytes; fails if they cannot fit in the
  /// rest of the file (so that no count can make us allocate absurdly).
  std::uint64_t read_count(std::string_view what, std::size_t tokens, std::size_t bytes);
  /// Skips white space before an ASCII value; the offset where the next
  /// value starts.
  std::size_t value_start();
  /// 4 raw bytes in host order (the endianness check of binary files).
  std::int32_t read_raw_int32();

  /// Reads the token "$End<section>" that must close the current section.
  void expect_section_end();
  /// Moves past "$End<section>" (for sections that are not read).
  void skip_section();

  /// Throws InputError "LOCATION: what".
  [[noreturn]] void fail(std::size_t at, std::string_view what) const;
  /// Throws InputError "LOCATION: unexpected end of file inside section X".
  [[noreturn]] void fail_eof() const;
  /// "FILE:LINE" for ASCII files, "FILE: byte OFFSET" for binary ones.
  [[nodiscard]] std::string location(std::size_t at) const;

 private:
  std::string_view take_bytes(std::size_t n);
  std::string_view number_token(std::string_view what);

  std::string_view bytes_;
  std::string name_;
  std::string section_;
  std::size_t pos_ = 0;
  bool binary_ = false;
  bool text_ = false;
};

/// A token shown in a message: at most 24 characters, non-printable bytes
/// escaped.
std::string printable(std::string_view token);

}  // namespace conserve::mesh::detail
