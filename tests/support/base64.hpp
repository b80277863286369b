#pragma once
/// Decoding the base64 payloads of our VTU files in tests.
#include <cstdint>
#include <string>
#include <vector>

namespace conserve::test {

/// Bytes of a base64 text (padding ends it; other characters are skipped).
inline std::vector<unsigned char> base64_decode(const std::string& text) {
  const std::string alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::vector<unsigned char> bytes;
  std::uint32_t bits = 0;
  int count = 0;
  for (char c : text) {
    if (c == '=') break;
    const auto value = alphabet.find(c);
    if (value == std::string::npos) continue;
    bits = (bits << 6) | static_cast<std::uint32_t>(value);
    if ((count += 6) >= 8) bytes.push_back(static_cast<unsigned char>(bits >> (count -= 8)));
  }
  return bytes;
}

}  // namespace conserve::test
