// More bad input through the command line (issue 7): broken meshes, bodies
// overlapping at t = 0, contact pairs on missing bodies or on surfaces that
// are not on the boundary. Each gets one line and exit code 1.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>

#include "support/cli.hpp"

namespace conserve::test {
namespace {

using ::testing::HasSubstr;

/// One tetrahedron; `coords` are its four node lines, `element` its node list.
std::string one_tet(const std::string& tags, const std::string& coords, const std::string& element) {
  return "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Entities\n0 0 0 1\n1 0 0 0 1 1 1 0 0\n$EndEntities\n"
         "$Nodes\n1 4 1 4\n3 1 0 4\n" +
         tags + coords + "$EndNodes\n$Elements\n1 1 1 1\n3 1 4 1\n1 " + element + "\n$EndElements\n";
}
const std::string kTags = "1\n2\n3\n4\n";
const std::string kCoords = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";

const std::string kTetScenario = R"(dimension = 3
[time]
step = 0.01
end = 0.02
[[body]]
name = "tet"
[body.material]
young = 1.0e5
poisson = 0.3
density = 1000.0
[body.mesh]
file = "tet.msh"
)";

CliResult check(const std::string& name, const std::string& scenario, const std::string& file = "",
                const std::string& content = "") {
  const auto dir = scratch("more_" + name);
  write_file(dir / "scenario.toml", scenario);
  if (!file.empty()) write_file(dir / file, content);
  return run_cli("check scenario.toml", dir);
}

TEST(BadInputMore, GoodTetPasses) {
  const CliResult r = check("tet_ok", kTetScenario, "tet.msh", one_tet(kTags, kCoords, "1 2 3 4"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

TEST(BadInputMore, DuplicateNodeTag) {
  const CliResult r = check("dup_node", kTetScenario, "tet.msh", one_tet("1\n2\n2\n4\n", kCoords, "1 2 3 4"));
  expect_one_line_error(r, "tet.msh:");
  EXPECT_THAT(r.err, HasSubstr("duplicate node tag 2"));
}

TEST(BadInputMore, ElementWithMissingNode) {
  const CliResult r = check("missing_node", kTetScenario, "tet.msh", one_tet(kTags, kCoords, "1 2 3 9"));
  expect_one_line_error(r, "tet.msh:");
  EXPECT_THAT(r.err, HasSubstr("node 9, which is not in $Nodes"));
}

TEST(BadInputMore, DegenerateElement) {
  const CliResult r =
      check("degenerate", kTetScenario, "tet.msh", one_tet(kTags, "0 0 0\n1 0 0\n0 1 0\n1 1 0\n", "1 2 3 4"));
  expect_one_line_error(r, "tet.msh:");
  EXPECT_THAT(r.err, HasSubstr("degenerate"));
}

std::string two_boxes(double x_second) {
  return R"(dimension = 3
[time]
step = 0.01
end = 0.02
[[body]]
name = "left"
[body.material]
young = 1.0e5
poisson = 0.3
density = 1000.0
[body.mesh]
generator = "box"
lx = 1.0
ly = 1.0
lz = 1.0
size = 0.5
[[body]]
name = "right"
translate = [)" +
         std::to_string(x_second) +
         R"(, 0.0, 0.0]
[body.material]
young = 1.0e5
poisson = 0.3
density = 1000.0
[body.mesh]
generator = "box"
lx = 1.0
ly = 1.0
lz = 1.0
size = 0.5
)";
}

TEST(BadInputMore, OverlappingBodies) {
  const CliResult r = check("overlap", two_boxes(0.7));
  expect_one_line_error(r, "scenario.toml:");
  EXPECT_THAT(r.err, HasSubstr(": body[1].translate: bodies '"));
  EXPECT_THAT(r.err, HasSubstr("overlap at t = 0"));
  EXPECT_THAT(r.err, HasSubstr("'left'"));
  EXPECT_THAT(r.err, HasSubstr("'right'"));
}

TEST(BadInputMore, TouchingBodiesAreFine) {
  const CliResult touching = check("touching", two_boxes(1.0));
  EXPECT_EQ(touching.exit_code, 0) << touching.err;
  const CliResult apart = check("apart", two_boxes(1.5));
  EXPECT_EQ(apart.exit_code, 0) << apart.err;
}

TEST(BadInputMore, ContactOnMissingBody) {
  const CliResult r = check("contact_missing", two_boxes(1.5) +
                                                   "[[contact]]\nslave = \"left\"\nmaster = \"nobody\"\n"
                                                   "kind = \"frictionless\"\n");
  expect_one_line_error(r, "scenario.toml:");
  EXPECT_THAT(r.err, HasSubstr("nobody"));
}

TEST(BadInputMore, ContactOnMissingGroup) {
  const CliResult r = check("contact_group", two_boxes(1.5) +
                                                 "[[contact]]\nslave = \"left:nowhere\"\n"
                                                 "master = \"right\"\nkind = \"frictionless\"\n");
  expect_one_line_error(r, "contact[0]");
  EXPECT_THAT(r.err, HasSubstr("nowhere"));
}

/// A unit square of two triangles with the interior diagonal as group "diag".
const std::string kSquareWithDiagonal = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
2
1 1 "diag"
2 2 "plate"
$EndPhysicalNames
$Entities
0 1 1 0
1 0 0 0 1 1 0 1 1 0
1 0 0 0 1 1 0 1 2 0
$EndEntities
$Nodes
1 4 1 4
2 1 0 4
1
2
3
4
0 0 0
1 0 0
1 1 0
0 1 0
$EndNodes
$Elements
2 3 1 3
1 1 1 1
1 1 3
2 1 2 2
2 1 2 3
3 1 3 4
$EndElements
)";

/// The square above in contact with a ground strip, slave "square:diag".
const std::string kSquareScenario = R"(dimension = 2
[time]
step = 0.01
end = 0.02
[[body]]
name = "square"
[body.material]
young = 1.0e5
poisson = 0.3
density = 1000.0
[body.mesh]
file = "square.msh"
[[body]]
name = "ground"
translate = [0.0, -0.5]
[body.material]
young = 1.0e5
poisson = 0.3
density = 1000.0
[body.mesh]
generator = "rectangle"
lx = 2.0
ly = 0.2
size = 0.2
[[contact]]
slave = "square:diag"
master = "ground"
kind = "frictionless"
)";

TEST(BadInputMore, ContactSurfaceNotOnTheBoundary) {
  const CliResult r = check("not_boundary", kSquareScenario, "square.msh", kSquareWithDiagonal);
  expect_one_line_error(r, "contact[0]");
  EXPECT_THAT(r.err, HasSubstr("not on the body's boundary"));
}

TEST(BadInputMore, EmptyContactSurface) {
  // A physical group that names no element: the contact surface is empty.
  std::string mesh = kSquareWithDiagonal;
  const std::string names = "$PhysicalNames\n2\n";
  mesh.replace(mesh.find(names), names.size(), "$PhysicalNames\n3\n1 3 \"rim\"\n");
  std::string scenario = kSquareScenario;
  scenario.replace(scenario.find("square:diag"), 11, "square:rim");
  const CliResult r = check("empty_surface", scenario, "square.msh", mesh);
  expect_one_line_error(r, "contact[0]");
  EXPECT_THAT(r.err, HasSubstr("rim"));
}

/// `conserve run` on bad input stops before it writes anything: no output
/// folder appears, so a failed run never leaves half a result behind.
TEST(BadInputMore, RunOnBadInputWritesNothing) {
  const auto dir = scratch("more_nothing_written");
  write_file(dir / "overlap.toml", two_boxes(0.7));
  write_file(dir / "square.toml", kSquareScenario);
  write_file(dir / "square.msh", kSquareWithDiagonal);
  write_file(dir / "tet.toml", kTetScenario);
  write_file(dir / "tet.msh", one_tet(kTags, kCoords, "1 3 2 4"));  // inverted
  std::string good = kTetScenario;
  good.replace(good.find("tet.msh"), 7, "good.msh");
  write_file(dir / "good_tet.toml", good);
  write_file(dir / "good.msh", one_tet(kTags, kCoords, "1 2 3 4"));
  write_file(dir / "ckpt.bin", "not a checkpoint at all");
  for (const std::string& args : {"run overlap.toml -q -o out", "run square.toml -q -o out", "run tet.toml -q -o out",
                                  "run good_tet.toml -q -o out --restart ckpt.bin"}) {
    const CliResult r = run_cli(args, dir);
    EXPECT_EQ(r.exit_code, 1) << args << ": " << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "out")) << args;
  }
}

/// A body name that history.csv's header cannot carry is refused by both
/// commands before anything is written (it used to pass `check` and make
/// `run` die with exit code 4 after creating the output folder).
TEST(BadInputMore, BodyNameTheOutputsCannotCarry) {
  const auto dir = scratch("more_bad_name");
  std::string scenario = kTetScenario;
  scenario.replace(scenario.find("name = \"tet\""), 12, "name = \"big, tet\"");
  write_file(dir / "scenario.toml", scenario);
  write_file(dir / "tet.msh", one_tet(kTags, kCoords, "1 2 3 4"));
  for (const std::string& args : {"check scenario.toml", "run scenario.toml -q -o out"}) {
    SCOPED_TRACE(args);
    const CliResult r = run_cli(args, dir);
    expect_one_line_error(r, "scenario.toml:6: body[0].name: 'big, tet' contains ',' (a comma)");
    EXPECT_FALSE(std::filesystem::exists(dir / "out"));
  }
}

TEST(BadInputMore, RestartFromGarbage) {
  const auto dir = scratch("more_restart_garbage");
  write_file(dir / "scenario.toml", kTetScenario);
  write_file(dir / "tet.msh", one_tet(kTags, kCoords, "1 2 3 4"));
  write_file(dir / "ckpt.bin", "not a checkpoint at all");
  const CliResult r = run_cli("run scenario.toml -q -o out --restart ckpt.bin", dir);
  expect_one_line_error(r, "ckpt.bin: bad checkpoint");
}

}  // namespace
}  // namespace conserve::test
