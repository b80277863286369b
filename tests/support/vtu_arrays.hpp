#pragma once
/// Reading the arrays of our VTU files back in tests: appended raw data,
/// plain or in zlib blocks (VTK's layout, UInt64 headers), decoded here
/// independently of io/vtu_writer.cpp.
#include <gtest/gtest.h>
#include <zlib.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace conserve::test {

/// The value of attribute `name` in the XML tag that contains position `at`.
inline std::string tag_attribute(const std::string& xml, std::size_t at, const std::string& name) {
  const auto open = xml.rfind('<', at), close = xml.find('>', at);
  const auto key = xml.find(" " + name + "=\"", open);
  if (key == std::string::npos || key > close) return {};
  const auto begin = key + name.size() + 3;
  return xml.substr(begin, xml.find('"', begin) - begin);
}

/// The bytes of the appended array at `offset` (after the '_' that starts
/// the appended data), decompressed if the file names a compressor.
inline std::vector<unsigned char> appended_bytes(const std::string& xml, std::size_t offset) {
  const auto data = xml.find('_', xml.find("<AppendedData encoding=\"raw\">")) + 1;
  const bool compressed = xml.find("compressor=\"vtkZLibDataCompressor\"") < xml.find("<UnstructuredGrid");
  auto word = [&](std::size_t k) {
    std::uint64_t w = 0;
    std::memcpy(&w, xml.data() + data + offset + 8 * k, 8);
    return static_cast<std::size_t>(w);
  };
  if (!compressed) {
    const auto* begin = reinterpret_cast<const unsigned char*>(xml.data() + data + offset + 8);
    return {begin, begin + word(0)};
  }
  const std::size_t blocks = word(0), block = word(1), last = word(2);
  std::vector<unsigned char> out;
  std::size_t at = data + offset + 8 * (3 + blocks);
  for (std::size_t b = 0; b < blocks; ++b) {
    const std::size_t size = b + 1 == blocks && last > 0 ? last : block;
    std::vector<unsigned char> part(size);
    uLongf written = size;
    EXPECT_EQ(uncompress(part.data(), &written, reinterpret_cast<const Bytef*>(xml.data() + at), word(3 + b)), Z_OK);
    EXPECT_EQ(written, size);
    out.insert(out.end(), part.begin(), part.end());
    at += word(3 + b);
  }
  return out;
}

/// The values of the first DataArray after `anchor` (an attribute such as
/// `Name="u"`, or a tag such as `<Points>` that precedes it), whose VTK
/// type must have T's size.
template <typename T>
std::vector<T> vtu_array(const std::string& xml, const std::string& anchor) {
  const auto at = xml.find(anchor);
  EXPECT_NE(at, std::string::npos) << anchor;
  if (at == std::string::npos) return {};
  const auto tag = anchor.front() == '<' ? xml.find("<DataArray", at) + 1 : at;
  EXPECT_EQ(tag_attribute(xml, tag, "format"), "appended") << anchor;
  const std::string type = tag_attribute(xml, tag, "type");
  const std::size_t size = type == "Float64" || type == "Int64" ? 8 : type == "Float32" ? 4 : type == "UInt8" ? 1 : 0;
  EXPECT_EQ(size, sizeof(T)) << anchor << " is " << type;
  if (size != sizeof(T)) return {};
  const auto bytes = appended_bytes(xml, std::stoull(tag_attribute(xml, tag, "offset")));
  EXPECT_EQ(bytes.size() % sizeof(T), 0u) << anchor;
  std::vector<T> values(bytes.size() / sizeof(T));
  if (!values.empty()) std::memcpy(values.data(), bytes.data(), values.size() * sizeof(T));
  return values;
}

}  // namespace conserve::test
