#pragma once
/// Private to io: whole-file writes that never leave a half-written file.
#include <filesystem>
#include <string>
#include <string_view>

namespace conserve::io::detail {

/// Writes `content` to "<file>.tmp" and renames it onto `file`, so that a
/// reader sees either the old or the new file. Throws Error on failure
/// (and removes the temporary file).
void write_atomically(const std::filesystem::path& file, std::string_view content);

/// `text` with &, <, >, " and ' replaced by XML entities.
std::string xml_escape(std::string_view text);

}  // namespace conserve::io::detail
