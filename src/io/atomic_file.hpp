#pragma once
/// Whole-file writes that never leave a half-written file (every output
/// file but the CSV histories, which are appended to), and XML escaping.
#include <filesystem>
#include <string>
#include <string_view>

namespace conserve::io {

/// Writes `content` to "<file>.tmp" and renames it onto `file`, so that a
/// reader sees either the old or the new file. Throws Error on failure
/// (and removes the temporary file).
void write_atomically(const std::filesystem::path& file, std::string_view content);

namespace detail {

/// `text` with &, <, >, " and ' replaced by XML entities.
std::string xml_escape(std::string_view text);

}  // namespace detail
}  // namespace conserve::io
