// Bad input gets one clear line naming the file and the key or line, and a
// non-zero exit code (issue 2, "what it must show" 4).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>

#include "support/cli.hpp"
#include "support/cube_scenario.hpp"

namespace conserve::test {
namespace {

using ::testing::HasSubstr;

const std::string& kGoodScenario = kCubeScenario;

/// Writes scenario.toml (and cube.msh) into a scratch folder, runs `check`.
CliResult check_with(const std::string& name, const std::string& scenario, const std::string& msh) {
  const auto dir = scratch(name);
  write_file(dir / "scenario.toml", scenario);
  write_file(dir / "cube.msh", msh);
  return run_cli("check scenario.toml", dir);
}

TEST(BadInput, GoodScenarioPassesCheck) {
  const CliResult r = check_with("good", kGoodScenario, cube_msh());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("valid"));
}

TEST(BadInput, MalformedScenario) {
  const CliResult r = check_with("malformed", replaced(kGoodScenario, "[time]", "[time"), cube_msh());
  expect_one_line_error(r, "scenario.toml:3");
}

TEST(BadInput, UnknownKey) {
  const CliResult r = check_with("unknown_key", replaced(kGoodScenario, "young = ", "youngs = "), cube_msh());
  expect_one_line_error(r, "scenario.toml:11");
  EXPECT_THAT(r.err, HasSubstr("youngs"));
}

TEST(BadInput, NegativeDensity) {
  const CliResult r =
      check_with("density", replaced(kGoodScenario, "density = 1000.0", "density = -1000.0"), cube_msh());
  expect_one_line_error(r, "scenario.toml:13");
  EXPECT_THAT(r.err, HasSubstr("density"));
}

TEST(BadInput, PoissonRatioAtLeastHalf) {
  const CliResult r = check_with("poisson", replaced(kGoodScenario, "poisson = 0.3", "poisson = 0.5"), cube_msh());
  expect_one_line_error(r, "scenario.toml:12");
  EXPECT_THAT(r.err, HasSubstr("poisson"));
}

TEST(BadInput, TruncatedMesh) {
  const std::string msh = cube_msh();
  const CliResult r = check_with("truncated", kGoodScenario, msh.substr(0, msh.size() * 2 / 3));
  expect_one_line_error(r, "cube.msh");
}

TEST(BadInput, InvertedElement) {
  // Swap two nodes of the first tetrahedron: "tag a b c d" -> "tag b a c d".
  std::string msh = cube_msh();
  const auto block = msh.find("\n", msh.find(" 4 ", msh.find("$Elements\n") + 10)) + 1;
  const auto eol = msh.find('\n', block);
  std::istringstream line(msh.substr(block, eol - block));
  long tag, a, b, c, d;
  line >> tag >> a >> b >> c >> d;
  msh.replace(block, eol - block,
              std::to_string(tag) + " " + std::to_string(b) + " " + std::to_string(a) + " " + std::to_string(c) + " " +
                  std::to_string(d) + " ");
  const CliResult r = check_with("inverted", kGoodScenario, msh);
  expect_one_line_error(r, "cube.msh");
  EXPECT_THAT(r.err, HasSubstr("inverted"));
}

TEST(BadInput, UnsupportedElementType) {
  // One 8-node hexahedron (type 5): conserve needs 4-node tetrahedra.
  const std::string hex = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$Entities
0 0 0 1
1 0 0 0 1 1 1 0 0
$EndEntities
$Nodes
1 8 1 8
3 1 0 8
1
2
3
4
5
6
7
8
0 0 0
1 0 0
1 1 0
0 1 0
0 0 1
1 0 1
1 1 1
0 1 1
$EndNodes
$Elements
1 1 1 1
3 1 5 1
1 1 2 3 4 5 6 7 8
$EndElements
)";
  const CliResult r = check_with("hex", kGoodScenario, hex);
  expect_one_line_error(r, "cube.msh:");
  EXPECT_THAT(r.err, HasSubstr("type 5"));
}

TEST(BadInput, MissingScenarioFile) {
  const auto dir = scratch("missing");
  const CliResult r = run_cli("check nowhere.toml", dir);
  expect_one_line_error(r, "nowhere.toml");
}

TEST(BadInput, BadCommandLine) {
  const auto dir = scratch("usage");
  EXPECT_EQ(run_cli("frobnicate", dir).exit_code, 2);
  EXPECT_EQ(run_cli("run", dir).exit_code, 2);
}

}  // namespace
}  // namespace conserve::test
