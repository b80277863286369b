#pragma once
/// SHA-256 digests of inputs, so that a run's output names exactly what it
/// was made from (summary.json's `inputs`). OpenSSL's EVP API computes them.
#include <filesystem>
#include <string>
#include <string_view>

namespace conserve::io {

/// SHA-256 of `bytes`, 64 lowercase hex digits.
std::string sha256_hex(std::string_view bytes);

/// SHA-256 of the file's bytes, 64 lowercase hex digits. Throws InputError
/// naming the file if it cannot be read.
std::string file_sha256(const std::filesystem::path& file);

}  // namespace conserve::io
