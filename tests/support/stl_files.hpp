#pragma once
/// STL files written by the tests themselves (not by Gmsh), from a list of
/// triangles: the binary layout (80-byte header, little-endian uint32
/// count, 50 bytes a triangle: normal and three corners as float32, two
/// attribute bytes) and the ASCII one.
#include <array>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace conserve::test {

/// Three corners, counter-clockwise seen from the side the normal points to.
using StlTriangle = std::array<std::array<double, 3>, 3>;

/// Binary STL; corners rounded to float32, the normals left zero (readers
/// take the orientation from the corners' order).
inline std::string binary_stl(const std::vector<StlTriangle>& triangles) {
  std::string bytes(80, ' ');
  const auto count = static_cast<std::uint32_t>(triangles.size());
  for (int i = 0; i < 4; ++i) bytes += static_cast<char>((count >> (8 * i)) & 0xffU);
  for (const StlTriangle& t : triangles) {
    float values[12] = {};
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k) values[3 + 3 * c + k] = static_cast<float>(t[c][k]);
    char data[50] = {};
    std::memcpy(data, values, sizeof(values));  // a little-endian host, as the format
    bytes.append(data, sizeof(data));
  }
  return bytes;
}

/// ASCII STL with 17 significant digits (the doubles exactly).
inline std::string ascii_stl(const std::vector<StlTriangle>& triangles) {
  std::string text = "solid test\n";
  char line[128];
  for (const StlTriangle& t : triangles) {
    text += "facet normal 0 0 0\n  outer loop\n";
    for (const auto& c : t) {
      std::snprintf(line, sizeof(line), "    vertex %.17g %.17g %.17g\n", c[0], c[1], c[2]);
      text += line;
    }
    text += "  endloop\nendfacet\n";
  }
  return text + "endsolid test\n";
}

}  // namespace conserve::test
