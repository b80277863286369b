/// Errors found while the model is built (after the scenario parsed) name
/// the file, the line and the key they come from, as the parser's do
/// (issue 44): a mesh group, a contact surface, overlapping bodies, a
/// boundary group, a material whose scales overflow; "--set KEY" when the
/// key came from the command line.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/error.hpp"
#include "io/scenario.hpp"
#include "simulation/run.hpp"

namespace conserve::simulation {
namespace {

std::string file() { return CONSERVE_SOURCE_DIR "/tests/data/scenarios/case.toml"; }

/// Two boxes side by side: "a" from the test mesh (groups cube, top,
/// bottom), "b" generated, 2 m to the right; `a_mesh` and `b_extra` are
/// spliced in.
std::string two_boxes(const std::string& a_mesh = "", const std::string& b_extra = "", const std::string& rest = "") {
  return "[time]\nstep = 0.01\nend = 0.1\n"
         "[[body]]\nname = \"a\"\n[body.material]\nyoung = 1e6\npoisson = 0.3\ndensity = 1000\n"
         "[body.mesh]\nfile = \"meshes/cube.msh\"\n" +
         a_mesh +
         "[[body]]\nname = \"b\"\n" + b_extra +
         "[body.material]\nyoung = 1e6\npoisson = 0.3\ndensity = 1000\n"
         "[body.mesh]\ngenerator = \"box\"\nlx = 1.0\nly = 1.0\nlz = 1.0\nsize = 0.5\n" +
         rest;
}

/// The 1-based line of the first line of `text` that starts with `start`.
int line_of(const std::string& text, const std::string& start) {
  int line = 1;
  for (std::size_t at = 0; at < text.size(); at = text.find('\n', at) + 1, ++line) {
    if (text.compare(at, start.size(), start) == 0) return line;
    if (text.find('\n', at) == std::string::npos) break;
  }
  ADD_FAILURE() << "no line starts with " << start;
  return -1;
}

/// The message of the InputError that check() of `text` throws ("" if none).
std::string build_error(const std::string& text, const std::vector<std::string>& overrides = {}) {
  try {
    check(io::parse_scenario(text, file(), overrides));
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

void expect_located(const std::string& message, const std::string& prefix, const std::string& contains) {
  EXPECT_EQ(message.rfind(prefix, 0), 0u) << "message\n  " << message << "\ndoes not start with\n  " << prefix;
  EXPECT_NE(message.find(contains), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

/// "FILE:LINE: PATH" of the first line of `text` that starts with `start`.
std::string at(const std::string& text, const std::string& start, const std::string& path) {
  return file() + ":" + std::to_string(line_of(text, start)) + ": " + path;
}

const std::string kApart = "translate = [2.0, 0.0, 0.0]\n";

TEST(BuildErrors, NameTheFileTheLineAndTheKey) {
  ASSERT_EQ(build_error(two_boxes("", kApart)), "");  // the base case builds

  const std::string group = two_boxes("group = \"nowhere\"\n", kApart);
  expect_located(build_error(group), at(group, "group = ", "body[0].mesh.group (body 'a'): "), "nowhere");

  const std::string overlap = two_boxes("", "translate = [0.5, 0.0, 0.0]\n");
  expect_located(build_error(overlap), at(overlap, "translate = [0.5", "body[1].translate: "), "overlap at t = 0");

  const std::string surface = two_boxes("", kApart, "[[contact]]\nslave = \"a:nowhere\"\nmaster = \"b\"\nkind = \"frictionless\"\n");
  expect_located(build_error(surface), at(surface, "slave = ", "contact[0].slave: "), "nowhere");
  const std::string master = two_boxes("", kApart, "[[contact]]\nslave = \"a\"\nmaster = \"b:nowhere\"\nkind = \"frictionless\"\n");
  expect_located(build_error(master), at(master, "master = ", "contact[0].master: "), "nowhere");

  const std::string boundary = two_boxes("", kApart, "[[boundary]]\nbody = \"a\"\ngroup = \"nowhere\"\n");
  expect_located(build_error(boundary), at(boundary, "group = \"nowhere", "boundary[0].group: "), "nowhere");

  std::string stiff = two_boxes("", kApart);
  stiff.replace(stiff.find("young = 1e6"), 11, "young = 1e308");
  expect_located(build_error(stiff), at(stiff, "[body.material]", "body[0].material (body 'a'): "),
                 "material.young");
}

TEST(BuildErrors, NameTheOverrideOfAKeyGivenOnTheCommandLine) {
  const std::string text = two_boxes("", kApart);
  expect_located(build_error(text, {"body.b.translate=[0.5, 0.0, 0.0]"}), "--set body[1].translate: ",
                 "overlap at t = 0");
  expect_located(build_error(text, {"body.a.mesh.group=nowhere"}), "--set body[0].mesh.group (body 'a'): ",
                 "nowhere");
}

}  // namespace
}  // namespace conserve::simulation
