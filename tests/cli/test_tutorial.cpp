// The tutorial in docs/user-guide.md ("Tutorial: your own part") run as
// written: between its <!-- tutorial --> markers, a fenced block whose info
// string names a file ("```toml drop.toml") is written to that file, and
// each line of a "```sh" block is run in order, in an empty folder with
// `conserve` on the PATH and the repository's scripts/ at hand.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "support/cli.hpp"

namespace conserve::test {
namespace {

namespace fs = std::filesystem;

struct Block {
  std::string info;  ///< "sh", "toml drop.toml", ...
  std::string text;
};

std::vector<Block> tutorial_blocks(const std::string& guide) {
  const auto begin = guide.find("<!-- tutorial -->"), end = guide.find("<!-- /tutorial -->");
  EXPECT_NE(begin, std::string::npos);
  EXPECT_NE(end, std::string::npos);
  std::istringstream in(guide.substr(begin, end - begin));
  std::vector<Block> blocks;
  bool inside = false;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("```", 0) == 0) {
      if (!inside) blocks.push_back({line.substr(3), {}});
      inside = !inside;
      continue;
    }
    if (inside) blocks.back().text += line + "\n";
  }
  EXPECT_FALSE(inside) << "an unclosed code block";
  return blocks;
}

TEST(Tutorial, RunsAsWritten) {
  const auto dir = scratch("tutorial");
  fs::create_directory_symlink(CONSERVE_SOURCE_DIR "/scripts", dir / "scripts");
  const std::string bin = fs::path(CONSERVE_BINARY).parent_path().string();
  int files = 0, commands = 0;
  for (const Block& b : tutorial_blocks(slurp(CONSERVE_SOURCE_DIR "/docs/user-guide.md"))) {
    const auto space = b.info.find(' ');
    if (space != std::string::npos) {  // a file
      write_file(dir / b.info.substr(space + 1), b.text);
      ++files;
      continue;
    }
    ASSERT_EQ(b.info, "sh") << "a block that is neither a file nor commands";
    std::istringstream lines(b.text);
    for (std::string line; std::getline(lines, line);) {
      if (line.empty() || line[0] == '#') continue;
      const std::string cmd = "cd '" + dir.string() + "' && PATH='" + bin + "':\"$PATH\" " + line +
                              " > step_out.txt 2> step_err.txt";
      const int status = std::system(cmd.c_str());
      ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0)
          << line << "\n" << slurp(dir / "step_out.txt") << slurp(dir / "step_err.txt");
      ++commands;
    }
  }
  EXPECT_EQ(files, 2);
  EXPECT_GE(commands, 5);
  const auto summary = nlohmann::json::parse(slurp(dir / "out/drop/summary.json"));
  std::printf("[ measured ] tutorial: %d steps, E drift %.2e, %d activations, %lld VTU frames of %.0f kB\n",
              summary.at("steps").get<int>(), summary.at("drift").at("E").get<double>(),
              summary.at("activations").get<int>(), summary.at("vtu_frames").get<long long>(),
              summary.at("vtu_bytes").get<double>() / 1e3 / summary.at("vtu_frames").get<double>());
  EXPECT_LT(summary.at("drift").at("E").get<double>(), 1e-10);
  EXPECT_GT(summary.at("activations").get<int>(), 0);  // it hit the floor
  for (const char* f : {"out/drop/solution.pvd", "out/drop/snapshots/snapshots.png", "out/drop/energy.png"})
    EXPECT_TRUE(fs::exists(dir / f)) << f;
}

}  // namespace
}  // namespace conserve::test
