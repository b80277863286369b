/// `--set SECTION.KEY=VALUE` overrides (read_scenario): keys replaced and
/// added, TOML and bare values, the effective text, and one-line errors
/// that name the override.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "scenario_test_support.hpp"

namespace conserve::io {
namespace {

using cases::case_file;
using cases::minimal;

/// The InputError message of parsing `text` with `overrides` ("" if none).
std::string error_of(const std::string& text, const std::vector<std::string>& overrides) {
  try {
    parse_scenario(text, case_file(), overrides);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

/// A bad override, the start of the one-line message it gives and a part of it.
struct BadOverride {
  std::string item, starts, contains;
};

/// Each override of `cases`, given alone with `text`, fails with its message.
void expect_messages(const std::string& text, const std::vector<BadOverride>& cases) {
  for (const BadOverride& c : cases) {
    const std::string message = error_of(text, {c.item});
    EXPECT_EQ(message.rfind(c.starts, 0), 0u) << c.item << ": " << message;
    EXPECT_NE(message.find(c.contains), std::string::npos) << c.item << ": " << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

TEST(ScenarioOverrides, ReplaceAndAddKeys) {
  const std::string text = minimal();
  const Scenario plain = parse_scenario(text, case_file());
  ASSERT_EQ(plain.active_set.scheme, ContactScheme::persistent);
  ASSERT_TRUE(plain.active_set.locate_impacts);
  const Scenario s = parse_scenario(text, case_file(),
                                    {"time.end=0.2", "active_set.scheme=paper", "active_set.locate_impacts=true",
                                     "active_set.gap_tolerance=2e-3", "loads.gravity=[0, 0, -9.81]",
                                     "title=a bare string", "output.directory=\"out/x\""});
  EXPECT_EQ(s.time.end, 0.2);                                 // replaced
  EXPECT_EQ(s.time.step, plain.time.step);                    // kept
  EXPECT_EQ(s.active_set.scheme, ContactScheme::paper);  // table created
  EXPECT_TRUE(s.active_set.locate_impacts);
  EXPECT_EQ(s.active_set.gap_tolerance, 2e-3);
  EXPECT_EQ(s.gravity, Eigen::Vector3d(0, 0, -9.81));
  EXPECT_EQ(s.title, "a bare string");
  EXPECT_EQ(s.output.directory, std::filesystem::path("out/x"));
  // The last of two overrides of one key wins.
  EXPECT_EQ(parse_scenario(text, case_file(), {"time.end=0.3", "time.end=0.4"}).time.end, 0.4);
}

TEST(ScenarioOverrides, TextIsTheEffectiveScenario) {
  const std::string text = minimal();
  EXPECT_EQ(parse_scenario(text, case_file(), {}).text, text);  // no override: the file's bytes
  const Scenario s = parse_scenario(text, case_file(), {"time.end=0.2", "active_set.scheme=persistent"});
  EXPECT_EQ(s.text.rfind("# " + case_file() + " --set 'time.end=0.2' --set 'active_set.scheme=persistent'\n", 0), 0u)
      << s.text;
  // Read back without overrides, it is the same scenario.
  const Scenario again = parse_scenario(s.text, case_file());
  EXPECT_EQ(again.time.end, 0.2);
  EXPECT_EQ(again.time.step, s.time.step);
  EXPECT_EQ(again.active_set.scheme, ContactScheme::persistent);
  ASSERT_EQ(again.bodies.size(), s.bodies.size());
  EXPECT_EQ(again.bodies[0].name, s.bodies[0].name);
  EXPECT_EQ(again.bodies[0].material.density, s.bodies[0].material.density);
}

/// Two bodies and two contacts: [[...]] entries addressed by name or index.
std::string two_bodies() {
  return minimal(
      "[[body]]\nname = \"b\"\ntranslate = [2, 0, 0]\n[body.material]\nyoung = 2e6\npoisson = 0.3\n"
      "density = 1000\n[body.mesh]\nfile = \"meshes/cube.msh\"\n"
      "[[contact]]\nslave = \"a\"\nmaster = \"b\"\nkind = \"frictionless\"\n[[contact]]\nslave = \"b:top\"\nmaster = \"a:top\"\nkind = \"frictionless\"\n");
}

TEST(ScenarioOverrides, EntriesOfArraysOfTablesByNameOrIndex) {
  const std::string text = two_bodies();
  const Scenario s = parse_scenario(text, case_file(),
                                    {"body.b.material.young=1e7", "body.0.material.density=2000",
                                     "body.a.velocity=[1, 0, 0]", "contact.1.kind=stick", "body.b.mesh.group=cube"});
  EXPECT_EQ(s.bodies[0].material.parameter("young"), 1e6);  // not the named one
  EXPECT_EQ(s.bodies[1].material.parameter("young"), 1e7);
  EXPECT_EQ(s.bodies[0].material.density, 2000.0);
  EXPECT_EQ(s.bodies[0].velocity, Eigen::Vector3d(1, 0, 0));
  EXPECT_EQ(s.bodies[1].mesh.group, "cube");
  EXPECT_EQ(s.contacts[0].kind, ContactKind::frictionless);
  EXPECT_EQ(s.contacts[1].kind, ContactKind::stick);
  // The effective text reads back as the same scenario.
  const Scenario again = parse_scenario(s.text, case_file());
  EXPECT_EQ(again.bodies[1].material.parameter("young"), 1e7);
  EXPECT_EQ(again.contacts[1].kind, ContactKind::stick);
}

TEST(ScenarioOverrides, EntriesAreValidatedAsInTheFile) {
  const std::string text = two_bodies();
  const std::vector<BadOverride> cases = {
      {"body.c.material.young=1", "--set 'body.c.material.young=1': ", "no entry named 'c' (expected an index 0 to 1 or a name: 'a', 'b')"},
      {"contact.2.kind=stick", "--set 'contact.2.kind=stick': ", "no entry number 2"},
      {"body.b.material.young=-1", "--set body[1].material.young: ", "out of range"},
      {"body.b.material.yung=1", "--set body[1].material.yung: ", "unknown key"},
      {"contact.0.kind=glue", "--set contact[0].kind: ", "frictionless"},
      {"body.b=1", "--set 'body.b=1': ", "array of tables [[body]]"},
      {"body=1", "--set 'body=1': ", "array of tables [[body]]"},
  };
  expect_messages(text, cases);
}

TEST(ScenarioOverrides, BadOverridesFailWithOneLineNamingThem) {
  const std::string text = minimal();
  const std::vector<BadOverride> cases = {
      {"time", "--set 'time': ", "no '='"},
      {"time..end=1", "--set 'time..end=1': ", "not a key path"},
      {"=1", "--set '=1': ", "not a key path"},
      {"time.end=", "--set time.end: ", "got a string"},
      {"body.density=3", "--set 'body.density=3': ", "[[body]]"},
      {"time.step.x=1", "--set 'time.step.x=1': ", "time.step is a float, not a table"},
      {"title.x=1", "--set title: ", "got a table"},  // the table it creates
      {"active_set.scheme=persisten", "--set active_set.scheme: ", "paper, persistent"},
      {"active_set.locate_impacts=yes", "--set active_set.locate_impacts: ", "true or false"},
      {"active_set.shceme=persistent", "--set active_set.shceme: ", "unknown key"},
      {"time.end=-1", "--set time.end: ", "end ≥ step"},
      {"title=\"\"\"two\nlines\"\"\"", "--set: ", "line break"},
  };
  expect_messages(text, cases);
  // An error in the file itself still names the file and line.
  EXPECT_TRUE(cases::fails_with(minimal("[active_set]\nscheme = \"x\"\n"), 13, "active_set.scheme", "paper"));
  EXPECT_EQ(error_of(minimal("[active_set]\nscheme = \"x\"\n"), {"time.end=0.2"})
                .rfind(case_file() + ":13: active_set.scheme: ", 0),
            0u);
}

}  // namespace
}  // namespace conserve::io
