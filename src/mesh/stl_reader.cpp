// STL files through the Gmsh API. The layouts (an ASCII file of "facet" …
// "vertex x y z" … "endfacet" blocks between "solid" and "endsolid"; a binary
// file of an 80-byte header, a little-endian uint32 triangle count and 50
// bytes per triangle: normal and three corners as float32, two attribute
// bytes) are checked here first, so that a file Gmsh would read as
// something else is refused with its reason; Gmsh then reads the
// triangles and merges their repeated corners.
#include "mesh/stl_reader.hpp"

#include <fmt/format.h>
#include <gmsh.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/error.hpp"
#include "mesh/gmsh_mesher.hpp"
#include "mesh/surface_mesh.hpp"

namespace conserve::mesh {

namespace {

constexpr std::size_t kHeader = 84;    // 80-byte header + uint32 count
constexpr std::size_t kTriangle = 50;  // 12 float32 + 2 attribute bytes

std::string file_bytes(const std::filesystem::path& file) {
  std::error_code ec;
  std::ifstream stream(file, std::ios::binary);
  if (!stream || std::filesystem::is_directory(file, ec))
    throw InputError(fmt::format("{}: cannot open the STL file (expected a readable .stl file)", file.string()));
  std::ostringstream bytes;
  bytes << stream.rdbuf();
  return bytes.str();
}

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

/// The number of "vertex" lines of an ASCII STL, each checked to hold
/// three finite numbers.
std::size_t ascii_vertices(const std::string& bytes, const std::string& name) {
  std::istringstream lines(bytes);
  std::string line, word;
  std::size_t vertices = 0;
  for (int number = 1; std::getline(lines, line); ++number) {
    std::istringstream words(line);
    if (!(words >> word) || lower(word) != "vertex") continue;
    double xyz[3] = {};
    std::string extra;
    words >> xyz[0] >> xyz[1] >> xyz[2];
    if (!words || (words >> extra) || !std::isfinite(xyz[0] + xyz[1] + xyz[2]))
      throw InputError(fmt::format("{}:{}: '{}' (expected 'vertex x y z', three finite numbers)", name, number,
                                   line.substr(line.find_first_not_of(" \t"), 60)));
    ++vertices;
  }
  return vertices;
}

/// Throws unless every corner coordinate of a binary STL is finite.
void check_binary_corners(const std::string& bytes, std::size_t count, const std::string& name) {
  for (std::size_t t = 0; t < count; ++t)
    for (std::size_t k = 3; k < 12; ++k) {
      float value = 0.0F;
      std::memcpy(&value, bytes.data() + kHeader + kTriangle * t + 4 * k, 4);  // little-endian host
      if (!std::isfinite(value))
        throw InputError(fmt::format("{}: triangle {} has a corner that is not a finite number", name, t + 1));
    }
}

/// How many triangles the file holds, from its layout.
std::size_t triangles_in(const std::string& bytes, const std::string& name) {
  std::uint32_t count = 0;
  for (std::size_t i = 0; bytes.size() >= kHeader && i < 4; ++i)
    count |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[80 + i])) << (8 * i);
  const bool binary = bytes.size() >= kHeader && bytes.size() == kHeader + kTriangle * count;
  if (binary && count == 0) throw InputError(fmt::format("{}: the binary STL file holds no triangles", name));
  if (binary) check_binary_corners(bytes, count, name);
  if (binary) return count;
  if (lower(bytes.substr(0, 5)) != "solid")
    throw InputError(fmt::format(
        "{}: not an STL file: {} bytes{} (expected an ASCII STL starting with 'solid' or a binary STL of 84 + 50 × N "
        "bytes for N triangles)",
        name, bytes.size(),
        bytes.size() >= kHeader ? fmt::format(", and its header announces {} triangles", count) : std::string()));
  const std::size_t vertices = ascii_vertices(bytes, name);
  if (vertices == 0 || vertices % 3 != 0)
    throw InputError(
        fmt::format("{}: the ASCII STL file has {} 'vertex' lines (expected 3 per facet, at least one "
                    "facet)",
                    name, vertices));
  return vertices / 3;
}

/// The triangles Gmsh read (corner node tags, 3 per triangle) and the
/// coordinates of every node tag.
struct GmshTriangles {
  std::vector<std::size_t> corners;
  std::unordered_map<std::size_t, Eigen::Vector3d> xyz;
};

GmshTriangles read_with_gmsh(const std::filesystem::path& file) {
  const detail::GmshSession session;
  GmshTriangles out;
  try {
    gmsh::merge(file.string());
    gmsh::model::mesh::removeDuplicateNodes();
    std::vector<int> types;
    std::vector<std::vector<std::size_t>> element_tags, node_tags;
    gmsh::model::mesh::getElements(types, element_tags, node_tags, 2, -1);
    for (std::size_t i = 0; i < types.size(); ++i)
      if (types[i] == 2) out.corners.insert(out.corners.end(), node_tags[i].begin(), node_tags[i].end());
    std::vector<std::size_t> tags;
    std::vector<double> xyz, parametric;
    gmsh::model::mesh::getNodes(tags, xyz, parametric, -1, -1, false, false);
    for (std::size_t n = 0; n < tags.size(); ++n)
      out.xyz[tags[n]] = Eigen::Vector3d(xyz[3 * n], xyz[3 * n + 1], xyz[3 * n + 2]);
  } catch (const std::string& message) {  // what Gmsh 4.8 throws on errors
    throw InputError(fmt::format("{}: Gmsh could not read the STL file: {}", file.string(), message));
  } catch (const std::exception& e) {
    throw InputError(fmt::format("{}: Gmsh could not read the STL file: {}", file.string(), e.what()));
  }
  return out;
}

std::string corner(const Eigen::MatrixXd& points, int node) {
  return fmt::format("({:g}, {:g}, {:g})", points(0, node), points(1, node), points(2, node));
}

void check_triangles(const Mesh& mesh, const std::string& name) {
  const Eigen::MatrixXi& facets = mesh.facet_groups.at("surface").facets;
  if (const auto f = degenerate_facet(mesh.points, facets))
    throw InputError(
        fmt::format("{}: triangle {} is degenerate (corners {}, {}, {}; expected a triangle of positive "
                    "area)",
                    name, *f + 1, corner(mesh.points, facets(0, *f)), corner(mesh.points, facets(1, *f)),
                    corner(mesh.points, facets(2, *f))));
  if (const auto clash = orientation_clash(facets))
    throw InputError(fmt::format(
        "{}: triangles {} and {} (counted from 1 in file order) share the edge from {} to {} in the same direction: "
        "the surface's facets are not consistently oriented (expected each edge of two triangles to run once each "
        "way, so that all normals point to one side)",
        name, clash->first + 1, clash->second + 1, corner(mesh.points, clash->from), corner(mesh.points, clash->to)));
}

}  // namespace

Mesh read_stl(const std::filesystem::path& file) {
  const std::string name = file.string();
  const std::size_t expected = triangles_in(file_bytes(file), name);
  const GmshTriangles read = read_with_gmsh(file);
  if (read.corners.size() != 3 * expected)
    throw InputError(
        fmt::format("{}: Gmsh read {} triangles but the file holds {} (expected an STL file in the "
                    "standard layout: one 'facet', 'outer loop', 'vertex', 'endloop' or 'endfacet' per "
                    "line)",
                    name, read.corners.size() / 3, expected));
  std::unordered_map<std::size_t, int> index;  // node tag → number, in order of first use
  Eigen::MatrixXi facets(3, static_cast<Eigen::Index>(expected));
  std::vector<Eigen::Vector3d> points;
  for (std::size_t k = 0; k < read.corners.size(); ++k) {
    const auto [it, fresh] = index.emplace(read.corners[k], static_cast<int>(points.size()));
    if (fresh) points.push_back(read.xyz.at(read.corners[k]));
    facets(static_cast<Eigen::Index>(k % 3), static_cast<Eigen::Index>(k / 3)) = it->second;
  }
  Eigen::MatrixXd xyz(3, static_cast<Eigen::Index>(points.size()));
  for (std::size_t n = 0; n < points.size(); ++n) xyz.col(static_cast<Eigen::Index>(n)) = points[n];
  Mesh mesh = bare_surface(3, std::move(xyz), std::move(facets));
  check_triangles(mesh, name);
  return mesh;
}

Mesh read_mesh_file(const std::filesystem::path& file, int dim, BareSurface bare) {
  if (lower(file.extension().string()) != ".stl") return read_msh(file, dim, bare);
  if (dim != 3)
    throw InputError(
        fmt::format("{}: an STL file holds a triangle surface, which needs dimension = 3 (expected a "
                    ".msh file of 2-node lines for a rigid line in 2D)",
                    file.string()));
  if (bare == BareSurface::rejected)
    throw InputError(
        fmt::format("{}: an STL file holds a bare surface, which only a rigid body may be (expected a "
                    ".msh file of 4-node tetrahedra)",
                    file.string()));
  return read_stl(file);
}

}  // namespace conserve::mesh
