/// summary.json's text: valid JSON whatever the strings and numbers hold
/// (issue 11), read back with nlohmann-json.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "simulation/summary.hpp"

namespace conserve::simulation {
namespace {

RunOrigin origin(const std::string& title) {
  return {.title = title,
          .started = "2026-11-21T10:00:00Z",
          .scenario = {.body = "", .path = "/tmp/s.toml", .sha256 = std::string(64, 'a')},
          .meshes = {{.body = "ball", .path = "/tmp/ball.msh", .sha256 = std::string(64, 'b')}}};
}

TEST(Summary, TitleWithQuotesBackslashesAndLineBreaksRoundTrips) {
  const std::string title = "a \"quoted\" \\ title\nover two lines\t\x01 and ünïcode";
  const auto j = nlohmann::json::parse(summary_json(RunSummary{}, 12, origin(title)));
  EXPECT_EQ(j.at("title"), title);
  EXPECT_EQ(j.at("inputs").at("scenario").at("path"), "/tmp/s.toml");
  EXPECT_EQ(j.at("inputs").at("meshes")[0].at("body"), "ball");
  EXPECT_EQ(j.at("inputs").at("meshes")[0].at("sha256"), std::string(64, 'b'));
  EXPECT_EQ(j.at("unknowns"), 12);
}

TEST(Summary, NonFiniteNumbersAreNull) {
  RunSummary s;
  s.conservation.present.fill(true);
  s.drift[0] = std::numeric_limits<double>::quiet_NaN();
  s.drift[2] = std::numeric_limits<double>::infinity();
  s.min_dt = -std::numeric_limits<double>::infinity();
  s.wall_seconds = 1.5;
  s.setup_seconds = 0.25;
  const std::string text = summary_json(s, 3, origin("t"));
  EXPECT_EQ(text.find("NaN"), std::string::npos) << text;
  EXPECT_EQ(text.find("nan"), std::string::npos) << text;
  EXPECT_EQ(text.find("inf"), std::string::npos) << text;
  const auto j = nlohmann::json::parse(text);
  EXPECT_TRUE(j.at("drift").at("E").is_null());
  EXPECT_TRUE(j.at("drift").at("L_y").is_null());
  EXPECT_EQ(j.at("drift").at("L_x"), 0.0);
  EXPECT_TRUE(j.at("min_dt").is_null());
  EXPECT_EQ(j.at("wall_seconds"), 1.5);
  EXPECT_EQ(j.at("setup_seconds"), 0.25);
  // The process's peak memory, and per unknown (3 here).
  const double peak = j.at("peak_memory_bytes");
  EXPECT_GT(peak, 1e6);
  EXPECT_EQ(j.at("bytes_per_unknown"), peak / 3);
}

TEST(Summary, StepsBeyondThirtyTwoBitsAndBadUtf8InAPath) {
  RunSummary s;
  s.steps = 3'000'000'000LL;
  RunOrigin o = origin("t");
  o.scenario.path = "/tmp/\xff\xfe.toml";  // a file name need not be UTF-8
  const auto j = nlohmann::json::parse(summary_json(s, 3, o));
  EXPECT_EQ(j.at("steps").get<std::int64_t>(), 3'000'000'000LL);
  EXPECT_EQ(j.at("inputs").at("scenario").at("path"), "/tmp/\xEF\xBF\xBD\xEF\xBF\xBD.toml");  // U+FFFD each
}

TEST(Summary, UtcTimestampIsIso8601) {
  EXPECT_EQ(utc_timestamp(std::chrono::system_clock::time_point{}), "1970-01-01T00:00:00Z");
  EXPECT_EQ(utc_timestamp(std::chrono::system_clock::time_point{std::chrono::seconds(1'800'000'000)}),
            "2027-01-15T08:00:00Z");
}

}  // namespace
}  // namespace conserve::simulation
