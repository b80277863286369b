// Plausibility warnings (issue 44): valid input that is likely a slip is
// run, but `check` and `run` say so first, naming the key and the figure:
// an impact faster than 0.3 of the wave speed (young = 2.0, an MPa slip),
// a density no solid has (1.1, a g/cm³ slip), a mesh size larger than the
// body. Every example and benchmark scenario checks without a warning.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "support/cli.hpp"
#include "support/files.hpp"

namespace conserve::test {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

/// A 0.3 m sphere (radius) at 2 m/s dropped onto a rigid plane under gravity.
const std::string kSphereOnPlane = R"(title = "a sphere dropped on a plane"
[time]
step = 0.001
end = 0.5
[loads]
gravity = [0.0, 0.0, -9.81]
[[body]]
name = "sphere"
translate = [0.0, 0.0, 0.5]
velocity = [0.0, 0.0, -2.0]
[body.material]
young = 1.0e6
poisson = 0.3
density = 1100.0
[body.mesh]
generator = "sphere"
radius = 0.3
size = 0.1
[[body]]
name = "plane"
rigid = true
[body.mesh]
generator = "square"
lx = 2.0
ly = 2.0
size = 0.25
[[contact]]
slave = "sphere:surface"
master = "plane:surface"
kind = "stick"
)";

/// The 1-based line of `text` that starts with `start`.
int line_of(const std::string& text, const std::string& start) {
  int line = 1;
  for (std::size_t at = 0; at != std::string::npos && at < text.size(); at = text.find('\n', at), ++line) {
    if (at > 0) ++at;
    if (text.compare(at, start.size(), start) == 0) return line;
  }
  return -1;
}

CliResult check(const std::string& name, const std::string& scenario, const std::string& command = "check s.toml") {
  const auto dir = scratch(name);
  write_file(dir / "s.toml", scenario);
  return run_cli(command, dir);
}

/// `check` of `scenario` exits 0 and warns exactly once, at `key` on the
/// line starting with `line_start`, with `contains`.
void expect_one_warning(const std::string& name, const std::string& scenario, const std::string& line_start,
                        const std::string& key, const std::string& contains) {
  const CliResult r = check(name, scenario);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_THAT(r.err, HasSubstr("conserve: warning: s.toml:" + std::to_string(line_of(scenario, line_start)) + ": " +
                               key + ": "));
  EXPECT_THAT(r.err, HasSubstr(contains));
  EXPECT_THAT(r.out, HasSubstr("valid."));
}

TEST(Warnings, FireOnTheThreeSlipsAndNamePlusFigure) {
  const CliResult plain = check("warnings_plain", kSphereOnPlane);
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  EXPECT_EQ(plain.err, "");

  const std::string soft = replaced(kSphereOnPlane, "young = 1.0e6", "young = 2.0");
  expect_one_warning("warnings_young", soft, "young = 2.0", "body[0].material.young",
                     "times its wave speed sqrt(E / density) = 0.0426 m/s");
  const std::string light = replaced(kSphereOnPlane, "density = 1100.0", "density = 1.1");
  expect_one_warning("warnings_density", light, "density = 1.1", "body[0].material.density",
                     "1.1 g/cm³ is 1100 kg/m³");
  const std::string coarse = replaced(kSphereOnPlane, "size = 0.1", "size = 5");
  expect_one_warning("warnings_size", coarse, "size = 5", "body[0].mesh.size",
                     "5 m is larger than the body it meshes (0.6 m across at most)");

  // run prints them too, before it starts, and still runs.
  const CliResult run = check("warnings_run", soft, "run s.toml -q --steps 0 -o out");
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_THAT(run.err, HasSubstr("conserve: warning: s.toml:"));
  EXPECT_THAT(run.err, HasSubstr("body[0].material.young"));
}

TEST(Warnings, EveryExampleAndBenchmarkIsSilent) {
  int checked = 0;
  for (const char* folder : {"examples", "bench"}) {
    for (const auto& e : fs::recursive_directory_iterator(fs::path(CONSERVE_SOURCE_DIR) / folder)) {
      if (e.path().extension() != ".toml") continue;
      const CliResult r = run_cli("check '" + e.path().string() + "'", scratch("warnings_examples"));
      EXPECT_EQ(r.exit_code, 0) << e.path() << ": " << r.err;
      EXPECT_EQ(r.err, "") << e.path();
      ++checked;
    }
  }
  EXPECT_GE(checked, 11);
}

}  // namespace
}  // namespace conserve::test
