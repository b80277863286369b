// Reading Gmsh MSH 4.1 files: the committed meshes of tests/data/msh (made
// by gmsh from the .geo files there) and small hand-written files.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "core/error.hpp"
#include "mesh/msh_reader.hpp"
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
std::string error_of(const std::string& text, int dim = 3, const std::string& name = "tiny.msh") {
  try {
    parse_msh(text, name, dim);
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
  const std::string tet10 = replace(test::kTinyTet, "3 1 4 1\n2 1 2 3 4\n", "3 1 11 1\n2 1 2 3 4 5 5 5 5 5 5\n");
  EXPECT_THAT(error_of(tet10),
              AllOf(HasSubstr("tiny.msh:32:"), HasSubstr("unsupported element type 11 (10-node tetrahedron)"),
                    HasSubstr("conserve needs 4-node tetrahedra")));
  const std::string hex = replace(test::kTinyTet, "3 1 4 1\n2 1 2 3 4\n", "3 1 5 1\n2 1 2 3 4 5 5 5 5\n");
  EXPECT_THAT(error_of(hex),
              AllOf(HasSubstr("tiny.msh:32:"), HasSubstr("unsupported element type 5 (8-node hexahedron)")));
  const std::string unknown = replace(test::kTinyTet, "3 1 4 1\n", "3 1 77 1\n");
  EXPECT_THAT(error_of(unknown), AllOf(HasSubstr("tiny.msh:32:"), HasSubstr("unknown element type 77")));
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

}  // namespace
}  // namespace conserve::mesh
