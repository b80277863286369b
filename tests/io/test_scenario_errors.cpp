/// The scenario parser on bad input: one test per validation rule, each
/// checking "FILE:LINE: KEY: " and the gist of the message.
#include <gtest/gtest.h>

#include <sstream>

#include "scenario_test_support.hpp"

namespace conserve::io {
namespace {

using cases::case_file;
using cases::fails_with;
using cases::minimal;
using cases::with_mesh;

// minimal(): 1 [time], 2 step, 3 end, 4 [[body]], 5 name, 6 [body.material],
// 7 young, 8 poisson, 9 density, 10 [body.mesh], 11 file; extra text from 12.

/// `text` with its line `number` (1-based) replaced by `line`.
std::string replace_line(const std::string& text, int number, std::string_view line) {
  std::istringstream in(text);
  std::string out;
  std::string current;
  for (int n = 1; std::getline(in, current); ++n) out += (n == number ? std::string(line) : current) + "\n";
  return out;
}

TEST(ScenarioErrors, TomlSyntaxErrorHasLineAndColumn) {
  try {
    parse_scenario(minimal("[output]\nvtu_every = = 3\n"), case_file());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(case_file() + ":13:", 0), 0u) << e.what();
    EXPECT_NE(std::string(e.what()).find("TOML syntax error"), std::string::npos) << e.what();
  }
}

TEST(ScenarioErrors, TomlRedefinedTable) {
  EXPECT_THROW(parse_scenario(minimal("[time]\nstep = 1\n"), case_file()), InputError);
}

TEST(ScenarioErrors, UnknownKeyInMaterial) {
  EXPECT_TRUE(fails_with(replace_line(minimal(), 7, "youngs = 1"), 7, "body[0].material.youngs",
                         "unknown key 'youngs' (not a parameter of model 'svk') (expected one of: young, poisson, density, model)"));
}

TEST(ScenarioErrors, LocatedReleasesNeedThePersistentVelocity) {
  EXPECT_TRUE(fails_with(minimal("[active_set]\nlocate_releases = true\nscheme = \"paper\"\n"), 13,
                         "active_set.locate_releases", "needs scheme = \"persistent\""));
  EXPECT_NO_THROW(parse_scenario(minimal("[active_set]\nlocate_releases = true\n"), case_file()));  // the default
}

TEST(ScenarioErrors, UnknownTopLevelTable) {
  EXPECT_TRUE(fails_with(minimal("[tiem]\nstep = 1\n"), 12, "tiem", "unknown key 'tiem' (expected one of: title,"));
}

TEST(ScenarioErrors, UnknownKeyInEveryTable) {
  EXPECT_TRUE(fails_with(replace_line(minimal(), 3, "ende = 1"), 3, "time.ende", "unknown key 'ende'"));
  EXPECT_TRUE(fails_with(minimal("[newton]\nmax_iter = 3\n"), 13, "newton.max_iter", "max_iterations"));
  EXPECT_TRUE(fails_with(minimal("[loads]\ngravitation = [0, 0, 1]\n"), 13, "loads.gravitation", "gravity"));
  EXPECT_TRUE(fails_with(minimal("[output]\ndir = \"x\"\n"), 13, "output.dir", "directory"));
  EXPECT_TRUE(fails_with(replace_line(minimal(), 5, "nam = \"a\""), 5, "body[0].nam", "unknown key 'nam'"));
  EXPECT_TRUE(fails_with(minimal("grp = \"x\"\n"), 12, "body[0].mesh.grp",
                         "expected one of: file, group, flip_normals, reorder, generator"));
  EXPECT_TRUE(fails_with(minimal("[[boundary]]\nbody = \"a\"\ngroup = \"all\"\nrates = [0, 0, 0]\n"), 15,
                         "boundary[0].rates", "unknown key 'rates'"));
}

TEST(ScenarioErrors, FlipNormalsIsABooleanOfAFileMesh) {
  EXPECT_FALSE(parse_scenario(minimal(), case_file()).bodies[0].mesh.flip_normals);
  EXPECT_TRUE(parse_scenario(minimal("flip_normals = true\n"), case_file()).bodies[0].mesh.flip_normals);
  EXPECT_TRUE(fails_with(minimal("flip_normals = \"yes\"\n"), 12, "body[0].mesh.flip_normals", "got a string"));
  EXPECT_TRUE(fails_with(with_mesh("generator = \"box\"\nlx = 1\nly = 1\nlz = 1\nsize = 0.5\nflip_normals = true\n"),
                         16, "body[0].mesh.flip_normals", "is only allowed with 'file'"));
}

TEST(ScenarioErrors, ReorderIsABooleanOfAFileMesh) {
  EXPECT_FALSE(parse_scenario(minimal(), case_file()).bodies[0].mesh.reorder);
  EXPECT_TRUE(parse_scenario(minimal("reorder = true\n"), case_file()).bodies[0].mesh.reorder);
  EXPECT_TRUE(fails_with(minimal("reorder = 1\n"), 12, "body[0].mesh.reorder", "got"));
  EXPECT_TRUE(fails_with(with_mesh("generator = \"box\"\nlx = 1\nly = 1\nlz = 1\nsize = 0.5\nreorder = true\n"),
                         16, "body[0].mesh.reorder", "is only allowed with 'file'"));
}

TEST(ScenarioErrors, FirstUnknownKeyInFileOrderIsReported) {
  EXPECT_TRUE(fails_with(minimal("[output]\nzz = 1\naa = 2\n"), 13, "output.zz", "unknown key 'zz'"));
}

TEST(ScenarioErrors, WrongTypes) {
  EXPECT_TRUE(fails_with(replace_line(minimal(), 7, "young = \"1e6\""), 7, "body[0].material.young",
                         "got a string (expected a finite number [Pa] > 0)"));
  EXPECT_TRUE(fails_with(minimal("translate = 1\n"), 12, "body[0].mesh.translate", "unknown key"));
  EXPECT_TRUE(fails_with(replace_line(minimal(), 5, "name = \"a\"\ntranslate = 1"), 6, "body[0].translate",
                         "got an integer (expected an array of 3 numbers [m])"));
  EXPECT_TRUE(
      fails_with(minimal("[output]\nvtu_every = 2.5\n"), 13, "output.vtu_every", "got a float (expected an integer"));
  EXPECT_TRUE(
      fails_with("time = 3\n" + std::string(cases::kBodyHead), 1, "time", "got an integer (expected a table [time])"));
  EXPECT_TRUE(fails_with(minimal("[loads]\ngravity = [0, \"down\", 0]\n"), 13, "loads.gravity[1]", "got a string"));
  EXPECT_TRUE(fails_with(replace_line(minimal(), 11, "file = 3"), 11, "body[0].mesh.file",
                         "got an integer (expected a string)"));
  EXPECT_TRUE(fails_with(minimal("[output]\nvtu_every = true\n"), 13, "output.vtu_every", "got a boolean"));
}

TEST(ScenarioErrors, IntegersAcceptedForNumbers) {
  const auto s = parse_scenario(replace_line(minimal(), 3, "end = 2"), case_file());
  EXPECT_EQ(s.time.end, 2.0);
}

TEST(ScenarioErrors, MissingKeyReportsEnclosingTableLine) {
  EXPECT_TRUE(fails_with(replace_line(minimal(), 9, ""), 6, "body[0].material.density",
                         "missing key (expected a finite number [kg/m³] > 0)"));
  EXPECT_TRUE(fails_with(replace_line(minimal(), 2, ""), 1, "time.step", "missing key"));
  EXPECT_TRUE(fails_with(std::string(cases::kBodyHead) + "file = \"meshes/cube.msh\"\n", 1, "time", "missing key"));
  EXPECT_TRUE(fails_with(replace_line(minimal(), 5, ""), 4, "body[0].name", "missing key (expected a string)"));
  EXPECT_TRUE(fails_with(minimal("[[boundary]]\nbody = \"a\"\n"), 12, "boundary[0].group", "missing key"));
}

TEST(ScenarioErrors, MaterialRanges) {
  EXPECT_TRUE(fails_with(replace_line(minimal(), 9, "density = -1"), 9, "body[0].material.density",
                         "-1 is out of range (expected a finite number [kg/m³] > 0)"));
  EXPECT_TRUE(fails_with(replace_line(minimal(), 9, "density = 0"), 9, "body[0].material.density", "out of range"));
  EXPECT_TRUE(fails_with(replace_line(minimal(), 7, "young = 0.0"), 7, "body[0].material.young", "out of range"));
  EXPECT_TRUE(fails_with(replace_line(minimal(), 8, "poisson = 0.5"), 8, "body[0].material.poisson",
                         "0.5 is out of range (expected a finite number > -1 and < 0.5)"));
  EXPECT_TRUE(fails_with(replace_line(minimal(), 8, "poisson = -1"), 8, "body[0].material.poisson", "out of range"));
  EXPECT_NO_THROW(parse_scenario(replace_line(minimal(), 8, "poisson = 0.4999"), case_file()));
}

TEST(ScenarioErrors, TimeRanges) {
  EXPECT_TRUE(fails_with(replace_line(minimal(), 2, "step = 0"), 2, "time.step",
                         "0 is out of range (expected a finite number [s] > 0)"));
  EXPECT_TRUE(fails_with(replace_line(minimal(), 2, "step = -1e-3"), 2, "time.step", "out of range"));
  EXPECT_TRUE(fails_with(replace_line(minimal(), 3, "end = 0.001"), 3, "time.end",
                         "0.001 is smaller than step = 0.01 (expected end ≥ step)"));
  EXPECT_NO_THROW(parse_scenario(replace_line(minimal(), 3, "end = 0.01"), case_file()));
  EXPECT_TRUE(fails_with(minimal().insert(7, "scheme = \"explicit\"\n"), 2, "time.scheme",
                         "'explicit' is not allowed (expected one of: conserving, midpoint)"));
  EXPECT_TRUE(fails_with(minimal().insert(7, "mass = \"diagonal\"\n"), 2, "time.mass", "one of: consistent, lumped"));
}

TEST(ScenarioErrors, NewtonAndOutputRanges) {
  EXPECT_TRUE(fails_with(minimal("[newton]\nmax_iterations = 0\n"), 13, "newton.max_iterations",
                         "0 is out of range (expected an integer ≥ 1)"));
  EXPECT_TRUE(
      fails_with(minimal("[newton]\nresidual_tolerance = 0\n"), 13, "newton.residual_tolerance", "out of range"));
  EXPECT_TRUE(fails_with(minimal("[newton]\nincrement_tolerance = 1e-13\n"), 13, "newton.increment_tolerance",
                         "'increment_tolerance' is no longer a key (expected removed: Newton converges on the residual "
                         "only"));
  EXPECT_TRUE(fails_with(minimal("[output]\nvtu_every = -1\n"), 13, "output.vtu_every", "expected an integer ≥ 0"));
  EXPECT_TRUE(fails_with(minimal("[output]\nprogress_every = -2\n"), 13, "output.progress_every", "out of range"));
  EXPECT_TRUE(fails_with(minimal("[output]\nvtu_every = 99999999999\n"), 13, "output.vtu_every", "too large"));
  EXPECT_TRUE(fails_with(minimal("[output]\ndirectory = \"\"\n"), 13, "output.directory", "is empty"));
}

TEST(ScenarioErrors, DimensionMustBeTwoOrThree) {
  EXPECT_TRUE(
      fails_with("dimension = 4\n" + minimal(), 1, "dimension", "4 is out of range (expected an integer ≥ 2 and ≤ 3)"));
  EXPECT_TRUE(fails_with("dimension = 1\n" + minimal(), 1, "dimension", "out of range"));
}

TEST(ScenarioErrors, ArraysOfWrongLength) {
  EXPECT_TRUE(fails_with(minimal("[loads]\ngravity = [0, -9.81]\n"), 13, "loads.gravity",
                         "has 2 elements (expected an array of 3 numbers [m/s²])"));
  EXPECT_TRUE(fails_with("dimension = 2\n" + minimal("[loads]\ngravity = [0, 0, -9.81]\n"), 14, "loads.gravity",
                         "has 3 elements (expected an array of 2 numbers"));
  EXPECT_TRUE(
      fails_with(replace_line(minimal(), 5, "name = \"a\"\nvelocity = []"), 6, "body[0].velocity", "has 0 elements"));
  EXPECT_TRUE(fails_with(replace_line(minimal(), 5, "name = \"a\"\ninitial_deformation = [[1, 0, 0], [0, 1, 0]]"), 6,
                         "body[0].initial_deformation", "has 2 rows (expected 3 rows, each an array of 3 numbers)"));
  EXPECT_TRUE(
      fails_with(replace_line(minimal(), 5, "name = \"a\"\ninitial_deformation = [[1, 0, 0], [0, 1], [0, 0, 1]]"), 6,
                 "body[0].initial_deformation[1]", "has 2 elements"));
  EXPECT_TRUE(fails_with(minimal("[[boundary]]\nbody = \"a\"\ngroup = \"all\"\nvalue = [1, 2]\n"), 15,
                         "boundary[0].value", "has 2 elements"));
}

TEST(ScenarioErrors, NonFiniteNumbers) {
  EXPECT_TRUE(fails_with(replace_line(minimal(), 7, "young = inf"), 7, "body[0].material.young", "inf is not finite"));
  EXPECT_TRUE(fails_with(replace_line(minimal(), 3, "end = nan"), 3, "time.end", "nan is not finite"));
  EXPECT_TRUE(fails_with(minimal("[loads]\ngravity = [0, 0, -inf]\n"), 13, "loads.gravity[2]", "-inf is not finite"));
}

TEST(ScenarioErrors, DuplicateBodyNames) {
  EXPECT_TRUE(fails_with(minimal(cases::kBodyHead) + "file = \"meshes/cube.msh\"\n", 13, "body[1].name",
                         "duplicate body name 'a' (expected a name not used by body[0])"));
}

TEST(ScenarioErrors, EmptyBodyName) {
  EXPECT_TRUE(fails_with(replace_line(minimal(), 5, "name = \"\""), 5, "body[0].name", "is empty"));
}

TEST(ScenarioErrors, BodyNameTheOutputsCannotCarry) {
  // history.csv's header (L_x:NAME), the "body:group" syntax of contact
  // surfaces and one-line messages limit what a name may hold (issue 11).
  const auto name = [](std::string_view line) { return replace_line(minimal(), 5, line); };
  EXPECT_TRUE(fails_with(name("name = \"big, cube\""), 5, "body[0].name", "'big, cube' contains ',' (a comma)"));
  EXPECT_TRUE(fails_with(name("name = 'say \"hi\"'"), 5, "body[0].name", "contains '\"' (a double quote)"));
  EXPECT_TRUE(fails_with(name("name = \"ball:outer\""), 5, "body[0].name", "'ball:outer' contains ':' (a colon)"));
  EXPECT_TRUE(fails_with(name("name = \"two\\nlines\""), 5, "body[0].name", "contains U+000A (a control character)"));
  EXPECT_TRUE(fails_with(name("name = \"tab\\tbed\""), 5, "body[0].name", "contains U+0009 (a control character)"));
  EXPECT_TRUE(fails_with(name("name = \"del\\u007f\""), 5, "body[0].name", "contains U+007F (a control character)"));
  EXPECT_TRUE(fails_with(name("name = \" ball\""), 5, "body[0].name", "' ball' starts with a space"));
  EXPECT_TRUE(fails_with(name("name = \"ball \""), 5, "body[0].name", "'ball ' ends with a space"));
  EXPECT_NO_THROW(parse_scenario(name("name = \"Kugel (hohl) #2\""), case_file()));
}

TEST(ScenarioErrors, GroupNameTheOutputsCannotCarry) {
  EXPECT_TRUE(fails_with(minimal("[[boundary]]\nbody = \"a\"\ngroup = \"top,side\"\n"), 14, "boundary[0].group",
                         "'top,side' contains ',' (a comma)"));
  EXPECT_TRUE(fails_with(minimal("[[contact]]\nslave = \"a:top\\r\"\nmaster = \"a\"\nkind = \"stick\"\n"), 13,
                         "contact[0].slave", "contains U+000D (a control character)"));
  EXPECT_TRUE(fails_with(minimal("[[contact]]\nslave = \"a:top\"\nmaster = \"a:x:y\"\nkind = \"stick\"\n"), 14,
                         "contact[0].master", "group 'x:y' contains ':' (a colon)"));
}

TEST(ScenarioErrors, ZeroBodies) {
  EXPECT_TRUE(fails_with(std::string(cases::kTime), 1, "body", "missing key (expected one or more [[body]] tables)"));
  EXPECT_TRUE(fails_with(std::string(cases::kTime) + "[output]\nvtu_every = 1\n", 1, "body", "missing key"));
  EXPECT_TRUE(fails_with("body = []\n" + std::string(cases::kTime), 1, "body", "is empty"));
  EXPECT_TRUE(fails_with(std::string(cases::kTime) + "[body]\nname = \"a\"\n", 4, "body",
                         "got a table (expected one or more [[body]] tables)"));
}

TEST(ScenarioErrors, BoundaryNamesUnknownBody) {
  EXPECT_TRUE(fails_with(minimal("[[boundary]]\nbody = \"b\"\ngroup = \"all\"\n"), 13, "boundary[0].body",
                         "unknown body 'b' (expected one of: a)"));
}

TEST(ScenarioErrors, BoundaryComponents) {
  const auto boundary = [](std::string_view components) {
    return minimal("[[boundary]]\nbody = \"a\"\ngroup = \"all\"\ncomponents = " + std::string(components) + "\n");
  };
  EXPECT_TRUE(fails_with(boundary("[]"), 15, "boundary[0].components", "is empty"));
  EXPECT_TRUE(fails_with(boundary("[\"x\", \"x\"]"), 15, "boundary[0].components[1]", "'x' is repeated"));
  EXPECT_TRUE(fails_with(boundary("[\"w\"]"), 15, "boundary[0].components[0]", "'w' is not a component in 3D"));
  EXPECT_TRUE(fails_with(boundary("[0]"), 15, "boundary[0].components[0]", "got an integer"));
  EXPECT_TRUE(fails_with(boundary("\"x\""), 15, "boundary[0].components", "got a string"));
}

TEST(ScenarioErrors, ZComponentIn2d) {
  const auto text = with_mesh("generator = \"disc\"\nradius = 1\nsize = 0.1\n",
                              "[[boundary]]\nbody = \"a\"\ngroup = \"all\"\ncomponents = [\"z\"]\n");
  EXPECT_TRUE(fails_with("dimension = 2\n" + text, 18, "boundary[0].components[0]", "'z' is not a component in 2D"));
}

TEST(ScenarioErrors, EmptyBoundaryGroup) {
  EXPECT_TRUE(fails_with(minimal("[[boundary]]\nbody = \"a\"\ngroup = \"\"\n"), 14, "boundary[0].group", "is empty"));
}

TEST(ScenarioErrors, MeshFileAndGeneratorBothOrNeither) {
  EXPECT_TRUE(fails_with(minimal("generator = \"box\"\n"), 10, "body[0].mesh",
                         "has both 'file' and 'generator' (expected exactly one of them)"));
  EXPECT_TRUE(fails_with(with_mesh(""), 10, "body[0].mesh", "has neither 'file' nor 'generator'"));
  EXPECT_TRUE(fails_with(with_mesh("group = \"x\"\n"), 10, "body[0].mesh", "has neither"));
}

TEST(ScenarioErrors, UnknownGenerator) {
  EXPECT_TRUE(fails_with(with_mesh("generator = \"teapot\"\n"), 11, "body[0].mesh.generator",
                         "unknown generator 'teapot' (expected one of: "));
}

TEST(ScenarioErrors, GeneratorOfWrongDimension) {
  EXPECT_TRUE(fails_with(with_mesh("generator = \"disc\"\nradius = 1\nsize = 0.1\n"), 11, "body[0].mesh.generator",
                         "generator 'disc' makes 2D meshes but dimension = 3 (expected a 3D generator, one of: "));
  EXPECT_TRUE(fails_with("dimension = 2\n" + with_mesh("generator = \"box\"\nlx = 1\nly = 1\nlz = 1\nsize = 1\n"), 12,
                         "body[0].mesh.generator", "makes 3D meshes but dimension = 2"));
}

TEST(ScenarioErrors, GeneratorParameters) {
  const auto box = [](std::string_view rest) {
    return with_mesh("generator = \"box\"\nlx = 1\nly = 1\n" + std::string(rest));
  };
  EXPECT_TRUE(fails_with(box("lz = 1\nsize = 1\nradius = 2\n"), 16, "body[0].mesh.radius",
                         "unknown parameter 'radius' of generator 'box' (expected one of: lx, ly, lz, size)"));
  EXPECT_TRUE(fails_with(box("size = 1\n"), 10, "body[0].mesh.lz",
                         "missing parameter of generator 'box' (expected a number [m]"));
  EXPECT_TRUE(fails_with(box("lz = \"1\"\nsize = 1\n"), 14, "body[0].mesh.lz", "got a string (expected a number [m]"));
  EXPECT_TRUE(fails_with(box("lz = nan\nsize = 1\n"), 14, "body[0].mesh.lz", "nan is not finite"));
  EXPECT_TRUE(
      fails_with(box("lz = 1\nsize = 1\ngroup = \"body\"\n"), 16, "body[0].mesh.group", "is only allowed with 'file'"));
}

TEST(ScenarioErrors, MeshFileMissingNamesResolvedPath) {
  const auto resolved = std::filesystem::absolute(cases::scenario_dir() + "/missing.msh").lexically_normal().string();
  EXPECT_TRUE(fails_with(with_mesh("file = \"missing.msh\"\n"), 11, "body[0].mesh.file",
                         "mesh file '" + resolved + "' does not exist"));
}

TEST(ScenarioErrors, ThicknessOnlyIn2d) {
  EXPECT_TRUE(fails_with(replace_line(minimal(), 5, "name = \"a\"\nthickness = 0.1"), 6, "body[0].thickness",
                         "is only meaningful in 2D"));
  const auto two_d = "dimension = 2\n" + with_mesh("generator = \"disc\"\nradius = 1\nsize = 0.1\n");
  EXPECT_TRUE(
      fails_with(replace_line(two_d, 6, "name = \"a\"\nthickness = 0"), 7, "body[0].thickness", "out of range"));
}

TEST(ScenarioErrors, AngularVelocityShape) {
  EXPECT_TRUE(fails_with(replace_line(minimal(), 5, "name = \"a\"\nangular_velocity = 2"), 6,
                         "body[0].angular_velocity", "got an integer (expected an array of 3 numbers [rad/s])"));
  const auto two_d = "dimension = 2\n" + with_mesh("generator = \"disc\"\nradius = 1\nsize = 0.1\n");
  EXPECT_TRUE(fails_with(replace_line(two_d, 6, "name = \"a\"\nangular_velocity = [0, 0, 2]"), 7,
                         "body[0].angular_velocity",
                         "got an array (expected one number [rad/s], the rotation about z in 2D)"));
}

TEST(ScenarioErrors, InitialDeformationMustHavePositiveDeterminant) {
  EXPECT_TRUE(
      fails_with(replace_line(minimal(), 5, "name = \"a\"\ninitial_deformation = [[1, 0, 0], [0, -1, 0], [0, 0, 1]]"),
                 6, "body[0].initial_deformation", "det F0 = -1 is not positive"));
  EXPECT_TRUE(
      fails_with(replace_line(minimal(), 5, "name = \"a\"\ninitial_deformation = [[1, 0, 0], [1, 0, 0], [0, 0, 1]]"), 6,
                 "body[0].initial_deformation", "is not positive"));
}

TEST(ScenarioErrors, SecondBodyErrorsNameIndexOne) {
  auto text = minimal(cases::kBodyHead) + "file = \"meshes/cube.msh\"\n";
  text = replace_line(text, 13, "name = \"b\"");
  text = replace_line(text, 16, "poisson = 0.7");
  EXPECT_TRUE(fails_with(text, 16, "body[1].material.poisson", "0.7 is out of range"));
}

}  // namespace
}  // namespace conserve::io
