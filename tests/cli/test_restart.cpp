// Checkpoint and restart (issue 7): a run stopped early and continued from
// a checkpoint writes the same history, byte for byte, as the run that was
// never interrupted; on a contact scenario, so that the active set is part
// of what the checkpoint must carry.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <set>

#include "support/cli.hpp"
#include "support/contact_scenarios.hpp"

namespace conserve::test {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

/// glancing_spheres(2, "frictionless", 0.05): contact from step 8 to 54,
/// releases at 47, 50 and 55; output and checkpoints added.
const std::string kGlancingDiscs =
    glancing_spheres(2, "frictionless", 0.05) + "[output]\nvtu_every = 20\ncheckpoint_every = 10\n";

/// ball_on_plane("stick", 0.12): the first slave sticks at step 64, a
/// second at 89.
const std::string kBallOnPlane =
    ball_on_plane("stick", 0.12) + "[output]\nvtu_every = 0\ncheckpoint_every = 25\n";

/// Runs `scenario` once uninterrupted and once stopped after `stop` steps
/// and restarted from the checkpoint of step `from`; both histories and
/// steps.csv must be identical.
void expect_identical_after_restart(const std::string& name, const std::string& scenario, int stop, int from) {
  const auto dir = scratch(name);
  write_file(dir / "s.toml", scenario);
  const CliResult full = run_cli("run s.toml -q -o full", dir);
  ASSERT_EQ(full.exit_code, 0) << full.err;
  const CliResult part = run_cli("run s.toml -q -o part --steps " + std::to_string(stop), dir);
  ASSERT_EQ(part.exit_code, 0) << part.err;
  const std::string ckpt =
      "part/checkpoints/ckpt_" + std::string(6 - std::to_string(from).size(), '0') + std::to_string(from) + ".bin";
  ASSERT_TRUE(fs::exists(dir / ckpt)) << ckpt;
  EXPECT_NE(slurp(dir / "full/history.csv"), slurp(dir / "part/history.csv"));
  const CliResult rest = run_cli("run s.toml -q -o part --restart " + ckpt, dir);
  ASSERT_EQ(rest.exit_code, 0) << rest.err;
  EXPECT_TRUE(slurp(dir / "full/history.csv") == slurp(dir / "part/history.csv")) << "history.csv differs";
  EXPECT_TRUE(slurp(dir / "full/steps.csv") == slurp(dir / "part/steps.csv")) << "steps.csv differs";
  if (fs::exists(dir / "full/solution.pvd"))  // the time series keeps the entries from before the restart
    EXPECT_EQ(slurp(dir / "full/solution.pvd"), slurp(dir / "part/solution.pvd"));
  for (const auto& f : fs::recursive_directory_iterator(dir / "part"))
    EXPECT_NE(f.path().extension(), ".tmp") << f.path();
}

TEST(Restart, FrictionlessContactHistoryIsBitIdentical) {
  // Checkpoint 30 has three slaves in contact, released after the restart.
  expect_identical_after_restart("restart_discs", kGlancingDiscs, 35, 30);
}

TEST(Restart, StickContactHistoryIsBitIdentical) {
  // Checkpoint 75 has one stuck slave; another sticks after the restart.
  expect_identical_after_restart("restart_ball", kBallOnPlane, 80, 75);
}

TEST(Restart, RefusesACheckpointOfAnotherScenario) {
  const auto dir = scratch("restart_other");
  write_file(dir / "s.toml", kGlancingDiscs);
  std::string other = kGlancingDiscs;
  other.replace(other.find("young = 1.0e6"), 13, "young = 2.0e6");
  write_file(dir / "other.toml", other);
  ASSERT_EQ(run_cli("run s.toml -q -o a --steps 10", dir).exit_code, 0);
  const CliResult r = run_cli("run other.toml -q -o b --restart a/checkpoints/ckpt_000010.bin", dir);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_THAT(r.err, HasSubstr("ckpt_000010.bin: bad checkpoint: written by another scenario"));
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

TEST(Restart, RefusesATruncatedCheckpoint) {
  const auto dir = scratch("restart_truncated");
  write_file(dir / "s.toml", kGlancingDiscs);
  ASSERT_EQ(run_cli("run s.toml -q -o a --steps 10", dir).exit_code, 0);
  const std::string bytes = slurp(dir / "a/checkpoints/ckpt_000010.bin");
  write_file(dir / "cut.bin", bytes.substr(0, bytes.size() / 2));
  const CliResult r = run_cli("run s.toml -q -o a --restart cut.bin", dir);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_THAT(r.err, HasSubstr("cut.bin: bad checkpoint"));
}

/// The checkpoint files in DIR/checkpoints, by name.
std::set<std::string> checkpoint_files(const fs::path& dir) {
  std::set<std::string> names;
  for (const auto& f : fs::directory_iterator(dir / "checkpoints")) names.insert(f.path().filename().string());
  return names;
}

TEST(Restart, KeepsOnlyTheNewestCheckpoints) {
  const auto dir = scratch("restart_keep");
  write_file(dir / "two.toml", kGlancingDiscs + "checkpoint_keep = 2\n");
  write_file(dir / "all.toml", kGlancingDiscs + "checkpoint_keep = 0\n");
  ASSERT_EQ(run_cli("run two.toml -q -o two --steps 45", dir).exit_code, 0);
  EXPECT_EQ(checkpoint_files(dir / "two"), (std::set<std::string>{"ckpt_000030.bin", "ckpt_000040.bin"}));
  ASSERT_EQ(run_cli("run all.toml -q -o all --steps 45", dir).exit_code, 0);
  EXPECT_EQ(checkpoint_files(dir / "all").size(), 4u);
  // A restart from an older checkpoint prunes those before the step it
  // reaches but leaves the later ones of the earlier run alone; an
  // unrelated file in the folder is never touched.
  write_file(dir / "two/checkpoints/notes.txt", "mine");
  ASSERT_EQ(run_cli("run two.toml -q -o two --steps 5 --restart two/checkpoints/ckpt_000030.bin", dir).exit_code, 0);
  EXPECT_EQ(checkpoint_files(dir / "two"),
            (std::set<std::string>{"ckpt_000030.bin", "ckpt_000040.bin", "notes.txt"}));
  ASSERT_EQ(run_cli("run two.toml -q -o two --steps 20 --restart two/checkpoints/ckpt_000030.bin", dir).exit_code, 0);
  EXPECT_EQ(checkpoint_files(dir / "two"),
            (std::set<std::string>{"ckpt_000040.bin", "ckpt_000050.bin", "notes.txt"}));
}

}  // namespace
}  // namespace conserve::test
