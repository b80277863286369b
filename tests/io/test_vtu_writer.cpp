/// VTU/PVD output, decoded back from the XML and compared bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <random>

#include "core/error.hpp"
#include "io/vtu_writer.hpp"
#include "support/base64.hpp"
#include "support/files.hpp"

namespace conserve::io {
namespace {

namespace fs = std::filesystem;

using test::base64_decode;

/// The base64 payload of the first DataArray after `anchor` (an attribute
/// such as `Name="u"` or the tag `<Points>`), decoded and checked against
/// its UInt64 byte-count header.
template <typename T>
std::vector<T> decode_array(const std::string& xml, const std::string& anchor) {
  const auto at = xml.find(anchor);
  EXPECT_NE(at, std::string::npos) << anchor;
  if (at == std::string::npos) return {};
  // an attribute is inside the DataArray's tag; a tag such as <Points> precedes it
  const auto tag = anchor.front() == '<' ? xml.find("<DataArray", at) : at;
  const auto start = xml.find('>', tag) + 1;
  const auto stop = xml.find("</DataArray>", start);
  const auto bytes = base64_decode(xml.substr(start, stop - start));
  std::uint64_t size = 0;
  std::memcpy(&size, bytes.data(), sizeof size);
  EXPECT_EQ(size + sizeof size, bytes.size()) << anchor;
  std::vector<T> values(size / sizeof(T));
  if (size > 0) std::memcpy(values.data(), bytes.data() + sizeof size, size);
  return values;
}

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
  const auto file = test::scratch("vtu_tets") / "grid.vtu";
  const auto grid = two_tetrahedra();
  write_vtu(file, grid);
  const auto xml = test::slurp(file);
  EXPECT_NE(xml.find("type=\"UnstructuredGrid\""), std::string::npos);
  EXPECT_NE(xml.find("header_type=\"UInt64\""), std::string::npos);
  EXPECT_NE(xml.find("NumberOfPoints=\"5\" NumberOfCells=\"2\""), std::string::npos);
  expect_same_bits(decode_array<double>(xml, "<Points>"),
                   std::vector<double>(grid.points.data(), grid.points.data() + grid.points.size()));
  EXPECT_EQ(decode_array<std::int64_t>(xml, "Name=\"connectivity\""),
            (std::vector<std::int64_t>{0, 1, 2, 3, 1, 2, 3, 4}));
  EXPECT_EQ(decode_array<std::int64_t>(xml, "Name=\"offsets\""), (std::vector<std::int64_t>{4, 8}));
  EXPECT_EQ(decode_array<std::uint8_t>(xml, "Name=\"types\""), (std::vector<std::uint8_t>{10, 10}));
  expect_same_bits(decode_array<double>(xml, "Name=\"u\""), grid.point_data[0].values);
  expect_same_bits(decode_array<double>(xml, "Name=\"energy density\""), grid.cell_data[0].values);
  EXPECT_NE(xml.find("Name=\"u\" NumberOfComponents=\"3\""), std::string::npos);
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
  EXPECT_EQ(decode_array<double>(xml, "<Points>"), (std::vector<double>{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}));
  EXPECT_EQ(decode_array<std::uint8_t>(xml, "Name=\"types\""), (std::vector<std::uint8_t>{5, 5}));
  EXPECT_EQ(decode_array<std::int64_t>(xml, "Name=\"offsets\""), (std::vector<std::int64_t>{3, 6}));
}

TEST(VtuWriter, LinesAndVertices) {
  const auto dir = test::scratch("vtu_lines");
  VtuGrid grid;
  grid.points = Eigen::MatrixXd::Zero(3, 3);
  grid.cells.resize(2, 2);
  grid.cells << 0, 1, 1, 2;
  write_vtu(dir / "lines.vtu", grid);
  EXPECT_EQ(decode_array<std::uint8_t>(test::slurp(dir / "lines.vtu"), "Name=\"types\""),
            (std::vector<std::uint8_t>{3, 3}));
  // 0 to 4 vertices: every base64 padding case of the UInt8 array.
  for (int n = 0; n <= 4; ++n) {
    grid.cells = Eigen::MatrixXi::Zero(1, n);
    write_vtu(dir / "vertices.vtu", grid);
    EXPECT_EQ(decode_array<std::uint8_t>(test::slurp(dir / "vertices.vtu"), "Name=\"types\""),
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
  EXPECT_EQ(decode_array<std::int64_t>(xml, "Name=\"connectivity\""),
            (std::vector<std::int64_t>{0, 1, 2, 3, 1, 2, 3, 4, 0, 1, 4, 2, 3}));
  EXPECT_EQ(decode_array<std::int64_t>(xml, "Name=\"offsets\""), (std::vector<std::int64_t>{4, 8, 11, 13}));
  EXPECT_EQ(decode_array<std::uint8_t>(xml, "Name=\"types\""), (std::vector<std::uint8_t>{10, 10, 5, 3}));
  expect_same_bits(decode_array<double>(xml, "Name=\"energy density\""), grid.cell_data[0].values);
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

TEST(VtuWriter, XmllintAcceptsTheFileIfAvailable) {
  if (std::system("xmllint --version > /dev/null 2>&1") != 0) GTEST_SKIP() << "xmllint not installed";
  const auto file = test::scratch("vtu_xmllint") / "a.vtu";
  write_vtu(file, two_tetrahedra());
  EXPECT_EQ(std::system(("xmllint --noout '" + file.string() + "'").c_str()), 0);
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
