// Obstacles from files (issue 47): a rigid body's mesh may be a triangle
// surface from a Gmsh .msh file or an STL file. The must-show: an STL
// obstacle and the same obstacle meshed by Gmsh give the same run, byte for
// byte. `check` states which way the normals point; bad surfaces stop with
// one line naming the scenario's key and the mesh file.
#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gmsh.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <vector>

#include "io/history_writer.hpp"
#include "support/cli.hpp"
#include "support/stl_files.hpp"

namespace conserve::test {
namespace {

namespace fs = std::filesystem;
using ::testing::AllOf;
using ::testing::HasSubstr;

/// A coarse elastic box (0.2 m, E = 1 MPa) thrown down and sideways into a
/// rigid tray read from FILE: it bounces on the bottom and is turned back
/// by the sloping +x wall (60 steps of 5 ms, refined at impacts).
const std::string kBoxIntoTray = R"(title = "a box thrown into a tray"
dimension = 3
[time]
step = 0.005
end = 0.3
[loads]
gravity = [0.0, 0.0, -9.81]
[output]
vtu_every = 0
[[body]]
name = "box"
translate = [0.2, 0.0, 0.11]
velocity = [0.8, 0.0, -0.5]
[body.material]
young = 1.0e6
poisson = 0.3
density = 1000.0
[body.mesh]
generator = "box"
lx = 0.2
ly = 0.2
lz = 0.2
size = 0.2
[[body]]
name = "tray"
rigid = true
[body.mesh]
file = "FILE"
[[contact]]
slave = "box:boundary"
master = "tray:surface"
kind = "frictionless"
)";

/// The 1-based line of `text` on which `needle` first appears.
int line_containing(const std::string& text, const std::string& needle) {
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(text.find(needle)), '\n'));
}

/// The shallow tray meshed by Gmsh: bottom [-0.5, 0.5]² at z = 0, walls
/// sloping up to [-0.75, 0.75]² at z = 0.25, each face two triangles on
/// its corners (transfinite, so every coordinate is exact in float32), the
/// curve loops counter-clockwise seen from inside (normals into the tray).
/// Writes DIR/tray.msh (MSH 4.1) and DIR/tray_gmsh.stl (Gmsh's ASCII STL);
/// returns the triangles as Gmsh meshed them.
std::vector<StlTriangle> mesh_tray_with_gmsh(const fs::path& dir) {
  namespace geo = gmsh::model::geo;
  gmsh::initialize(0, nullptr, false);
  gmsh::option::setNumber("General.Terminal", 0);
  gmsh::model::add("tray");
  const double corners[8][3] = {{-0.5, -0.5, 0},      {0.5, -0.5, 0},      {0.5, 0.5, 0},      {-0.5, 0.5, 0},
                                {-0.75, -0.75, 0.25}, {0.75, -0.75, 0.25}, {0.75, 0.75, 0.25}, {-0.75, 0.75, 0.25}};
  for (int p = 0; p < 8; ++p) geo::addPoint(corners[p][0], corners[p][1], corners[p][2], 0.0, p + 1);
  const int lines[12][2] = {{1, 2}, {2, 3}, {3, 4}, {4, 1}, {5, 6}, {6, 7},
                            {7, 8}, {8, 5}, {1, 5}, {2, 6}, {3, 7}, {4, 8}};
  for (int l = 0; l < 12; ++l) geo::addLine(lines[l][0], lines[l][1], l + 1);
  const std::vector<std::vector<int>> loops = {
      {1, 2, 3, 4}, {9, 5, -10, -1}, {10, 6, -11, -2}, {11, 7, -12, -3}, {12, 8, -9, -4}};
  for (int s = 0; s < 5; ++s)
    geo::addPlaneSurface({geo::addCurveLoop(loops[static_cast<std::size_t>(s)], s + 1)}, s + 1);
  for (int l = 1; l <= 12; ++l) geo::mesh::setTransfiniteCurve(l, 2);
  for (int s = 1; s <= 5; ++s) geo::mesh::setTransfiniteSurface(s);
  geo::synchronize();
  gmsh::model::setPhysicalName(2, gmsh::model::addPhysicalGroup(2, {1, 2, 3, 4, 5}), "tray");
  gmsh::model::mesh::generate(2);
  gmsh::option::setNumber("Mesh.MshFileVersion", 4.1);
  gmsh::option::setNumber("Mesh.Binary", 0);
  gmsh::write((dir / "tray.msh").string());
  gmsh::write((dir / "tray_gmsh.stl").string());
  std::vector<int> types;
  std::vector<std::vector<std::size_t>> elements, nodes;
  gmsh::model::mesh::getElements(types, elements, nodes, 2, -1);
  std::vector<StlTriangle> triangles;
  for (std::size_t k = 0; k < nodes.front().size(); ++k) {
    if (k % 3 == 0) triangles.emplace_back();
    std::vector<double> xyz, parametric;
    gmsh::model::mesh::getNode(nodes.front()[k], xyz, parametric);
    triangles.back()[k % 3] = {xyz[0], xyz[1], xyz[2]};
  }
  gmsh::finalize();
  return triangles;
}

/// A folder with the tray as tray.msh and tray_gmsh.stl (both written by
/// Gmsh) and tray.stl (binary, written here from Gmsh's triangles).
fs::path tray_folder(const std::string& name) {
  const fs::path dir = scratch(name);
  const std::vector<StlTriangle> triangles = mesh_tray_with_gmsh(dir);
  EXPECT_EQ(triangles.size(), 10u);
  write_file(dir / "tray.stl", binary_stl(triangles));
  return dir;
}

/// `conserve check` of `scenario` written into `dir`.
CliResult check_in(const fs::path& dir, const std::string& scenario) {
  write_file(dir / "scenario.toml", scenario);
  return run_cli("check scenario.toml", dir);
}

TEST(Obstacles, StlObstacleAndTheSameObstacleMeshedByGmshGiveTheSameRun) {
  const fs::path dir = tray_folder("obstacle_runs");
  std::map<std::string, std::string> histories, steps;
  for (const std::string file : {"tray.msh", "tray.stl", "tray_gmsh.stl"}) {
    write_file(dir / (file + ".toml"), replaced(kBoxIntoTray, "FILE", file));
    const CliResult r = run_cli("run " + file + ".toml -q -o out_" + file, dir);
    ASSERT_EQ(r.exit_code, 0) << file << ": " << r.err;
    histories[file] = slurp(dir / ("out_" + file) / "history.csv");
    steps[file] = slurp(dir / ("out_" + file) / "steps.csv");
  }
  const io::History h = io::read_history(dir / "out_tray.msh/history.csv");
  const auto contacts = h.column("active_contacts"), lx = h.column("L_x"), drift = h.column("drift_E");
  const auto penetration = h.column("max_penetration");
  const double most = *std::max_element(contacts.begin(), contacts.end());
  const double deepest = *std::max_element(penetration.begin(), penetration.end());
  std::printf(
      "[ measured ] box into a tray: %zu steps, up to %.0f active contacts, L_x %.3f -> %.3f kg m/s (turned "
      "back by the wall), drift_E %.1e, deepest penetration %.1e m\n",
      h.rows.size() - 1, most, lx.front(), lx.back(), drift.back(), deepest);
  std::printf(
      "[ measured ] history.csv of tray.stl (binary, written by the test) %s, of tray_gmsh.stl (Gmsh's ASCII "
      "STL) %s that of tray.msh (%zu bytes)\n",
      histories["tray.stl"] == histories["tray.msh"] ? "byte-identical to" : "DIFFERENT from",
      histories["tray_gmsh.stl"] == histories["tray.msh"] ? "byte-identical to" : "DIFFERENT from",
      histories["tray.msh"].size());
  EXPECT_GT(most, 0.0);       // the box touched the tray
  EXPECT_LT(lx.back(), 0.0);  // and the sloping +x wall sent it back
  EXPECT_LT(std::abs(drift.back()), 1e-10);
  EXPECT_EQ(deepest, 0.0);
  EXPECT_EQ(histories["tray.stl"], histories["tray.msh"]);
  EXPECT_EQ(histories["tray_gmsh.stl"], histories["tray.msh"]);
  EXPECT_EQ(steps["tray.stl"], steps["tray.msh"]);
  EXPECT_EQ(steps["tray_gmsh.stl"], steps["tray.msh"]);
}

TEST(Obstacles, CheckStatesWhichWayTheNormalsPoint) {
  const fs::path dir = tray_folder("obstacle_check");
  const std::string stated =
      "body 'tray': surface of 10 triangles, normals point mostly +z (area-weighted mean normal (0.00, 0.00, 0.81)): "
      "the slaves belong on that side";
  for (const std::string file : {"tray.msh", "tray.stl"}) {
    const CliResult r = check_in(dir, replaced(kBoxIntoTray, "FILE", file));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_THAT(r.out, AllOf(HasSubstr("valid. 3D, 2 bodies"), HasSubstr("(24 prescribed)"), HasSubstr(stated)));
    EXPECT_THAT(r.err, ::testing::Not(HasSubstr("behind")));
  }
  // flipped, the tray faces away from the box above it: stated, and warned about
  const std::string flip = replaced(kBoxIntoTray, "file = \"FILE\"", "file = \"tray.stl\"\nflip_normals = true");
  const CliResult flipped = check_in(dir, flip);
  ASSERT_EQ(flipped.exit_code, 0) << flipped.err;
  EXPECT_THAT(flipped.out, HasSubstr("normals point mostly -z (area-weighted mean normal (0.00, 0.00, -0.81))"));
  EXPECT_THAT(flipped.err,
              HasSubstr(fmt::format("scenario.toml:{}: contact[0].master: 272 of the 272 nodes of the slave surface "
                                    "'box:boundary' start behind the bare master surface 'tray:surface' (gaps down to "
                                    "-0.21 m)",
                                    line_containing(flip, "master = "))));
  // no statement for a generated surface, whose normals the generator's doc gives
  const CliResult generated = check_in(
      dir, replaced(kBoxIntoTray, "file = \"FILE\"", "generator = \"square\"\nlx = 2.0\nly = 2.0\nsize = 1.0"));
  ASSERT_EQ(generated.exit_code, 0) << generated.err;
  EXPECT_THAT(generated.out, ::testing::Not(HasSubstr("normals")));
}

TEST(Obstacles, LineMeshObstacleIn2D) {
  const fs::path dir = scratch("obstacle_2d");
  fs::copy_file(fs::path(CONSERVE_SOURCE_DIR) / "tests/data/msh/valley.msh", dir / "valley.msh");
  const std::string scenario = R"(dimension = 2
[time]
step = 0.01
end = 0.1
[[body]]
name = "disc"
translate = [0.0, 0.2]
[body.material]
young = 1.0e6
poisson = 0.3
density = 1000.0
[body.mesh]
generator = "disc"
radius = 0.1
size = 0.05
[[body]]
name = "ground"
rigid = true
[body.mesh]
file = "valley.msh"
[[contact]]
slave = "disc:circle"
master = "ground:floor"
kind = "frictionless"
)";
  const CliResult r = check_in(dir, scenario);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("body 'ground': line of 4 segments, normals point mostly +y"));
}

TEST(ObstacleErrors, InconsistentStlNamesTheKeyAndTheFile) {
  const fs::path dir = scratch("obstacle_bad_stl");
  std::vector<StlTriangle> triangles = {StlTriangle{{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}}},
                                        StlTriangle{{{0, 0, 0}, {0, 1, 0}, {1, 1, 0}}}};  // the second reversed
  write_file(dir / "tray.stl", ascii_stl(triangles));
  const std::string scenario = replaced(kBoxIntoTray, "FILE", "tray.stl");
  expect_one_line_error(
      check_in(dir, scenario),
      fmt::format("scenario.toml:{}: body[1].mesh.file (body 'tray'): {}: triangles 1 and 2 (counted from 1 in file "
                  "order) share the edge from (1, 1, 0) to (0, 0, 0) in the same direction: the surface's facets are "
                  "not consistently oriented",
                  line_containing(scenario, "file = "), (dir / "tray.stl").string()));
}

TEST(ObstacleErrors, OnlyARigidBodyMayBeASurface) {
  const fs::path dir = tray_folder("obstacle_deformable");
  const auto deformable = [](const std::string& file) {
    return replaced(
        replaced(kBoxIntoTray, "rigid = true\n", "[body.material]\nyoung = 1.0e6\npoisson = 0.3\ndensity = 1000.0\n"),
        "FILE", file);
  };
  expect_one_line_error(check_in(dir, deformable("tray.msh")),
                        "body[1].mesh.file (body 'tray'): " + (dir / "tray.msh").string() +
                            ": no 4-node tetrahedra (element type 4) in the file (expected a 3D mesh; its 10 3-node "
                            "triangles make a bare surface, which only a rigid body may be)");
  expect_one_line_error(check_in(dir, deformable("tray.stl")),
                        "body[1].mesh.file (body 'tray'): " + (dir / "tray.stl").string() +
                            ": an STL file holds a bare surface, which only a rigid body may be");
}

TEST(ObstacleErrors, StlIn2DGroupOnASurfaceAndFlipOfCells) {
  const fs::path dir = tray_folder("obstacle_misc");
  const std::string in_2d = R"(dimension = 2
[time]
step = 0.01
end = 0.1
[[body]]
name = "ground"
rigid = true
[body.mesh]
file = "tray.stl"
)";
  expect_one_line_error(check_in(dir, in_2d),
                        "scenario.toml:9: body[0].mesh.file (body 'ground'): " + (dir / "tray.stl").string() +
                            ": an STL file holds a triangle surface, which needs dimension = 3");
  const std::string grouped = replaced(kBoxIntoTray, "file = \"FILE\"", "file = \"tray.msh\"\ngroup = \"tray\"");
  expect_one_line_error(check_in(dir, grouped), fmt::format("scenario.toml:{}: body[1].mesh.group (body 'tray'): the "
                                                            "mesh is a bare surface, without cells to choose from",
                                                            line_containing(grouped, "group = ")));
  fs::copy_file(fs::path(CONSERVE_SOURCE_DIR) / "tests/data/msh/cube_ascii.msh", dir / "cube.msh");
  const std::string solid = replaced(kBoxIntoTray, "file = \"FILE\"", "file = \"cube.msh\"\nflip_normals = true");
  expect_one_line_error(check_in(dir, replaced(solid, "translate = [0.2, 0.0, 0.11]", "translate = [0.2, 0.0, 1.5]")),
                        "body[1].mesh.flip_normals (body 'tray'): the mesh has cells");
  const std::string generated = replaced(kBoxIntoTray, "file = \"FILE\"",
                                         "generator = \"square\"\nlx = 1.0\nly = 1.0\nsize = 0.5\nflip_normals = true");
  expect_one_line_error(check_in(dir, generated), "body[1].mesh.flip_normals: is only allowed with 'file'");
}

}  // namespace
}  // namespace conserve::test
