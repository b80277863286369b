#pragma once
/// Running the conserve binary from tests and capturing what it prints.
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace conserve::test {

struct CliResult {
  int exit_code = -1;
  std::string out, err;
};

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

inline void write_file(const std::filesystem::path& p, const std::string& text) {
  std::filesystem::create_directories(p.parent_path());
  std::ofstream(p, std::ios::binary) << text;
}

/// A fresh, empty scratch folder for one test.
inline std::filesystem::path scratch(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("conserve_test_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

/// Runs `conserve ARGS` with the working directory `dir`.
inline CliResult run_cli(const std::string& args, const std::filesystem::path& dir) {
  const std::string cmd =
      "cd '" + dir.string() + "' && '" + std::string(CONSERVE_BINARY) + "' " + args + " > cli_out.txt 2> cli_err.txt";
  const int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(dir / "cli_out.txt"), slurp(dir / "cli_err.txt")};
}

}  // namespace conserve::test
