#pragma once
/// Running the conserve binary from tests and capturing what it prints.
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <string>

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

}  // namespace conserve::test
