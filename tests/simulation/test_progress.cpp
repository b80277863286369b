/// The progress line and its step arithmetic, also for runs of more than
/// 2^31 steps (issue 11).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>

#include "simulation/progress.hpp"

namespace conserve::simulation {
namespace {

using ::testing::HasSubstr;

constexpr std::int64_t kNoLimit = std::numeric_limits<std::int64_t>::max();

TEST(StepsLeft, ToTheEndTimeAtTheCurrentStepSize) {
  EXPECT_EQ(steps_left(0.5, 1.0, 0.1, 5, kNoLimit, false), 5);
  EXPECT_EQ(steps_left(0.55, 1.0, 0.1, 5, kNoLimit, false), 5);         // the last step overshoots
  EXPECT_EQ(steps_left(0.5, 1.0, 0.05, 5, kNoLimit, false), 10);        // after a cutback
  EXPECT_EQ(steps_left(1.0 - 1e-12, 1.0, 0.1, 5, kNoLimit, false), 1);  // at least one unless last
  EXPECT_EQ(steps_left(1.0, 1.0, 0.1, 10, kNoLimit, true), 0);
}

TEST(StepsLeft, AtMostWhatTheStepLimitAllows) {
  EXPECT_EQ(steps_left(0.0, 1.0, 0.001, 3, 10, false), 7);
  EXPECT_EQ(steps_left(0.0, 1.0, 0.001, 9, 10, false), 1);
}

TEST(StepsLeft, BeyondThirtyTwoBits) {
  EXPECT_EQ(steps_left(0.001, 3.0e6, 0.001, 1, kNoLimit, false), 2'999'999'999);
  EXPECT_EQ(steps_left(0.0, 1.0, 1e-300, 1, kNoLimit, false), std::int64_t{1} << 62);  // saturates
  EXPECT_EQ(steps_left(0.0, 3.0e6, 0.001, 2'000'000'000, 3'000'000'000, false), 1'000'000'000);
}

/// What ProgressLine prints for `p` (every step, not a terminal).
std::string printed(const ProgressPoint& p) {
  std::FILE* file = std::tmpfile();
  {
    ProgressLine line(file, 1);
    line.update(p);
  }
  std::rewind(file);
  std::string text(4096, '\0');
  text.resize(std::fread(text.data(), 1, text.size(), file));
  std::fclose(file);
  return text;
}

TEST(ProgressLine, ShowsStepsBeyondThirtyTwoBits) {
  ProgressPoint p;
  p.step = 2'999'999'999LL;
  p.expected_steps = 3'000'000'000LL;
  p.time = 2999.999999;
  p.fraction = 0.5;
  EXPECT_THAT(printed(p), HasSubstr("step 2999999999/3000000000  t = 3000 s  50%"));
}

}  // namespace
}  // namespace conserve::simulation
