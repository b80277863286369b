/// VTU/PVD output, decoded back from the appended data (raw and zlib) and
/// compared bit for bit; linear and quadratic cells.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <random>

#include "core/error.hpp"
#include "io/vtu_writer.hpp"
#include "support/vtu_arrays.hpp"
#include "support/files.hpp"

namespace conserve::io {
namespace {

namespace fs = std::filesystem;

using test::vtu_array;

/// Bitwise equality of doubles (distinguishes -0.0, compares NaN payloads).
void expect_same_bits(const std::vector<double>& actual, const std::vector<double>& expected) {
  ASSERT_EQ(actual.size(), expected.size());
  EXPECT_EQ(std::memcmp(actual.data(), expected.data(), actual.size() * sizeof(double)), 0);
}

VtuGrid two_tetrahedra() {
  VtuGrid grid;
  std::mt19937_64 random(42);
  std::uniform_real_distribution<double> uniform(-1e3, 1e3);
  grid.points = Eigen::MatrixXd::NullaryExpr(3, 5, [&] { return uniform(random); });
  grid.points(0, 0) = -0.0;
  grid.points(1, 0) = 1.0 / 3.0;
  grid.cells.resize(4, 2);
  grid.cells << 0, 1, 1, 2, 2, 3, 3, 4;
  grid.point_data.push_back({"u", 3, {}});
  for (int i = 0; i < 15; ++i) grid.point_data[0].values.push_back(uniform(random) * 1e-300);
  grid.cell_data.push_back({"energy density", 1, {1.5e300, -2.25}});
  return grid;
}

TEST(VtuWriter, TetrahedraDecodeBitForBit) {
  for (const bool compress : {true, false}) {
    const auto file = test::scratch("vtu_tets") / "grid.vtu";
    const auto grid = two_tetrahedra();
    write_vtu(file, grid, {.compress = compress});
    const auto xml = test::slurp(file);
    EXPECT_NE(xml.find("type=\"UnstructuredGrid\""), std::string::npos);
    EXPECT_NE(xml.find("header_type=\"UInt64\""), std::string::npos);
    EXPECT_EQ(xml.find("compressor=\"vtkZLibDataCompressor\"") != std::string::npos, compress);
    EXPECT_NE(xml.find("NumberOfPoints=\"5\" NumberOfCells=\"2\""), std::string::npos);
    expect_same_bits(vtu_array<double>(xml, "<Points>"),
                     std::vector<double>(grid.points.data(), grid.points.data() + grid.points.size()));
    EXPECT_EQ(vtu_array<std::int64_t>(xml, "Name=\"connectivity\""),
              (std::vector<std::int64_t>{0, 1, 2, 3, 1, 2, 3, 4}));
    EXPECT_EQ(vtu_array<std::int64_t>(xml, "Name=\"offsets\""), (std::vector<std::int64_t>{4, 8}));
    EXPECT_EQ(vtu_array<std::uint8_t>(xml, "Name=\"types\""), (std::vector<std::uint8_t>{10, 10}));
    expect_same_bits(vtu_array<double>(xml, "Name=\"u\""), grid.point_data[0].values);
    expect_same_bits(vtu_array<double>(xml, "Name=\"energy density\""), grid.cell_data[0].values);
    EXPECT_NE(xml.find("Name=\"u\" NumberOfComponents=\"3\""), std::string::npos);
  }
}

// Single precision: the fields as Float32 (rounded to nearest), the
// points still Float64.
TEST(VtuWriter, SinglePrecisionFields) {
  const auto file = test::scratch("vtu_single") / "grid.vtu";
  auto grid = two_tetrahedra();
  grid.point_data[0].values.assign(15, 1.0 / 3.0);
  write_vtu(file, grid, {.compress = true, .single_precision = true});
  const auto xml = test::slurp(file);
  expect_same_bits(vtu_array<double>(xml, "<Points>"),
                   std::vector<double>(grid.points.data(), grid.points.data() + grid.points.size()));
  EXPECT_EQ(vtu_array<float>(xml, "Name=\"u\""), std::vector<float>(15, 1.0f / 3.0f));
}

// A field larger than one zlib block (32 kB) is split into several, the
// last one partial.
TEST(VtuWriter, CompressedFieldsSpanSeveralBlocks) {
  VtuGrid grid;
  const int n = 10000;  // 240 kB of point coordinates
  grid.points = Eigen::MatrixXd::Random(3, n);
  grid.cells = Eigen::MatrixXi::Zero(1, n);
  for (int i = 0; i < n; ++i) grid.cells(0, i) = i;
  grid.point_data.push_back({"id", 1, std::vector<double>(n)});
  for (int i = 0; i < n; ++i) grid.point_data[0].values[i] = i * 0.5;
  const auto file = test::scratch("vtu_blocks") / "grid.vtu";
  write_vtu(file, grid);
  const auto xml = test::slurp(file);
  expect_same_bits(vtu_array<double>(xml, "<Points>"),
                   std::vector<double>(grid.points.data(), grid.points.data() + grid.points.size()));
  expect_same_bits(vtu_array<double>(xml, "Name=\"id\""), grid.point_data[0].values);
}

// ParaView names the components of a symmetric tensor.
TEST(VtuWriter, ComponentNames) {
  auto grid = two_tetrahedra();
  grid.cell_data.push_back({"stress", 2, {1, 2, 3, 4}, {"xx", "yy"}});
  const auto file = test::scratch("vtu_names") / "grid.vtu";
  write_vtu(file, grid);
  const auto xml = test::slurp(file);
  EXPECT_NE(xml.find("Name=\"stress\" ComponentName0=\"xx\" ComponentName1=\"yy\" NumberOfComponents=\"2\""),
            std::string::npos);
  grid.cell_data.back().component_names = {"xx"};
  EXPECT_THROW(write_vtu(file, grid), Error);
}

TEST(VtuWriter, TwoDimensionalPointsArePaddedWithZ) {
  VtuGrid grid;
  grid.points.resize(2, 4);
  grid.points << 0, 1, 1, 0, 0, 0, 1, 1;
  grid.cells.resize(3, 2);
  grid.cells << 0, 0, 1, 2, 2, 3;
  const auto file = test::scratch("vtu_tris") / "grid.vtu";
  write_vtu(file, grid);
  const auto xml = test::slurp(file);
  EXPECT_EQ(vtu_array<double>(xml, "<Points>"), (std::vector<double>{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}));
  EXPECT_EQ(vtu_array<std::uint8_t>(xml, "Name=\"types\""), (std::vector<std::uint8_t>{5, 5}));
  EXPECT_EQ(vtu_array<std::int64_t>(xml, "Name=\"offsets\""), (std::vector<std::int64_t>{3, 6}));
}

TEST(VtuWriter, LinesAndVertices) {
  const auto dir = test::scratch("vtu_lines");
  VtuGrid grid;
  grid.points = Eigen::MatrixXd::Zero(3, 3);
  grid.cells.resize(2, 2);
  grid.cells << 0, 1, 1, 2;
  write_vtu(dir / "lines.vtu", grid);
  EXPECT_EQ(vtu_array<std::uint8_t>(test::slurp(dir / "lines.vtu"), "Name=\"types\""),
            (std::vector<std::uint8_t>{3, 3}));
  // 0 to 4 vertices: an empty array and short ones.
  for (int n = 0; n <= 4; ++n) {
    grid.cells = Eigen::MatrixXi::Zero(1, n);
    write_vtu(dir / "vertices.vtu", grid);
    EXPECT_EQ(vtu_array<std::uint8_t>(test::slurp(dir / "vertices.vtu"), "Name=\"types\""),
              std::vector<std::uint8_t>(static_cast<std::size_t>(n), 1));
  }
}

TEST(VtuWriter, MixedCellsTakeTheirOwnNodeCounts) {
  // Tetrahedra of a body and the triangles of a bare rigid surface in one
  // grid (issue 11): each column of `cells` uses its first nodes_per_cell
  // entries; the rest of a column is not read.
  VtuGrid grid = two_tetrahedra();
  grid.cells.conservativeResize(4, 4);
  grid.cells.col(2) << 0, 1, 4, -1;
  grid.cells.col(3) << 2, 3, -7, 99;
  grid.nodes_per_cell = {4, 4, 3, 2};
  grid.cell_data[0].values = {1.0, 2.0, std::nan(""), -0.0};
  const auto file = test::scratch("vtu_mixed") / "grid.vtu";
  write_vtu(file, grid);
  const auto xml = test::slurp(file);
  EXPECT_NE(xml.find("NumberOfPoints=\"5\" NumberOfCells=\"4\""), std::string::npos);
  EXPECT_EQ(vtu_array<std::int64_t>(xml, "Name=\"connectivity\""),
            (std::vector<std::int64_t>{0, 1, 2, 3, 1, 2, 3, 4, 0, 1, 4, 2, 3}));
  EXPECT_EQ(vtu_array<std::int64_t>(xml, "Name=\"offsets\""), (std::vector<std::int64_t>{4, 8, 11, 13}));
  EXPECT_EQ(vtu_array<std::uint8_t>(xml, "Name=\"types\""), (std::vector<std::uint8_t>{10, 10, 5, 3}));
  expect_same_bits(vtu_array<double>(xml, "Name=\"energy density\""), grid.cell_data[0].values);
}

/// A 10-node tetrahedron, a 6-node triangle and a 3-node line, in Gmsh's
/// node order (mesh/mesh.hpp); unused entries of a column are -1.
VtuGrid quadratic_cells() {
  VtuGrid grid;
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  grid.points = Eigen::MatrixXd::NullaryExpr(3, 13, [&] { return uniform(random); });
  grid.cells = Eigen::MatrixXi::Constant(10, 3, -1);
  grid.cells.col(0) << 0, 1, 2, 3, 4, 5, 6, 7, 8, 9;
  grid.cells.col(1).head(6) << 0, 2, 1, 6, 5, 4;
  grid.cells.col(2).head(3) << 10, 12, 11;
  grid.types = {vtk_cell_type(3, 10), vtk_cell_type(2, 6), vtk_cell_type(1, 3)};
  grid.cell_data.push_back({"id", 1, {0.0, 1.0, 2.0}});
  return grid;
}

TEST(VtuWriter, VtkCellTypesOfLinearAndQuadraticSimplices) {
  EXPECT_EQ(vtk_cell_type(0, 1), 1);
  EXPECT_EQ(vtk_cell_type(1, 2), 3);
  EXPECT_EQ(vtk_cell_type(2, 3), 5);
  EXPECT_EQ(vtk_cell_type(3, 4), 10);
  EXPECT_EQ(vtk_cell_type(1, 3), 21);
  EXPECT_EQ(vtk_cell_type(2, 6), 22);
  EXPECT_EQ(vtk_cell_type(3, 10), 24);
  EXPECT_THROW(vtk_cell_type(2, 4), Error);
  EXPECT_THROW(vtk_cell_type(3, 6), Error);
  for (const int type : {1, 3, 5, 10, 21, 22, 24}) {
    const auto t = static_cast<std::uint8_t>(type);
    const int nodes = vtk_cell_nodes(t);
    const int dim = type == 1 ? 0 : (type == 3 || type == 21 ? 1 : (type == 5 || type == 22 ? 2 : 3));
    EXPECT_EQ(vtk_cell_type(dim, nodes), t) << type;
  }
  EXPECT_THROW(vtk_cell_nodes(12), Error);  // a hexahedron
}

// Quadratic cells need their types (a 3-node line and a 3-node triangle
// have the same count); a 10-node tetrahedron's connectivity is written in
// VTK's order, whose slots 7–9 are edges (0,3), (1,3), (2,3): Gmsh's slots
// 8 (3,2) and 9 (3,1) swap. A 6-node triangle and a 3-node line are alike
// in both.
TEST(VtuWriter, QuadraticCellsTakeTheirTypesAndVtkNodeOrder) {
  for (const bool compress : {true, false}) {
    const auto file = test::scratch("vtu_quadratic") / "grid.vtu";
    const VtuGrid grid = quadratic_cells();
    write_vtu(file, grid, {.compress = compress});
    const auto xml = test::slurp(file);
    EXPECT_NE(xml.find("NumberOfPoints=\"13\" NumberOfCells=\"3\""), std::string::npos);
    EXPECT_EQ(vtu_array<std::int64_t>(xml, "Name=\"connectivity\""),
              (std::vector<std::int64_t>{0, 1, 2, 3, 4, 5, 6, 7, 9, 8, 0, 2, 1, 6, 5, 4, 10, 12, 11}));
    EXPECT_EQ(vtu_array<std::int64_t>(xml, "Name=\"offsets\""), (std::vector<std::int64_t>{10, 16, 19}));
    EXPECT_EQ(vtu_array<std::uint8_t>(xml, "Name=\"types\""), (std::vector<std::uint8_t>{24, 22, 21}));
    expect_same_bits(vtu_array<double>(xml, "Name=\"id\""), grid.cell_data[0].values);
  }
}

TEST(VtuWriter, TypesMustFitTheNodeCounts) {
  const auto file = test::scratch("vtu_bad_types") / "a.vtu";
  VtuGrid grid = quadratic_cells();
  grid.types.pop_back();  // two types for three cells
  EXPECT_THROW(write_vtu(file, grid), Error);
  grid = quadratic_cells();
  grid.nodes_per_cell = {10, 6, 2};  // a 3-node line given 2 nodes
  EXPECT_THROW(write_vtu(file, grid), Error);
  grid.nodes_per_cell = {10, 6, 3};  // agreeing counts are fine
  EXPECT_NO_THROW(write_vtu(file, grid));
  grid = quadratic_cells();
  grid.types[1] = 12;  // not a simplex
  EXPECT_THROW(write_vtu(file, grid), Error);
  grid = quadratic_cells();
  grid.types.clear();  // 10 nodes per cell, no type inferred for them
  EXPECT_THROW(write_vtu(file, grid), Error);
  grid = quadratic_cells();
  grid.cells.conservativeResize(6, 3);  // a column too short for the tetrahedron
  EXPECT_THROW(write_vtu(file, grid), Error);
}

TEST(VtuWriter, PieceKeepsTheCellsTypes) {
  const VtuGrid grid = quadratic_cells();
  const VtuGrid part = piece(grid, 1, 3);  // the triangle and the line
  EXPECT_EQ(part.types, (std::vector<std::uint8_t>{22, 21}));
  EXPECT_TRUE(part.nodes_per_cell.empty());
  ASSERT_EQ(part.points.cols(), 9);  // nodes 0, 1, 2, 4, 5, 6, 10, 11, 12
  EXPECT_EQ(part.points.col(6), grid.points.col(10));
  const auto file = test::scratch("vtu_quadratic_piece") / "part.vtu";
  write_vtu(file, part);
  const auto xml = test::slurp(file);
  EXPECT_EQ(vtu_array<std::int64_t>(xml, "Name=\"connectivity\""),
            (std::vector<std::int64_t>{0, 2, 1, 5, 4, 3, 6, 8, 7}));
  EXPECT_EQ(vtu_array<std::uint8_t>(xml, "Name=\"types\""), (std::vector<std::uint8_t>{22, 21}));
  EXPECT_EQ(piece(two_tetrahedra(), 0, 2).types, std::vector<std::uint8_t>{});  // none given, none made
}

TEST(VtuWriter, BadNodesPerCellThrowsError) {
  VtuGrid grid = two_tetrahedra();
  grid.nodes_per_cell = {4};  // one count for two cells
  EXPECT_THROW(write_vtu(test::scratch("vtu_bad_counts") / "a.vtu", grid), Error);
  grid.nodes_per_cell = {4, 5};  // more nodes than the column holds
  EXPECT_THROW(write_vtu(test::scratch("vtu_bad_counts") / "a.vtu", grid), Error);
  grid.nodes_per_cell = {4, 0};
  EXPECT_THROW(write_vtu(test::scratch("vtu_bad_counts") / "a.vtu", grid), Error);
}

TEST(VtuWriter, NoTemporaryFileLeftBehind) {
  const auto dir = test::scratch("vtu_tmp");
  write_vtu(dir / "a.vtu", two_tetrahedra());
  write_vtu(dir / "a.vtu", two_tetrahedra());  // overwrite in place
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) names.push_back(entry.path().filename().string());
  EXPECT_EQ(names, std::vector<std::string>{"a.vtu"});
}

TEST(VtuWriter, MissingDirectoryThrowsError) {
  const auto file = test::scratch("vtu_missing") / "no" / "such" / "dir" / "a.vtu";
  EXPECT_THROW(write_vtu(file, two_tetrahedra()), Error);
}

TEST(VtuWriter, WrongFieldSizeThrowsError) {
  auto grid = two_tetrahedra();
  grid.point_data[0].values.pop_back();
  EXPECT_THROW(write_vtu(test::scratch("vtu_bad") / "a.vtu", grid), Error);
  grid = two_tetrahedra();
  grid.cells(0, 0) = 5;  // no such point
  EXPECT_THROW(write_vtu(test::scratch("vtu_bad") / "a.vtu", grid), Error);
}

// The XML part (the appended data is raw bytes, which XML does not
// allow; VTK and meshio read it past the '_').
TEST(VtuWriter, XmllintAcceptsTheXmlPartIfAvailable) {
  if (std::system("xmllint --version > /dev/null 2>&1") != 0) GTEST_SKIP() << "xmllint not installed";
  const auto dir = test::scratch("vtu_xmllint");
  write_vtu(dir / "a.vtu", two_tetrahedra());
  const auto xml = test::slurp(dir / "a.vtu");
  const auto data = xml.find("<AppendedData");
  ASSERT_NE(data, std::string::npos);
  test::write_file(dir / "head.xml", xml.substr(0, data) + "</VTKFile>\n");
  EXPECT_EQ(std::system(("xmllint --noout '" + (dir / "head.xml").string() + "'").c_str()), 0);
}

TEST(PvdWriter, ListsEntriesInOrderAndRewritesAfterEachAdd) {
  const auto dir = test::scratch("vtu_pvd");
  PvdWriter pvd(dir / "run.pvd");
  pvd.add(0.0, "step_0000.vtu");
  EXPECT_NE(test::slurp(dir / "run.pvd").find("file=\"step_0000.vtu\""), std::string::npos);
  pvd.add(0.1, "step_0010.vtu");
  pvd.add(0.30000000000000004, "a&b.vtu");
  const auto xml = test::slurp(dir / "run.pvd");
  const auto first = xml.find("<DataSet timestep=\"0\" group=\"\" part=\"0\" file=\"step_0000.vtu\"/>");
  const auto second = xml.find("<DataSet timestep=\"0.1\" group=\"\" part=\"0\" file=\"step_0010.vtu\"/>");
  const auto third = xml.find("timestep=\"0.30000000000000004\" group=\"\" part=\"0\" file=\"a&amp;b.vtu\"/>");
  EXPECT_NE(first, std::string::npos) << xml;
  EXPECT_LT(first, second);
  EXPECT_LT(second, third);
  EXPECT_NE(third, std::string::npos) << xml;
  EXPECT_NE(xml.find("type=\"Collection\""), std::string::npos);
  EXPECT_FALSE(fs::exists(dir / "run.pvd.tmp"));
}

TEST(PvdWriter, MissingDirectoryThrowsError) {
  PvdWriter pvd(test::scratch("vtu_pvd_missing") / "no" / "run.pvd");
  EXPECT_THROW(pvd.add(0.0, "a.vtu"), Error);
}

}  // namespace
}  // namespace conserve::io
