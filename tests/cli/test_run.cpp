// The program end to end: a run writes its history and ParaView files, the
// whole pipeline conserves, and every example scenario runs (shortened).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>

#include "io/history_writer.hpp"
#include "support/cli.hpp"
#include "support/files.hpp"

namespace conserve::test {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

const std::string kSpinningBox = R"(title = "spinning, deformed box"
dimension = 3
[time]
step = 0.01
end = 0.4
[output]
vtu_every = 10
[[body]]
name = "box"
velocity = [1.0, 0.5, 0.0]
angular_velocity = [0.5, 1.0, 3.0]
initial_deformation = [[1.1, 0.05, 0.0], [0.0, 0.95, 0.0], [0.0, 0.0, 1.0]]
[body.material]
young = 5.0e4
poisson = 0.3
density = 1000.0
[body.mesh]
generator = "box"
lx = 1.0
ly = 0.4
lz = 0.3
size = 0.2
)";

/// `--set SECTION.KEY=VALUE` changes the run without editing the file: the
/// run follows the override, and the output's scenario.toml is the
/// effective scenario, which runs to the same history. A bad override is
/// one line, exit code 1, and nothing written.
TEST(Run, SetOverridesAKeyAndTheOutputKeepsTheEffectiveScenario) {
  const auto dir = scratch("run_set");
  write_file(dir / "box.toml", kSpinningBox);
  const CliResult r = run_cli("run box.toml -o result -q --set time.end=0.1 --set 'time.mass=\"lumped\"'", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("finished 10 steps"));
  const std::string effective = slurp(dir / "result/scenario.toml");
  EXPECT_THAT(effective, HasSubstr("--set 'time.end=0.1' --set 'time.mass=\"lumped\"'"));
  EXPECT_THAT(effective, HasSubstr("mass = 'lumped'"));
  const CliResult again = run_cli("run result/scenario.toml -o again -q", dir);
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(slurp(dir / "again/history.csv"), slurp(dir / "result/history.csv"));
  const CliResult plain = run_cli("run box.toml -o plain -q --steps 10", dir);
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  EXPECT_NE(slurp(dir / "plain/history.csv"), slurp(dir / "result/history.csv"));  // the mass was lumped

  for (const std::string& bad : {"--set time.mass=diagonal", "--set time.end", "--set body.size=0.1"}) {
    const CliResult b = run_cli("run box.toml -o bad -q " + bad, dir);
    EXPECT_EQ(b.exit_code, 1) << bad;
    EXPECT_EQ(std::count(b.err.begin(), b.err.end(), '\n'), 1) << b.err;
    EXPECT_THAT(b.err, HasSubstr("conserve: error: --set ")) << b.err;
    EXPECT_FALSE(fs::exists(dir / "bad")) << bad;
  }
}

TEST(Run, WritesHistoryAndParaViewFilesAndConserves) {
  const auto dir = scratch("run_box");
  write_file(dir / "box.toml", kSpinningBox);
  const CliResult r = run_cli("run box.toml -o result -q", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("finished 40 steps"));
  const io::History h = io::read_history(dir / "result/history.csv");
  ASSERT_EQ(h.rows.size(), 41u);
  const auto E = h.column("total");
  const auto Jz = h.column("J_z");
  double drift = 0.0, j_drift = 0.0;
  for (std::size_t i = 0; i < E.size(); ++i) {
    drift = std::max(drift, std::abs(E[i] - E[0]) / std::abs(E[0]));
    j_drift = std::max(j_drift, std::abs(Jz[i] - Jz[0]) / std::abs(Jz[0]));
  }
  std::printf("[ measured ] pipeline run: relative drift E %.2e, J_z %.2e\n", drift, j_drift);
  EXPECT_LT(drift, 1e-10);
  EXPECT_LT(j_drift, 1e-10);
  EXPECT_GT(h.column("newton_iterations")[1], 0.0);
  for (const char* f : {"step_000000.vtu", "step_000010.vtu", "step_000040.vtu"})
    EXPECT_TRUE(fs::exists(dir / "result/vtu" / f)) << f;
  const std::string pvd = slurp(dir / "result/solution.pvd");
  EXPECT_THAT(pvd, HasSubstr("vtu/step_000040.vtu"));
  EXPECT_THAT(slurp(dir / "result/vtu/step_000040.vtu"),
              HasSubstr("Name=\"stress\" ComponentName0=\"xx\" ComponentName1=\"yy\" ComponentName2=\"zz\" "
                        "ComponentName3=\"xy\" ComponentName4=\"yz\" ComponentName5=\"xz\""));
}

TEST(Run, ProgressLineWhenNotQuiet) {
  const auto dir = scratch("run_progress");
  write_file(dir / "box.toml", kSpinningBox);
  const CliResult r = run_cli("run box.toml -o result --steps 3", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.err, HasSubstr("step 3/3"));
  EXPECT_THAT(r.err, HasSubstr("ETA"));
}

/// kSpinningBox with `[time]` replaced by step = `step`, end = `end`.
std::string spinning_box_until(const std::string& step, const std::string& end) {
  std::string s = kSpinningBox;
  s.replace(s.find("step = 0.01\nend = 0.4"), 21, "step = " + step + "\nend = " + end);
  return s;
}

TEST(Check, CountsStepsBeyond32Bits) {
  // end / step = 3e9 > 2^31: the count must not wrap around (issue 11).
  const auto dir = scratch("check_many_steps");
  write_file(dir / "long.toml", spinning_box_until("0.001", "3.0e6"));
  const CliResult r = run_cli("check long.toml", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr(", 3000000000 steps\n"));
}

TEST(Check, RefusesMoreStepsThanTheHistoryCanNumber) {
  // history.csv holds the step number as a double: exact up to 2^53.
  const auto dir = scratch("check_too_many_steps");
  write_file(dir / "endless.toml", spinning_box_until("1e-9", "1e9"));
  const CliResult r = run_cli("check endless.toml", dir);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_THAT(r.err, HasSubstr("endless.toml:5: time.end: 1e+18 steps"));
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

TEST(Run, StepLimitBeyond32BitsIsAccepted) {
  const auto dir = scratch("run_steps_limit");
  write_file(dir / "box.toml", kSpinningBox);
  const CliResult r = run_cli("run box.toml -o result -q --steps 3000000000", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("finished 40 steps"));
}

// Every scenario under examples/ runs a few steps (a smoke test).
TEST(Examples, EveryExampleRunsShortened) {
  int count = 0;
  for (const auto& entry : fs::recursive_directory_iterator(fs::path(CONSERVE_SOURCE_DIR) / "examples")) {
    if (entry.path().extension() != ".toml") continue;
    const auto dir = scratch("example_" + entry.path().stem().string());
    const CliResult r = run_cli("run '" + entry.path().string() + "' -o result -q --steps 3", dir);
    EXPECT_EQ(r.exit_code, 0) << entry.path() << ": " << r.err;
    EXPECT_TRUE(fs::exists(dir / "result/history.csv")) << entry.path();
    ++count;
  }
  EXPECT_GT(count, 0);
}

}  // namespace
}  // namespace conserve::test
