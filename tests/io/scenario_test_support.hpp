#pragma once
/// Helpers shared by the scenario tests.
#include <gtest/gtest.h>

#include <string>
#include <string_view>

#include "core/error.hpp"
#include "io/scenario.hpp"

namespace conserve::io::cases {

/// Folder of the test scenarios (mesh files are resolved against it).
inline std::string scenario_dir() { return CONSERVE_SOURCE_DIR "/tests/data/scenarios"; }

/// The file name the parser is given for in-memory scenarios.
inline std::string case_file() { return scenario_dir() + "/case.toml"; }

/// [time] on lines 1–3.
inline constexpr std::string_view kTime = "[time]\nstep = 0.01\nend = 0.1\n";

/// A 3D [[body]] "a" up to its [body.mesh] header (lines 4–10 after kTime).
inline constexpr std::string_view kBodyHead =
    "[[body]]\nname = \"a\"\n[body.material]\nyoung = 1e6\npoisson = 0.3\ndensity = 1000\n[body.mesh]\n";

/// kTime + kBodyHead + `mesh` (from line 11) + `rest`.
inline std::string with_mesh(std::string_view mesh, std::string_view rest = "") {
  return std::string(kTime) + std::string(kBodyHead) + std::string(mesh) + std::string(rest);
}

/// A valid 3D scenario of 11 lines; `rest` starts on line 12.
inline std::string minimal(std::string_view rest = "") { return with_mesh("file = \"meshes/cube.msh\"\n", rest); }

/// Succeeds if parsing `text` throws one InputError line starting with
/// "case.toml path:LINE: KEY: " and containing `contains`.
inline ::testing::AssertionResult fails_with(std::string_view text, int line, std::string_view key,
                                             std::string_view contains) {
  try {
    parse_scenario(text, case_file());
  } catch (const InputError& e) {
    const std::string message = e.what();
    const std::string prefix = case_file() + ":" + std::to_string(line) + ": " + std::string(key) + ": ";
    if (message.rfind(prefix, 0) != 0) {
      return ::testing::AssertionFailure() << "message\n  " << message << "\ndoes not start with\n  " << prefix;
    }
    if (message.find(contains) == std::string::npos) {
      return ::testing::AssertionFailure() << "message\n  " << message << "\ndoes not contain\n  " << contains;
    }
    if (message.find('\n') != std::string::npos) {
      return ::testing::AssertionFailure() << "message has more than one line:\n" << message;
    }
    return ::testing::AssertionSuccess() << message;
  }
  return ::testing::AssertionFailure() << "no InputError";
}

}  // namespace conserve::io::cases
