/// libFuzzer target: the Gmsh .msh 4.1 reader on arbitrary bytes. The only
/// acceptable failure is conserve::InputError; anything else (another
/// exception, a crash, a sanitizer report) is a finding.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/error.hpp"
#include "mesh/msh_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  // The first byte picks the expected dimension and whether a file without
  // cells may be a bare surface (a rigid body's); the rest is the file.
  const int dim = (data[0] & 1) ? 3 : 2;
  const auto bare = (data[0] & 2) ? conserve::mesh::BareSurface::accepted : conserve::mesh::BareSurface::rejected;
  const std::string_view bytes(reinterpret_cast<const char*>(data + 1), size - 1);
  try {
    const conserve::mesh::Mesh mesh = conserve::mesh::parse_msh(bytes, "fuzz.msh", dim, bare);
    (void)mesh;
  } catch (const conserve::InputError&) {
  }
  return 0;
}
