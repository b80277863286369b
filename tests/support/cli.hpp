#pragma once
/// Running the conserve binary from tests and capturing what it prints.
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>

#include "support/files.hpp"

namespace conserve::test {

struct CliResult {
  int exit_code = -1;
  std::string out, err;
};

/// Runs `conserve ARGS` with the working directory `dir`.
inline CliResult run_cli(const std::string& args, const std::filesystem::path& dir) {
  const std::string cmd =
      "cd '" + dir.string() + "' && '" + std::string(CONSERVE_BINARY) + "' " + args + " > cli_out.txt 2> cli_err.txt";
  const int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(dir / "cli_out.txt"), slurp(dir / "cli_err.txt")};
}

/// Expects a refusal: exit code 1 and one line on stderr, "conserve:
/// error: …" containing `what`.
inline void expect_one_line_error(const CliResult& r, const std::string& what) {
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_THAT(r.err, ::testing::AllOf(::testing::StartsWith("conserve: error: "), ::testing::HasSubstr(what)))
      << r.err;
}

/// `text` with the first `from` replaced by `to` (expected to be there).
inline std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return at == std::string::npos ? text : text.replace(at, from.size(), to);
}

}  // namespace conserve::test
