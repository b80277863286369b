// The number of assembly threads changes no result: the peer cube (13 182
// cells, assembled in parallel) run for a few steps with OMP_NUM_THREADS=1
// and =2 writes the same history and steps.csv, byte for byte.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cstdlib>
#include <string>

#include "support/cli.hpp"

namespace conserve::test {
namespace {

/// Runs the cube for 5 steps into `out` with `threads` assembly threads.
CliResult run_cube(const std::filesystem::path& dir, const std::string& out, int threads) {
  setenv("OMP_NUM_THREADS", std::to_string(threads).c_str(), 1);
  return run_cli("run '" CONSERVE_SOURCE_DIR "/bench/cube/febio_cube.toml' -q --steps 5 -o " + out, dir);
}

TEST(Threads, HistoryIsBitIdenticalForOneAndTwoThreads) {
  const char* before = std::getenv("OMP_NUM_THREADS");
  const std::string saved = before ? before : "";
  const auto dir = scratch("threads_cube");
  const CliResult one = run_cube(dir, "one", 1);
  const CliResult two = run_cube(dir, "two", 2);
  if (before)
    setenv("OMP_NUM_THREADS", saved.c_str(), 1);
  else
    unsetenv("OMP_NUM_THREADS");
  ASSERT_EQ(one.exit_code, 0) << one.err;
  ASSERT_EQ(two.exit_code, 0) << two.err;
  ASSERT_FALSE(slurp(dir / "one/history.csv").empty());
  // Not vacuous: the second run did use two threads.
  EXPECT_EQ(nlohmann::json::parse(slurp(dir / "one/summary.json")).at("threads").at("most"), 1);
  EXPECT_EQ(nlohmann::json::parse(slurp(dir / "two/summary.json")).at("threads").at("most"), 2);
  EXPECT_TRUE(slurp(dir / "one/history.csv") == slurp(dir / "two/history.csv")) << "history.csv differs";
  EXPECT_TRUE(slurp(dir / "one/steps.csv") == slurp(dir / "two/steps.csv")) << "steps.csv differs";
}

}  // namespace
}  // namespace conserve::test
