// Reading STL files through Gmsh: the committed tray (tests/data/msh) saved
// as STL by Gmsh reads like its .msh; repeated corners are merged; bad
// files, degenerate and inconsistently oriented triangles are refused with
// one line naming the file.
#include <gmock/gmock.h>
#include <gmsh.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "mesh/gmsh_mesher.hpp"
#include "mesh/stl_reader.hpp"
#include "mesh/surface_mesh.hpp"
#include "mesh_checks.hpp"
#include "support/stl_files.hpp"

namespace conserve::mesh {
namespace {

using test::all_facets;

namespace fs = std::filesystem;
using ::testing::AllOf;
using ::testing::HasSubstr;
using Triangle = conserve::test::StlTriangle;
using conserve::test::ascii_stl;
using conserve::test::binary_stl;

fs::path scratch_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("conserve_test_stl_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

void write_bytes(const fs::path& file, const std::string& bytes) { std::ofstream(file, std::ios::binary) << bytes; }

/// `msh` saved by Gmsh as the STL file `stl` (ASCII: 16 significant digits;
/// binary: float32).
void gmsh_to_stl(const fs::path& msh, const fs::path& stl, bool binary) {
  const detail::GmshSession session;
  gmsh::merge(msh.string());
  gmsh::option::setNumber("Mesh.Binary", binary ? 1 : 0);
  gmsh::write(stl.string());
}

/// The unit square z = 0 as two triangles (six corners), normals +z.
const std::vector<Triangle> kSquare = {Triangle{{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}}},
                                       Triangle{{{0, 0, 0}, {1, 1, 0}, {0, 1, 0}}}};

std::string error_of(const fs::path& file, int dim = 3, BareSurface bare = BareSurface::accepted) {
  try {
    read_mesh_file(file, dim, bare);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError for " << file;
  return "";
}

TEST(StlReader, GmshAsciiStlReadsExactlyLikeItsMsh) {
  const fs::path dir = scratch_dir("ascii");
  gmsh_to_stl(test::data_dir() / "tray.msh", dir / "tray.stl", false);
  const Mesh msh = read_msh(test::data_dir() / "tray.msh", 3, BareSurface::accepted);
  const Mesh stl = read_mesh_file(dir / "tray.stl", 3, BareSurface::accepted);
  EXPECT_EQ(stl.num_cells(), 0);
  ASSERT_EQ(stl.num_nodes(), msh.num_nodes());  // 120 corners merged into the 25 nodes
  EXPECT_EQ(all_facets(stl), all_facets(msh));
  EXPECT_EQ(stl.facet_groups.at("boundary").facets, all_facets(msh));
  const double difference = (stl.points - msh.points).cwiseAbs().maxCoeff();
  std::printf("[ measured ] tray: Gmsh's ASCII STL vs its .msh: %d nodes, %d triangles, max |Δx| = %.1e m\n",
              stl.num_nodes(), static_cast<int>(all_facets(stl).cols()), difference);
  EXPECT_EQ(difference, 0.0);
}

TEST(StlReader, GmshBinaryStlReadsLikeItsMshToSinglePrecision) {
  const fs::path dir = scratch_dir("binary");
  gmsh_to_stl(test::data_dir() / "tray.msh", dir / "tray.stl", true);
  EXPECT_EQ(fs::file_size(dir / "tray.stl"), 84u + 50u * 40u);
  const Mesh msh = read_msh(test::data_dir() / "tray.msh", 3, BareSurface::accepted);
  const Mesh stl = read_stl(dir / "tray.stl");
  ASSERT_EQ(stl.num_nodes(), msh.num_nodes());
  EXPECT_EQ(all_facets(stl), all_facets(msh));
  const double difference = (stl.points - msh.points).cwiseAbs().maxCoeff();
  std::printf("[ measured ] tray: Gmsh's binary STL vs its .msh: max |Δx| = %.1e m (float32)\n", difference);
  EXPECT_LE(difference, 0.75 * std::numeric_limits<float>::epsilon());
}

TEST(StlReader, RepeatedCornersAreMergedSoNeighboursShareNodes) {
  const fs::path dir = scratch_dir("merge");
  std::vector<Triangle> triangles = kSquare;
  triangles[1][0] = {1e-9, 0, 0};  // (0, 0, 0) within Geometry.Tolerance × the diagonal
  triangles.push_back(Triangle{{{1, 0, 0}, {2, 0, 0}, {1, 1, 0}}});
  write_bytes(dir / "square.stl", binary_stl(triangles));
  const Mesh mesh = read_stl(dir / "square.stl");
  EXPECT_EQ(mesh.num_nodes(), 5);
  EXPECT_EQ(mesh.points.col(0), Eigen::Vector3d::Zero());  // the first corner met is kept
  EXPECT_EQ(all_facets(mesh), (Eigen::MatrixXi(3, 3) << 0, 0, 1, 1, 2, 4, 2, 3, 2).finished());
  const SurfaceSummary s = summarize_surface(mesh.points, all_facets(mesh));
  EXPECT_EQ(s.pieces, 1);
  EXPECT_NEAR(s.mean_normal.z(), 1.0, 1e-15);
  // several solids in one ASCII file: their triangles in file order, shared corners merged
  std::string two = ascii_stl({kSquare[0]});
  two += ascii_stl({kSquare[1]});
  write_bytes(dir / "two.stl", two);
  const Mesh joined = read_stl(dir / "two.stl");
  EXPECT_EQ(joined.num_nodes(), 4);
  EXPECT_EQ(all_facets(joined), (Eigen::MatrixXi(3, 2) << 0, 0, 1, 2, 2, 3).finished());
}

TEST(StlReader, ExtensionInAnyCase) {
  const fs::path dir = scratch_dir("case");
  write_bytes(dir / "SQUARE.STL", ascii_stl(kSquare));
  EXPECT_EQ(read_mesh_file(dir / "SQUARE.STL", 3, BareSurface::accepted).num_nodes(), 4);
}

TEST(StlReaderErrors, InconsistentNormalsNameTheTrianglesAndTheEdge) {
  const fs::path dir = scratch_dir("clash");
  std::vector<Triangle> triangles = kSquare;
  std::swap(triangles[1][1], triangles[1][2]);
  write_bytes(dir / "bad.stl", ascii_stl(triangles));
  EXPECT_THAT(error_of(dir / "bad.stl"), AllOf(HasSubstr((dir / "bad.stl").string() +
                                                         ": triangles 1 and 2 (counted from 1 in file order) share "
                                                         "the edge from (1, 1, 0) to (0, 0, 0) in the same direction"),
                                               HasSubstr("the surface's facets are not consistently oriented")));
  write_bytes(dir / "bad_binary.stl", binary_stl(triangles));
  EXPECT_THAT(error_of(dir / "bad_binary.stl"), HasSubstr("bad_binary.stl: triangles 1 and 2"));
}

TEST(StlReaderErrors, DegenerateOrNotFiniteTriangles) {
  const fs::path dir = scratch_dir("degenerate");
  std::vector<Triangle> triangles = kSquare;
  triangles[1][2] = {2, 2, 0};  // on the line through (0, 0, 0) and (1, 1, 0)
  write_bytes(dir / "flat.stl", binary_stl(triangles));
  EXPECT_THAT(error_of(dir / "flat.stl"),
              HasSubstr("flat.stl: triangle 2 is degenerate (corners (0, 0, 0), (1, 1, 0), (2, 2, 0)"));
  triangles = kSquare;
  triangles[1][2] = {0, std::numeric_limits<double>::infinity(), 0};
  write_bytes(dir / "inf.stl", binary_stl(triangles));
  EXPECT_THAT(error_of(dir / "inf.stl"), HasSubstr("inf.stl: triangle 2 has a corner that is not a finite number"));
  std::string ascii = ascii_stl(kSquare);
  ascii.replace(ascii.find("vertex 1 0 0"), 12, "vertex 1 nan 0");
  write_bytes(dir / "nan.stl", ascii);
  EXPECT_THAT(error_of(dir / "nan.stl"),
              HasSubstr("nan.stl:5: 'vertex 1 nan 0' (expected 'vertex x y z', three finite numbers)"));
}

TEST(StlReaderErrors, NotAnStlFile) {
  const fs::path dir = scratch_dir("not_stl");
  write_bytes(dir / "text.stl", "hello, this is not a mesh\n");
  EXPECT_THAT(error_of(dir / "text.stl"),
              AllOf(HasSubstr("text.stl: not an STL file: 26 bytes"), HasSubstr("expected an ASCII STL")));
  const std::string binary = binary_stl(kSquare);
  write_bytes(dir / "cut.stl", binary.substr(0, binary.size() - 7));
  EXPECT_THAT(error_of(dir / "cut.stl"),
              HasSubstr("cut.stl: not an STL file: 177 bytes, and its header announces 2 triangles"));
  write_bytes(dir / "empty.stl", binary_stl({}));
  EXPECT_THAT(error_of(dir / "empty.stl"), HasSubstr("empty.stl: the binary STL file holds no triangles"));
  std::string ascii = ascii_stl(kSquare);
  ascii.erase(ascii.rfind("    vertex"), ascii.find('\n', ascii.rfind("    vertex")) - ascii.rfind("    vertex") + 1);
  write_bytes(dir / "five.stl", ascii);
  EXPECT_THAT(error_of(dir / "five.stl"), HasSubstr("five.stl: the ASCII STL file has 5 'vertex' lines"));
  std::string loose = ascii_stl(kSquare);  // no "outer loop" lines: Gmsh reads the blocks askew
  for (auto at = loose.find("  outer loop\n"); at != std::string::npos; at = loose.find("  outer loop\n"))
    loose.erase(at, 13);
  write_bytes(dir / "loose.stl", loose);
  EXPECT_THAT(error_of(dir / "loose.stl"), HasSubstr("loose.stl: Gmsh read 1 triangles but the file holds 2"));
  EXPECT_THAT(error_of(dir / "missing.stl"), HasSubstr("missing.stl: cannot open the STL file"));
}

TEST(StlReaderErrors, OnlyIn3DAndOnlyForABareSurface) {
  const fs::path dir = scratch_dir("dims");
  write_bytes(dir / "square.stl", ascii_stl(kSquare));
  EXPECT_THAT(error_of(dir / "square.stl", 2),
              HasSubstr("square.stl: an STL file holds a triangle surface, which needs dimension = 3"));
  EXPECT_THAT(error_of(dir / "square.stl", 3, BareSurface::rejected),
              HasSubstr("square.stl: an STL file holds a bare surface, which only a rigid body may be"));
}

}  // namespace
}  // namespace conserve::mesh
