// A run owns its output folder (issue 44): run again into a used folder,
// it leaves only its own files (the .pvd lists every frame in vtu/ and no
// other), keeps files that are not conserve's, and a restart drops the
// earlier run's frames and checkpoints after its step.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>

#include "support/cli.hpp"
#include "support/files.hpp"

namespace conserve::test {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

const std::string kBox = R"(title = "a spinning box"
[time]
step = 0.01
end = 1.0
[output]
vtu_every = 1
checkpoint_every = 2
checkpoint_keep = 0
[[body]]
name = "box"
angular_velocity = [0.0, 0.0, 3.0]
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

/// The names of the files in `dir` (not recursive).
std::set<std::string> files_in(const fs::path& dir) {
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_regular_file()) names.insert(e.path().filename().string());
  return names;
}

/// The frames solution.pvd lists, as "step_NNNNNN.vtu".
std::set<std::string> pvd_frames(const fs::path& out) {
  std::set<std::string> frames;
  const std::string pvd = slurp(out / "solution.pvd"), key = "file=\"vtu/";
  for (std::size_t at = pvd.find(key); at != std::string::npos; at = pvd.find(key, at + 1))
    frames.insert(pvd.substr(at + key.size(), pvd.find('"', at + key.size()) - at - key.size()));
  return frames;
}

std::size_t history_rows(const fs::path& out) {
  const std::string h = slurp(out / "history.csv");
  return static_cast<std::size_t>(std::count(h.begin(), h.end(), '\n')) - 1;
}

TEST(OutputFolder, ARunAgainIntoAUsedFolderLeavesOnlyItsOwnFiles) {
  const auto dir = scratch("output_folder_rerun");
  write_file(dir / "box.toml", kBox);
  ASSERT_EQ(run_cli("run box.toml -q -o out --steps 8", dir).exit_code, 0);
  ASSERT_EQ(files_in(dir / "out/vtu").size(), 9u);
  write_file(dir / "out/energy.png", "a plot of the earlier run");
  write_file(dir / "out/notes.txt", "the user's own file");

  const CliResult again = run_cli("run box.toml -o out --steps 3 --set output.checkpoint_every=0 -q", dir);
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_THAT(again.out, HasSubstr("files of an earlier run in that folder removed first"));
  EXPECT_EQ(files_in(dir / "out/vtu"), pvd_frames(dir / "out"));
  EXPECT_EQ(files_in(dir / "out/vtu").size(), 4u);  // steps 0 to 3
  EXPECT_TRUE(files_in(dir / "out/checkpoints").empty());
  EXPECT_EQ(history_rows(dir / "out"), 4u);
  EXPECT_FALSE(fs::exists(dir / "out/energy.png"));
  EXPECT_EQ(slurp(dir / "out/notes.txt"), "the user's own file");
}

TEST(OutputFolder, ARestartDropsTheEarlierRunsStepsAfterIt) {
  const auto dir = scratch("output_folder_restart");
  write_file(dir / "box.toml", kBox);
  ASSERT_EQ(run_cli("run box.toml -q -o out --steps 8", dir).exit_code, 0);
  ASSERT_EQ(files_in(dir / "out/checkpoints").size(), 4u);  // steps 2, 4, 6, 8
  const CliResult r = run_cli("run box.toml -q -o out --steps 1 --restart out/checkpoints/ckpt_000004.bin", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(files_in(dir / "out/vtu"), pvd_frames(dir / "out"));
  EXPECT_EQ(files_in(dir / "out/vtu").size(), 6u);  // steps 0 to 5
  EXPECT_EQ(files_in(dir / "out/checkpoints"), (std::set<std::string>{"ckpt_000002.bin", "ckpt_000004.bin"}));
  EXPECT_EQ(history_rows(dir / "out"), 6u);
}

/// Bad input changes nothing in the folder: the check comes first.
TEST(OutputFolder, BadInputLeavesAUsedFolderAsItWas) {
  const auto dir = scratch("output_folder_bad");
  write_file(dir / "box.toml", kBox);
  ASSERT_EQ(run_cli("run box.toml -q -o out --steps 2", dir).exit_code, 0);
  const std::set<std::string> before = files_in(dir / "out/vtu");
  const std::string history = slurp(dir / "out/history.csv");
  EXPECT_EQ(run_cli("run box.toml -q -o out --set body.box.material.young=-1", dir).exit_code, 1);
  EXPECT_EQ(files_in(dir / "out/vtu"), before);
  EXPECT_EQ(slurp(dir / "out/history.csv"), history);
}

}  // namespace
}  // namespace conserve::test
