// The scenario files in examples/validation/ are the texts the tests run
// (validation_scenarios.hpp) with a comment block in front. This test fails
// when they drift apart; CONSERVE_WRITE_EXAMPLES=1 rewrites the files
// (keeping their comment blocks) instead.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "io/scenario.hpp"
#include "support/cli.hpp"
#include "validation_scenarios.hpp"

namespace conserve::test {
namespace {

namespace fs = std::filesystem;

/// The leading comment lines of a file (empty if none or no file).
std::string comment_block(const std::string& text) {
  std::istringstream in(text);
  std::string line, block;
  while (std::getline(in, line) && line.starts_with("#")) block += line + "\n";
  return block;
}

void check_example(const std::string& name, const std::string& scenario) {
  const fs::path file = fs::path(CONSERVE_SOURCE_DIR) / "examples" / "validation" / name;
  const std::string old = fs::exists(file) ? slurp(file) : std::string();
  const std::string wanted = comment_block(old) + scenario;
  const char* write = std::getenv("CONSERVE_WRITE_EXAMPLES");
  if (write != nullptr && std::string(write) == "1" && old != wanted) write_file(file, wanted);
  EXPECT_EQ(slurp(file), wanted) << name << " differs from the tested scenario; CONSERVE_WRITE_EXAMPLES=1 rewrites it";
  EXPECT_NO_THROW(io::read_scenario(file)) << name;
}

TEST(ValidationExamples, AreTheTestedScenarios) {
  Bars bars2;
  bars2.directory = "out/validation/bars_2d";
  check_example("bars_2d.toml", bars_scenario(bars2));
  Bars bars3;
  bars3.dimension = 3;
  bars3.size = 0.05;
  bars3.directory = "out/validation/bars_3d";
  check_example("bars_3d.toml", bars_scenario(bars3));
  Bars chain;
  chain.count = 3;
  chain.end = 7e-3;
  chain.directory = "out/validation/chain_2d";
  check_example("chain_2d.toml", bars_scenario(chain));
  Hertz hertz;
  hertz.size = 0.04;
  hertz.directory = "out/validation/hertz_2d";
  check_example("hertz_2d.toml", hertz_scenario(hertz));
}

}  // namespace
}  // namespace conserve::test
