// A run can be traced to its input and its program (issue 11): the output
// folder holds a byte-identical copy of the scenario, and summary.json (read
// back with nlohmann-json) names the scenario and mesh files with their
// SHA-256, the program's version and commit, the start time and the host.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <ctime>
#include <nlohmann/json.hpp>
#include <regex>
#include <thread>

#include "support/cli.hpp"
#include "support/cube_scenario.hpp"

namespace conserve::test {
namespace {

namespace fs = std::filesystem;

/// kCubeScenario with a title that JSON must escape.
std::string titled_cube() {
  std::string s = kCubeScenario;
  return s.replace(0, s.find('\n'), R"(title = "a \"quoted\" \\ back\nslash")");
}

/// What a command prints on its standard output (first line), or "".
std::string first_line_of(const std::string& command) {
  std::FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return "";
  char buffer[512] = {};
  const bool got = std::fgets(buffer, sizeof buffer, pipe) != nullptr;
  pclose(pipe);
  std::string line = got ? buffer : "";
  if (!line.empty() && line.back() == '\n') line.pop_back();
  return line;
}

/// SHA-256 of a file by coreutils' sha256sum (an independent implementation).
std::string sha256sum(const fs::path& file) {
  const std::string line = first_line_of("sha256sum '" + file.string() + "'");
  return line.substr(0, line.find(' '));
}

/// Now as ISO-8601 UTC, to the second.
std::string utc_now() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&now, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return text;
}

TEST(Trace, OutputHasTheScenarioAndSummaryNamesInputsAndProgram) {
  const auto dir = scratch("trace_inputs");
  write_file(dir / "s.toml", titled_cube());
  write_file(dir / "cube.msh", cube_msh());
  const std::string before = utc_now();
  const CliResult r = run_cli("run s.toml -q -o out", dir);
  const std::string after = utc_now();
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(slurp(dir / "out/scenario.toml") == slurp(dir / "s.toml")) << "scenario.toml is not a copy";

  const auto j = nlohmann::json::parse(slurp(dir / "out/summary.json"));  // throws on invalid JSON
  EXPECT_EQ(j.at("title"), "a \"quoted\" \\ back\nslash");
  const auto& scenario = j.at("inputs").at("scenario");
  EXPECT_EQ(scenario.at("path"), fs::canonical(dir / "s.toml").string());
  EXPECT_EQ(scenario.at("sha256"), sha256sum(dir / "s.toml"));
  ASSERT_EQ(j.at("inputs").at("meshes").size(), 1u);
  const auto& mesh = j.at("inputs").at("meshes")[0];
  EXPECT_EQ(mesh.at("body"), "cube");
  EXPECT_EQ(mesh.at("path"), fs::canonical(dir / "cube.msh").string());
  EXPECT_EQ(mesh.at("sha256"), sha256sum(dir / "cube.msh"));
  EXPECT_EQ(sha256sum(dir / "cube.msh").size(), 64u);

  const auto& program = j.at("program");
  EXPECT_EQ(program.at("name"), "conserve");
  EXPECT_EQ(program.at("version"), CONSERVE_VERSION);
  const std::string commit = program.at("commit");
  EXPECT_TRUE(std::regex_match(commit, std::regex("[0-9a-f]{40}(-dirty)?|unknown"))) << commit;
  // In a checkout, the commit built is HEAD or (built, then committed) one of its ancestors.
  const std::string head = first_line_of("git -C '" CONSERVE_SOURCE_DIR "' rev-parse HEAD 2>/dev/null");
  if (head.size() == 40 && commit != "unknown") {
    const std::string ancestry = first_line_of("git -C '" CONSERVE_SOURCE_DIR "' merge-base --is-ancestor " +
                                               commit.substr(0, 40) + " HEAD && echo ancestor");
    EXPECT_EQ(ancestry, "ancestor") << commit << " is not HEAD (" << head << ") or before it";
  }
  const std::string started = j.at("started");
  EXPECT_TRUE(std::regex_match(started, std::regex("\\d{4}-\\d\\d-\\d\\dT\\d\\d:\\d\\d:\\d\\dZ"))) << started;
  EXPECT_LE(before, started);
  EXPECT_LE(started, after);
  EXPECT_EQ(j.at("host").at("cores"), std::thread::hardware_concurrency());
}

TEST(Trace, SummaryKeepsEveryEarlierKey) {
  // bench/make_table.py and the user guide read these.
  const auto dir = scratch("trace_keys");
  write_file(dir / "s.toml", titled_cube());
  write_file(dir / "cube.msh", cube_msh());
  ASSERT_EQ(run_cli("run s.toml -q -o out", dir).exit_code, 0);
  const auto j = nlohmann::json::parse(slurp(dir / "out/summary.json"));
  EXPECT_EQ(j.at("steps"), 3);
  EXPECT_GT(j.at("unknowns").get<int>(), 0);
  for (const char* key : {"wall_seconds", "mean_newton_iterations", "max_penetration", "min_dt"})
    EXPECT_TRUE(j.at(key).is_number()) << key;
  for (const char* key : {"max_newton_iterations", "activations", "releases", "linear_setups", "linear_solves",
                          "linear_iterations", "linear_fallbacks", "lu_first", "symbolic_analyses", "cutbacks"})
    EXPECT_TRUE(j.at(key).is_number_integer()) << key;
  EXPECT_TRUE(j.at("drift").at("E").is_number());
  EXPECT_TRUE(j.at("not_conserved").is_object());
  EXPECT_TRUE(j.at("linear_solver").is_string());
  for (const char* key : {"assembly", "elimination", "linear_setup", "linear_solve", "contact_search", "output"})
    EXPECT_TRUE(j.at("seconds").at(key).is_number()) << key;
  EXPECT_EQ(j.at("min_dt"), 0.01);
}

}  // namespace
}  // namespace conserve::test
