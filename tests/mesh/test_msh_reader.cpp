// Reading Gmsh MSH 4.1 files: the committed meshes of tests/data/msh (made
// by gmsh from the .geo files there) and small files, hand-written or as
// Gmsh wrote them; volume meshes, linear and quadratic (tet10, tri6), and
// bare surfaces (a rigid body's) in 3D and 2D.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <vector>

#include "core/error.hpp"
#include "mesh/msh_reader.hpp"
#include "mesh/surface_mesh.hpp"
#include "mesh/topology.hpp"
#include "mesh_checks.hpp"
#include "msh_samples.hpp"

namespace conserve::mesh {
namespace {

using test::data_dir;
using test::file_bytes;
using test::replace;
using ::testing::AllOf;
using ::testing::HasSubstr;

/// The message of the InputError that parsing `text` as `name` throws.
std::string error_of(const std::string& text, int dim = 3, const std::string& name = "tiny.msh",
                     BareSurface bare = BareSurface::rejected) {
  try {
    parse_msh(text, name, dim, bare);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError";
  return "";
}

TEST(MshReader, AsciiAndBinaryCubeReadIdentically) {
  const Mesh ascii = read_msh(data_dir() / "cube_ascii.msh", 3);
  const Mesh binary = read_msh(data_dir() / "cube_binary.msh", 3);
  ASSERT_GT(ascii.num_cells(), 10);
  // ASCII files hold 16 significant digits, binary ones the exact doubles
  ASSERT_EQ(ascii.points.cols(), binary.points.cols());
  EXPECT_LT((ascii.points - binary.points).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_EQ(ascii.cells, binary.cells);
  EXPECT_EQ(ascii.cell_groups, binary.cell_groups);
  ASSERT_EQ(ascii.facet_groups.size(), binary.facet_groups.size());
  for (const auto& [name, group] : ascii.facet_groups) EXPECT_EQ(group.facets, binary.facet_groups.at(name).facets);
  EXPECT_NEAR(test::check_mesh_consistency(ascii), 1.0, 1e-12);
}

TEST(MshReader, CubePhysicalGroupsComeThrough) {
  const Mesh mesh = read_msh(data_dir() / "cube_ascii.msh", 3);
  ASSERT_EQ(mesh.cell_groups.size(), 1u);
  EXPECT_EQ(mesh.cell_groups.at("body").size(), static_cast<std::size_t>(mesh.num_cells()));
  ASSERT_EQ(mesh.facet_groups.size(), 2u);
  const Eigen::MatrixXi boundary = boundary_facets(mesh);
  for (const auto& [name, axis, value] : {std::tuple{"xmin", 0, 0.0}, std::tuple{"zmax", 2, 1.0}}) {
    const Eigen::MatrixXi& facets = mesh.facet_groups.at(name).facets;
    int on_face = 0;  // boundary facets on that face of the cube
    for (int f = 0; f < boundary.cols(); ++f)
      on_face += std::abs(mesh.points(axis, boundary(0, f)) - value) +
                     std::abs(mesh.points(axis, boundary(1, f)) - value) +
                     std::abs(mesh.points(axis, boundary(2, f)) - value) <
                 1e-12;
    EXPECT_EQ(facets.cols(), on_face) << name;
    for (int f = 0; f < facets.cols(); ++f)
      for (int i = 0; i < 3; ++i) EXPECT_DOUBLE_EQ(mesh.points(axis, facets(i, f)), value) << name;
    EXPECT_NEAR(test::total_area_normal(mesh, facets).norm(), 1.0, 1e-12) << name;  // unit square face
    test::expect_oriented_subset(facets, boundary);  // outward, whatever the file's order
  }
}

TEST(MshReader, SquareIn2D) {
  const Mesh mesh = read_msh(data_dir() / "square.msh", 2);
  EXPECT_EQ(mesh.dim, 2);
  EXPECT_EQ(mesh.points.rows(), 2);
  EXPECT_EQ(mesh.num_cells(), 14);
  EXPECT_NEAR(test::check_mesh_consistency(mesh), 1.0, 1e-12);
  EXPECT_EQ(mesh.cell_groups.at("plate").size(), 14u);
  ASSERT_EQ(mesh.facet_groups.size(), 2u);
  EXPECT_EQ(mesh.facet_groups.at("bottom").facets.cols(), 2);
  EXPECT_EQ(mesh.facet_groups.at("left").facets.cols(), 2);
  EXPECT_EQ(mesh.facet_groups.at("bottom").facets.rows(), 2);
}

TEST(MshReader, TinyFileKeepsOnlyCellNodesInFileOrder) {
  const Mesh mesh = parse_msh(test::kTinyTet, "tiny.msh", 3);
  ASSERT_EQ(mesh.num_nodes(), 4);  // node 5 (7, 7, 7) is used by no cell
  ASSERT_EQ(mesh.num_cells(), 1);
  EXPECT_EQ(mesh.cells.col(0), Eigen::Vector4i(0, 1, 2, 3));
  EXPECT_EQ(mesh.points.col(3), Eigen::Vector3d(0, 0, 1));
  EXPECT_NEAR(total_volume(mesh), 1.0 / 6.0, 1e-15);
  EXPECT_EQ(mesh.cell_groups.at("solid"), std::vector<int>{0});
  EXPECT_EQ(mesh.facet_groups.at("bottom").facets.col(0), Eigen::Vector3i(0, 2, 1));
}

TEST(MshReader, BoundaryFacetsOfGroupsAreOrientedOutward) {
  const Mesh mesh = parse_msh(replace(test::kTinyTet, "1 1 3 2", "1 1 2 3"), "tiny.msh", 3);  // inward in the file
  EXPECT_EQ(mesh.facet_groups.at("bottom").facets.col(0), Eigen::Vector3i(0, 2, 1));
}

TEST(MshReader, RenumbersNodesInFileOrderNotTagOrder) {
  // tags 1..4 listed as 4, 3, 2, 1: new numbers follow the file
  const std::string text = replace(test::kTinyTet, "1\n2\n3\n4\n5\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n",
                                   "4\n3\n2\n1\n5\n0 0 1\n0 1 0\n1 0 0\n0 0 0\n");
  const Mesh mesh = parse_msh(text, "tiny.msh", 3);
  EXPECT_EQ(mesh.cells.col(0), Eigen::Vector4i(3, 2, 1, 0));
  EXPECT_EQ(mesh.points.col(0), Eigen::Vector3d(0, 0, 1));
}

TEST(MshReader, UnnamedPhysicalGroupIsNamedByItsNumber) {
  const std::string text = replace(test::kTinyTet, "2\n2 1 \"bottom\"\n", "1\n");
  const Mesh mesh = parse_msh(text, "tiny.msh", 3);
  EXPECT_TRUE(mesh.facet_groups.contains("1"));
  EXPECT_TRUE(mesh.cell_groups.contains("solid"));
}

TEST(MshReader, SkipsUnknownSections) {
  const std::string text = std::string(test::kTinyTet) + "$NodeData\n1\n\"u\"\n$EndNodeData\n";
  EXPECT_EQ(parse_msh(text, "tiny.msh", 3).num_cells(), 1);
}

TEST(MshReader, CrLfLineEndings) {
  std::string text;
  for (const char c : std::string(test::kTinyTet)) text += c == '\n' ? std::string("\r\n") : std::string(1, c);
  EXPECT_EQ(parse_msh(text, "tiny.msh", 3).num_cells(), 1);
}

TEST(MshReaderErrors, MissingFile) {
  EXPECT_THAT(([] {
                try {
                  read_msh("/nonexistent/x.msh", 3);
                } catch (const InputError& e) {
                  return std::string(e.what());
                }
                return std::string();
              })(),
              HasSubstr("/nonexistent/x.msh: cannot open"));
}

TEST(MshReaderErrors, MissingMeshFormat) {
  const std::string text = replace(test::kTinyTet, "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n", "");
  EXPECT_THAT(error_of(text), AllOf(HasSubstr("tiny.msh:1:"), HasSubstr("missing $MeshFormat")));
  EXPECT_THAT(error_of(""), HasSubstr("missing $MeshFormat"));
}

TEST(MshReaderErrors, WrongVersionOrFormat) {
  EXPECT_THAT(error_of(replace(test::kTinyTet, "4.1 0 8", "2.2 0 8")),
              AllOf(HasSubstr("tiny.msh:2:"), HasSubstr("unsupported MSH version '2.2'"), HasSubstr("4.1")));
  EXPECT_THAT(error_of(replace(test::kTinyTet, "4.1 0 8", "4.1 0 4")),
              AllOf(HasSubstr("tiny.msh:2:"), HasSubstr("data size 4")));
  EXPECT_THAT(error_of(replace(test::kTinyTet, "4.1 0 8", "4.1 2 8")),
              AllOf(HasSubstr("tiny.msh:2:"), HasSubstr("file type 2")));
}

TEST(MshReaderErrors, UnsupportedElementTypes) {
  const std::string tet20 = replace(test::kTinyTet, "3 1 4 1\n", "3 1 29 1\n");
  EXPECT_THAT(error_of(tet20),
              AllOf(HasSubstr("tiny.msh:32:"), HasSubstr("unsupported element type 29 (20-node tetrahedron)"),
                    HasSubstr("conserve needs 4-node tetrahedra (type 4) or 10-node ones (type 11)")));
  const std::string hex = replace(test::kTinyTet, "3 1 4 1\n2 1 2 3 4\n", "3 1 5 1\n2 1 2 3 4 5 5 5 5\n");
  EXPECT_THAT(error_of(hex),
              AllOf(HasSubstr("tiny.msh:32:"), HasSubstr("unsupported element type 5 (8-node hexahedron)")));
  const std::string unknown = replace(test::kTinyTet, "3 1 4 1\n", "3 1 77 1\n");
  EXPECT_THAT(error_of(unknown), AllOf(HasSubstr("tiny.msh:32:"), HasSubstr("unknown element type 77")));
  // 2D: cubic and incomplete quartic triangles
  for (const auto& [type, name] : {std::pair{"20", "9-node triangle"}, std::pair{"21", "10-node triangle"},
                                   std::pair{"24", "15-node incomplete triangle"}})
    EXPECT_THAT(error_of(replace(test::kTinySquare2D, "2 1 2 2\n", "2 1 " + std::string(type) + " 2\n"), 2),
                AllOf(HasSubstr("tiny.msh:22:"), HasSubstr(fmt::format("unsupported element type {} ({})", type, name)),
                      HasSubstr("conserve needs 3-node triangles (type 2) or 6-node ones (type 9)")));
}

TEST(MshReader, GmshTet10KeepsEveryNodeInGmshOrder) {
  const Mesh mesh = parse_msh(test::kGmshTet10, "tet10.msh", 3);
  EXPECT_EQ(mesh.order(), 2);
  ASSERT_EQ(mesh.num_nodes(), 10);  // the midside nodes too
  ASSERT_EQ(mesh.num_cells(), 1);
  ASSERT_EQ(mesh.cells.rows(), 10);
  // tags 1…10 in file order are nodes 0…9; the element is "1 3 4 2 7 10 8 5 9 6"
  EXPECT_EQ(mesh.cells.col(0), (Eigen::Matrix<int, 10, 1>() << 0, 2, 3, 1, 6, 9, 7, 4, 8, 5).finished());
  const auto x = [&](int slot) { return Eigen::Vector3d(mesh.points.col(mesh.cells(slot, 0))); };
  EXPECT_LT((x(4) - (x(0) + x(1)) / 2).norm(), 1e-9);  // 4 = (0,1)
  EXPECT_LT((x(8) - (x(3) + x(2)) / 2).norm(), 1e-9);  // 8 = (3,2)
  EXPECT_LT((x(9) - (x(3) + x(1)) / 2).norm(), 1e-9);  // 9 = (3,1)
  test::expect_straight_midsides(mesh, mesh.cells, 1e-9);
  EXPECT_NEAR(total_volume(mesh), 1.0 / 6.0, 1e-12);
  EXPECT_EQ(mesh.cell_groups.at("solid"), std::vector<int>{0});
  // The file's bottom "1 2 3 5 6 7" faces +z, into the body: turned outward,
  // its midside nodes with it.
  const Eigen::MatrixXi& bottom = mesh.facet_groups.at("bottom").facets;
  ASSERT_EQ(bottom.rows(), 6);
  EXPECT_EQ(bottom.col(0), (Eigen::Matrix<int, 6, 1>() << 0, 2, 1, 6, 5, 4).finished());
  test::expect_straight_midsides(mesh, bottom, 1e-9);
  EXPECT_LT(test::area_normal(mesh, bottom, 0).z(), 0.0);
  EXPECT_NEAR(test::check_mesh_consistency(mesh), 1.0 / 6.0, 1e-12);
}

TEST(MshReader, GmshSquareOfTri6In2D) {
  const Mesh mesh = parse_msh(test::kGmshSquareTri6, "square6.msh", 2);
  EXPECT_EQ(mesh.order(), 2);
  ASSERT_EQ(mesh.num_nodes(), 13);
  ASSERT_EQ(mesh.cells.rows(), 6);
  ASSERT_EQ(mesh.num_cells(), 4);
  EXPECT_EQ(mesh.cells.col(0), (Eigen::Matrix<int, 6, 1>() << 0, 1, 8, 4, 9, 10).finished());  // "1 2 9 5 10 11"
  test::expect_straight_midsides(mesh, mesh.cells, 1e-9);
  EXPECT_EQ(mesh.cell_groups.at("plate").size(), 4u);
  const Eigen::MatrixXi& left = mesh.facet_groups.at("left").facets;
  ASSERT_EQ(left.rows(), 3);
  EXPECT_EQ(left.col(0), Eigen::Vector3i(3, 0, 7));  // "4 1 8": (0,1) → (0,0), outward already
  test::expect_straight_midsides(mesh, left, 1e-9);
  EXPECT_EQ(boundary_facets(mesh).cols(), 4);
  EXPECT_NEAR(test::check_mesh_consistency(mesh), 1.0, 1e-12);
}

TEST(MshReaderErrors, MixedOrdersAreRefused) {
  const std::string linear_facet = replace(test::kGmshTet10, "2 1 9 1\n1 1 2 3 5 6 7 \n", "2 1 2 1\n1 1 2 3\n");
  EXPECT_THAT(error_of(linear_facet),
              AllOf(HasSubstr("tiny.msh:66: element type 11 (10-node tetrahedron) is quadratic but the block at "
                              "tiny.msh:64 holds type 2 (3-node triangle), which is linear"),
                    HasSubstr("expected one order in a file")));
  const std::string quadratic_facet = replace(test::kTinyTet, "2 1 2 1\n1 1 3 2\n", "2 1 9 1\n1 1 3 2 5 5 5\n");
  EXPECT_THAT(error_of(quadratic_facet),
              HasSubstr("tiny.msh:32: element type 4 (4-node tetrahedron) is linear but the block at tiny.msh:30 "
                        "holds type 9 (6-node triangle), which is quadratic"));
}

TEST(MshReaderErrors, InvertedAndFoldedTet10) {
  EXPECT_THAT(error_of(replace(test::kGmshTet10, "2 1 3 4 2 7 10 8 5 9 6", "2 3 1 4 2 7 10 8 5 9 6")),
              AllOf(HasSubstr("tiny.msh:67:"), HasSubstr("element 2 is inverted")));
  // node 5, the midside node of edge (3,0), pulled to 0.15 of the edge from
  // vertex 0: the vertex simplex is still positive, but det J < 0 there
  EXPECT_THAT(error_of(replace(test::kGmshTet10, "0.4999999999986718 0 0\n", "0.15 0 0\n")),
              AllOf(HasSubstr("tiny.msh:67: element 2 is folded"), HasSubstr("Jacobian determinant"),
                    HasSubstr("-0.4 at a vertex")));
  EXPECT_NO_THROW(parse_msh(replace(test::kGmshTet10, "0.4999999999986718 0 0\n", "0.3 0 0.1\n"), "t.msh", 3));
}

TEST(MshSurfaceErrors, QuadraticBareSurfaceIsRefused) {
  const std::string surface =
      replace(test::kGmshTet10, "2 2 1 2\n2 1 9 1\n1 1 2 3 5 6 7 \n3 1 11 1\n2 1 3 4 2 7 10 8 5 9 6 \n",
              "1 1 1 1\n2 1 9 1\n1 1 2 3 5 6 7\n");
  EXPECT_THAT(error_of(surface, 3, "tiny.msh", BareSurface::accepted),
              HasSubstr("tiny.msh:64: element type 9 (6-node triangle) in a surface mesh: conserve needs 3-node "
                        "triangles"));
  EXPECT_THAT(error_of(surface), HasSubstr("its 1 6-node triangles make a bare surface"));
}

TEST(MshReaderErrors, QuadsIn2DAndTetsIn2D) {
  const std::string quad =
      replace(test::kTinySquare2D, "1 2 1 2\n2 1 2 2\n1 1 2 3\n2 1 3 4\n", "1 1 1 1\n2 1 3 1\n1 1 2 3 4\n");
  EXPECT_THAT(error_of(quad, 2),
              AllOf(HasSubstr("unsupported element type 3 (4-node quadrangle)"), HasSubstr("3-node triangles")));
  EXPECT_THAT(error_of(test::kTinyTet, 2), AllOf(HasSubstr("tiny.msh:32:"), HasSubstr("in a 2D mesh")));
  EXPECT_THAT(error_of(test::kTinySquare2D, 3), AllOf(HasSubstr("tiny.msh: no 4-node tetrahedra")));
}

TEST(MshReaderErrors, MissingNode) {
  EXPECT_THAT(error_of(replace(test::kTinyTet, "2 1 2 3 4", "2 1 2 3 9")),
              AllOf(HasSubstr("tiny.msh:33:"), HasSubstr("element 2 references node 9")));
}

TEST(MshReaderErrors, DuplicateNodeTag) {
  EXPECT_THAT(error_of(replace(test::kTinyTet, "1\n2\n3\n4\n5\n", "1\n2\n3\n4\n3\n")),
              AllOf(HasSubstr("tiny.msh:21:"), HasSubstr("duplicate node tag 3")));
}

TEST(MshReaderErrors, InvertedAndDegenerateTets) {
  EXPECT_THAT(error_of(replace(test::kTinyTet, "2 1 2 3 4", "2 1 3 2 4")),
              AllOf(HasSubstr("tiny.msh:33:"), HasSubstr("element 2 is inverted")));
  EXPECT_THAT(error_of(replace(test::kTinyTet, "0 0 1\n7 7 7", "1 1 0\n7 7 7")),
              AllOf(HasSubstr("tiny.msh:33:"), HasSubstr("element 2 is degenerate")));
}

TEST(MshReaderErrors, InvertedTriangleIn2D) {
  EXPECT_THAT(error_of(replace(test::kTinySquare2D, "1 1 2 3", "1 1 3 2"), 2),
              AllOf(HasSubstr("tiny.msh:"), HasSubstr("element 1 is inverted")));
}

TEST(MshReaderErrors, NonNumericToken) {
  EXPECT_THAT(error_of(replace(test::kTinyTet, "0 1 0\n0 0 1", "0 1 0\n0 0 x1")),
              AllOf(HasSubstr("tiny.msh:25:"), HasSubstr("non-numeric token 'x1'"), HasSubstr("node coordinate")));
  EXPECT_THAT(error_of(replace(test::kTinyTet, "2 1 2 3 4", "2 1 2 3 -4")),
              AllOf(HasSubstr("tiny.msh:33:"), HasSubstr("node tag -4 is negative")));
  EXPECT_THAT(error_of(replace(test::kTinyTet, "2 1 2 3 4", "2 1 2 3 4.5")),
              AllOf(HasSubstr("tiny.msh:33:"), HasSubstr("non-numeric token '4.5'"), HasSubstr("node tag")));
}

TEST(MshReaderErrors, NonPlanar2D) {
  EXPECT_THAT(error_of(replace(test::kTinySquare2D, "1 1 0\n", "1 1 0.5\n"), 2),
              AllOf(HasSubstr("tiny.msh:17:"), HasSubstr("node 3 has z = 0.5")));
}

TEST(MshReaderErrors, FacetOnUnusedNode) {
  EXPECT_THAT(error_of(replace(test::kTinyTet, "1 1 3 2", "1 1 3 5")),
              AllOf(HasSubstr("tiny.msh:31:"), HasSubstr("uses node 5, which belongs to no 3D cell")));
}

TEST(MshReaderErrors, PartitionedMesh) {
  const std::string text =
      replace(test::kTinyTet, "$Nodes\n", "$PartitionedEntities\n1\n0\n$EndPartitionedEntities\n$Nodes\n");
  EXPECT_THAT(error_of(text), AllOf(HasSubstr("tiny.msh:14:"), HasSubstr("partitioned meshes are not supported")));
}

TEST(MshReaderErrors, CountsThatDoNotMatch) {
  EXPECT_THAT(error_of(replace(test::kTinyTet, "1 5 1 5", "1 6 1 5")), HasSubstr("declares 6 nodes"));
  EXPECT_THAT(error_of(replace(test::kTinyTet, "3 1 0 5", "3 1 0 4")), HasSubstr("tiny.msh:"));
  EXPECT_THAT(error_of(replace(test::kTinyTet, "3 1 0 5", "3 1 0 99999999999")),
              AllOf(HasSubstr("tiny.msh:16:"), HasSubstr("does not fit in the 116 bytes left")));
}

TEST(MshReaderErrors, TruncatedAsciiFile) {
  const std::string text = file_bytes(data_dir() / "cube_ascii.msh");
  const std::size_t nodes = text.find("$Nodes"), elements = text.find("$Elements");
  for (const std::size_t cut : {text.size() / 2, nodes + 20, elements + 30, text.size() - 5, text.size() - 100}) {
    const std::string message = error_of(text.substr(0, cut), 3, "cube.msh");
    EXPECT_THAT(message, AllOf(HasSubstr("cube.msh:"), HasSubstr("truncated"))) << cut;
    EXPECT_THAT(message, HasSubstr(cut > elements ? "section $Elements" : "section $Nodes")) << cut;
  }
  for (std::size_t cut = 0; cut < text.size(); cut += 7)
    EXPECT_THAT(error_of(text.substr(0, cut), 3, "cube.msh"), HasSubstr("cube.msh"));
}

TEST(MshReaderErrors, TruncatedBinaryFile) {
  const std::string bytes = file_bytes(data_dir() / "cube_binary.msh");
  for (const std::size_t cut : {bytes.size() / 2, bytes.size() - 20, bytes.size() - 3})
    EXPECT_THAT(error_of(bytes.substr(0, cut), 3, "cube.bin"),
                AllOf(HasSubstr("cube.bin: byte "), HasSubstr("truncated")));
  for (std::size_t cut = 0; cut < bytes.size(); cut += 5)
    EXPECT_THAT(error_of(bytes.substr(0, cut), 3, "cube.bin"), HasSubstr("cube.bin"));
}

TEST(MshReaderErrors, BinaryEndiannessCheck) {
  std::string bytes = file_bytes(data_dir() / "cube_binary.msh");
  const std::size_t one = bytes.find('\n', bytes.find("4.1 1 8")) + 1;
  std::swap(bytes[one], bytes[one + 3]);
  EXPECT_THAT(error_of(bytes, 3, "cube.bin"), AllOf(HasSubstr("cube.bin: byte"), HasSubstr("endianness")));
}

/// Each side (edge in 3D, node in 2D) and how many facets use it.
std::map<std::vector<int>, int> side_uses(const Eigen::MatrixXi& facets) {
  std::map<std::vector<int>, int> uses;
  for (int f = 0; f < facets.cols(); ++f)
    for (int i = 0; i < facets.rows(); ++i) {
      std::vector<int> side{facets(i, f)};
      if (facets.rows() == 3) side.push_back(facets((i + 1) % 3, f));
      std::sort(side.begin(), side.end());
      ++uses[side];
    }
  return uses;
}

TEST(MshSurface, GmshTrayIsOneConnectedSurfaceWithItsGroups) {
  const Mesh mesh = read_msh(data_dir() / "tray.msh", 3, BareSurface::accepted);
  EXPECT_EQ(mesh.num_cells(), 0);
  EXPECT_EQ(mesh.num_nodes(), 25);
  const Eigen::MatrixXi& all = mesh.facet_groups.at("surface").facets;
  ASSERT_EQ(all.cols(), 40);
  EXPECT_EQ(mesh.facet_groups.at("boundary").facets, all);
  EXPECT_EQ(mesh.facet_groups.at("bottom").facets.cols(), 8);
  EXPECT_EQ(mesh.facet_groups.at("walls").facets.cols(), 32);
  int border = 0, shared = 0;  // the rim (4 sides × 2 segments) is the only border
  for (const auto& [side, uses] : side_uses(all)) (uses == 1 ? border : shared) += 1;
  EXPECT_EQ(border, 8);
  EXPECT_EQ(shared, 56);
  EXPECT_FALSE(orientation_clash(all).has_value());
  for (int f = 0; f < all.cols(); ++f) EXPECT_GT(test::area_normal(mesh, all, f).z(), 0.0) << f;  // into the tray
  for (int f = 0, next = 0; f < all.cols(); ++f)  // numbered in the order the facets first use the nodes
    for (int i = 0; i < 3; ++i)
      if (all(i, f) >= next) EXPECT_EQ(all(i, f), next++) << f;
  EXPECT_EQ(mesh.points.rows(), 3);
}

TEST(MshSurface, TinySurfaceNumbersNodesByFirstUse) {
  const Mesh mesh = parse_msh(test::kTinySurface, "tiny.msh", 3, BareSurface::accepted);
  ASSERT_EQ(mesh.num_nodes(), 4);
  EXPECT_EQ(mesh.points.col(0), Eigen::Vector3d(1, 1, 0));  // tag 3
  EXPECT_EQ(mesh.points.col(3), Eigen::Vector3d(1, 0, 0));  // tag 2
  EXPECT_EQ(mesh.facet_groups.at("pad").facets, (Eigen::MatrixXi(3, 2) << 0, 0, 1, 2, 2, 3).finished());
  EXPECT_EQ(mesh.facet_groups.at("surface").facets, mesh.facet_groups.at("pad").facets);
  EXPECT_TRUE(mesh.cell_groups.at("body").empty());
}

TEST(MshSurface, LineMeshIn2D) {
  const Mesh valley = read_msh(data_dir() / "valley.msh", 2, BareSurface::accepted);
  EXPECT_EQ(valley.points.rows(), 2);
  EXPECT_EQ(valley.num_nodes(), 5);
  const Eigen::MatrixXi& all = valley.facet_groups.at("surface").facets;
  ASSERT_EQ(all.rows(), 2);
  EXPECT_EQ(all.cols(), 4);
  EXPECT_EQ(valley.facet_groups.at("floor").facets.cols(), 2);
  EXPECT_EQ(valley.facet_groups.at("slopes").facets.cols(), 2);
  for (int f = 0; f < all.cols(); ++f) EXPECT_GT(test::area_normal(valley, all, f).y(), 0.0) << f;  // up
  const Mesh tiny = parse_msh(test::kTinyLine2D, "tiny.msh", 2, BareSurface::accepted);
  EXPECT_EQ(tiny.facet_groups.at("surface").facets, (Eigen::MatrixXi(2, 2) << 0, 1, 1, 2).finished());
}

TEST(MshSurface, AFileWithCellsIsReadAsBefore) {
  const Mesh with_cells = parse_msh(test::kTinyTet, "tiny.msh", 3, BareSurface::accepted);
  EXPECT_EQ(with_cells.num_cells(), 1);
  EXPECT_EQ(with_cells.num_nodes(), 4);
  EXPECT_EQ(with_cells.facet_groups.at("bottom").facets.col(0), Eigen::Vector3i(0, 2, 1));
  EXPECT_FALSE(with_cells.facet_groups.contains("surface"));
}

TEST(MshSurfaceErrors, RejectedUnlessTheCallerAcceptsBareSurfaces) {
  EXPECT_THAT(error_of(test::kTinySurface),
              AllOf(HasSubstr("tiny.msh: no 4-node tetrahedra (element type 4) in the file (expected a 3D mesh"),
                    HasSubstr("its 2 3-node triangles make a bare surface, which only a rigid body may be")));
  EXPECT_THAT(error_of(test::kTinyLine2D, 2),
              AllOf(HasSubstr("no 3-node triangles (element type 2)"), HasSubstr("its 2 2-node lines")));
}

TEST(MshSurfaceErrors, InconsistentOrientationNamesTheElementsAndTheShared) {
  const auto accepted = BareSurface::accepted;
  EXPECT_THAT(error_of(replace(test::kTinySurface, "2 3 1 2", "2 1 3 2"), 3, "tiny.msh", accepted),
              AllOf(HasSubstr("tiny.msh:28: elements 1 and 2 share the edge from node 1 to node 3 in the same "
                              "direction: the surface's facets are not consistently oriented")));
  EXPECT_THAT(
      error_of(replace(test::kTinyLine2D, "2 2 3", "2 3 2"), 2, "tiny.msh", accepted),
      AllOf(HasSubstr("tiny.msh:22: elements 1 and 2 both end at node 2"), HasSubstr("not consistently oriented")));
  EXPECT_THAT(error_of(replace(test::kTinyLine2D, "\n1 1 2\n", "\n1 2 1\n"), 2, "tiny.msh", accepted),
              HasSubstr("tiny.msh:22: elements 1 and 2 both start at node 2"));
}

TEST(MshSurfaceErrors, DegenerateAndNonSimplexFacets) {
  const auto accepted = BareSurface::accepted;
  EXPECT_THAT(error_of(replace(test::kTinySurface, "2 3 1 2", "2 3 1 1"), 3, "tiny.msh", accepted),
              HasSubstr("tiny.msh:28: element 2 is degenerate"));
  EXPECT_THAT(error_of(replace(test::kTinySurface, "0 1 0\n$EndNodes", "2 2 0\n$EndNodes"), 3, "tiny.msh", accepted),
              HasSubstr("tiny.msh:27: element 1 is degenerate"));  // (1,1), (2,2), (0,0) aligned
  const std::string quads =
      replace(test::kTinySurface, "1 2 1 2\n2 1 2 2\n1 3 4 1\n2 3 1 2\n", "1 1 1 1\n2 1 3 1\n1 1 2 3 4\n");
  EXPECT_THAT(error_of(quads, 3, "tiny.msh", accepted),
              AllOf(HasSubstr("tiny.msh:26: element type 3 (4-node quadrangle) in a surface mesh"),
                    HasSubstr("conserve needs 3-node triangles")));
  EXPECT_THAT(error_of(replace(test::kTinyLine2D, "-1 0 0\n", "-1 0 0.5\n"), 2, "tiny.msh", accepted),
              HasSubstr("tiny.msh:16: node 3 has z = 0.5"));
}

}  // namespace
}  // namespace conserve::mesh
