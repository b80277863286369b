/// The declared key tables against docs/scenario.md and the struct defaults.
#include <gtest/gtest.h>

#include <algorithm>
#include <charconv>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "io/scenario.hpp"
#include "io/scenario_keys.hpp"
#include "scenario_test_support.hpp"

namespace conserve::io {
namespace {

std::string docs_text() {
  std::ifstream in(CONSERVE_SOURCE_DIR "/docs/scenario.md");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// The lines strictly between the marker lines "<!-- BEGIN name -->" and
/// "<!-- END name -->", without leading and trailing blank lines.
std::string generated_block(const std::string& docs, const std::string& name) {
  const auto begin_marker = "<!-- BEGIN " + name + " -->\n";
  const auto begin = docs.find(begin_marker);
  const auto end = docs.find("<!-- END " + name + " -->");
  if (begin == std::string::npos || end == std::string::npos || end < begin) return "(markers not found)";
  auto block = docs.substr(begin + begin_marker.size(), end - begin - begin_marker.size());
  block.erase(0, block.find_first_not_of('\n'));
  block.erase(block.find_last_not_of('\n') + 1);
  return block + "\n";
}

/// The one switch that regenerates the generated blocks of docs/scenario.md:
///   CONSERVE_REGENERATE_DOCS=1 ./build/release/tests/io/test_io --gtest_filter='ScenarioDocs.*'
/// Replaces the text between the markers of `name` with `block`.
void regenerate_if_asked(const std::string& name, const std::string& block) {
  if (!std::getenv("CONSERVE_REGENERATE_DOCS")) return;
  std::string docs = docs_text();
  const auto begin_marker = "<!-- BEGIN " + name + " -->\n";
  const auto begin = docs.find(begin_marker);
  const auto end = docs.find("<!-- END " + name + " -->");
  ASSERT_TRUE(begin != std::string::npos && end != std::string::npos && end > begin) << name;
  docs.replace(begin + begin_marker.size(), end - begin - begin_marker.size(), "\n" + block + "\n");
  std::ofstream(CONSERVE_SOURCE_DIR "/docs/scenario.md") << docs;
}

TEST(ScenarioDocs, EveryDeclaredKeyIsDocumented) {
  const auto docs = docs_text();
  ASSERT_FALSE(docs.empty()) << "docs/scenario.md is missing";
  for (const auto& section : scenario_sections()) {
    for (const auto& key : section.keys) {
      EXPECT_NE(docs.find("`" + std::string(key.name) + "`"), std::string::npos)
          << "key '" << key.name << "' of [" << section.name << "] is not in docs/scenario.md";
    }
  }
}

TEST(ScenarioDocs, KeyReferenceIsGeneratedFromTheKeyTables) {
  regenerate_if_asked("KEY REFERENCE", scenario_key_reference());
  EXPECT_EQ(generated_block(docs_text(), "KEY REFERENCE"), scenario_key_reference())
      << "regenerate: CONSERVE_REGENERATE_DOCS=1 ./build/release/tests/io/test_io --gtest_filter='ScenarioDocs.*'";
}

TEST(ScenarioDocs, GeneratorReferenceIsGeneratedFromTheCatalog) {
  regenerate_if_asked("GENERATOR REFERENCE", generator_reference());
  EXPECT_EQ(generated_block(docs_text(), "GENERATOR REFERENCE"), generator_reference())
      << "regenerate: CONSERVE_REGENERATE_DOCS=1 ./build/release/tests/io/test_io --gtest_filter='ScenarioDocs.*'";
}

TEST(ScenarioDocs, MaterialReferenceIsGeneratedFromTheCatalog) {
  regenerate_if_asked("MATERIAL REFERENCE", material_reference());
  EXPECT_EQ(generated_block(docs_text(), "MATERIAL REFERENCE"), material_reference())
      << "regenerate: CONSERVE_REGENERATE_DOCS=1 ./build/release/tests/io/test_io --gtest_filter='ScenarioDocs.*'";
}

TEST(ScenarioDocs, EveryTomlExampleParses) {
  const auto docs = docs_text();
  int examples = 0;
  for (auto begin = docs.find("```toml\n"); begin != std::string::npos; begin = docs.find("```toml\n", begin + 1)) {
    const auto end = docs.find("```\n", begin + 8);
    ASSERT_NE(end, std::string::npos);
    const auto example = docs.substr(begin + 8, end - begin - 8);
    EXPECT_NO_THROW(parse_scenario(example, CONSERVE_SOURCE_DIR "/docs/example.toml")) << example;
    ++examples;
  }
  EXPECT_GE(examples, 2);
}

TEST(ScenarioKeys, ScalarDefaultsAreValid) {
  for (const auto& section : scenario_sections()) {
    for (const auto& key : section.keys) {
      if (key.required || key.default_value.empty()) continue;  // none: "—" in the docs
      const auto text = key.default_value;
      if (key.type == KeyType::integer || key.type == KeyType::number) {
        double value = 0.0;
        const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
        EXPECT_TRUE(error == std::errc() && end == text.data() + text.size()) << key.name << " = " << text;
      }
      if (key.type == KeyType::boolean) {
        EXPECT_TRUE(text == "true" || text == "false") << key.name << " = " << text;
      }
      if (key.type == KeyType::choice) {
        EXPECT_NE(std::find(key.choices.begin(), key.choices.end(), text), key.choices.end()) << key.name;
      }
    }
  }
}

TEST(ScenarioKeys, EveryTableKeyHasASection) {
  for (const auto& section : scenario_sections()) {
    for (const auto& key : section.keys) {
      if (key.type != KeyType::table && key.type != KeyType::table_array) continue;
      const auto child =
          section.name.empty() ? std::string(key.name) : std::string(section.name) + "." + std::string(key.name);
      EXPECT_NO_THROW(scenario_section(child)) << child;
    }
  }
}

TEST(ScenarioKeys, DeclaredDefaultsEqualStructDefaults) {
  const auto s = parse_scenario(cases::minimal(), cases::case_file());
  const Scenario plain;
  EXPECT_EQ(s.dimension, plain.dimension);
  EXPECT_EQ(s.title, plain.title);
  EXPECT_EQ(s.time.scheme, plain.time.scheme);
  EXPECT_EQ(s.time.mass, plain.time.mass);
  EXPECT_EQ(s.newton.max_iterations, plain.newton.max_iterations);
  EXPECT_EQ(s.newton.residual_tolerance, plain.newton.residual_tolerance);
  EXPECT_EQ(s.output.directory, plain.output.directory);
  EXPECT_EQ(s.output.vtu_every, plain.output.vtu_every);
  EXPECT_EQ(s.output.progress_every, plain.output.progress_every);
  EXPECT_EQ(s.bodies.at(0).thickness, BodySpec{}.thickness);
  EXPECT_EQ(s.bodies.at(0).rigid, BodySpec{}.rigid);
  EXPECT_EQ(s.active_set.max_passes, plain.active_set.max_passes);
}

TEST(ScenarioKeys, DeclaredContactDefaultsEqualStructDefaults) {
  const auto s = parse_scenario(
      cases::minimal("[[contact]]\nslave = \"a:top\"\nmaster = \"a:bottom\"\nkind = \"stick\"\n"), cases::case_file());
  ASSERT_EQ(s.contacts.size(), 1u);
  EXPECT_EQ(s.contacts[0].depth_factor, ContactSpec{}.depth_factor);
}

}  // namespace
}  // namespace conserve::io
