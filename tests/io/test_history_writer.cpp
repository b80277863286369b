/// The CSV history: bit-exact round trip, flushing, malformed input.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>

#include "core/error.hpp"
#include "io/history_writer.hpp"
#include "support/files.hpp"

namespace conserve::io {
namespace {

namespace fs = std::filesystem;

fs::path scratch_file(const std::string& name) {
  const auto dir = fs::path(::testing::TempDir()) / "conserve_history";
  fs::create_directories(dir);
  return dir / name;
}

void write_text(const fs::path& file, const std::string& text) { std::ofstream(file) << text; }

std::vector<double> awkward_values() {
  using limits = std::numeric_limits<double>;
  std::vector<double> values{0.0,
                             -0.0,
                             0.1,
                             -1.0 / 3.0,
                             1e-300,
                             -2.5e-310,
                             limits::denorm_min(),
                             limits::min(),
                             limits::max(),
                             -limits::max(),
                             limits::epsilon(),
                             limits::infinity(),
                             -limits::infinity(),
                             123456789012345678.0};
  std::mt19937_64 random(7);
  std::uniform_int_distribution<std::uint64_t> bits;
  while (values.size() < 1000) {  // random bit patterns: every exponent and sign
    const auto pattern = bits(random);
    double value = 0.0;
    std::memcpy(&value, &pattern, sizeof value);
    if (std::isfinite(value)) values.push_back(value);
  }
  return values;
}

TEST(History, RoundTripIsBitExact) {
  const auto file = scratch_file("roundtrip.csv");
  const auto values = awkward_values();
  {
    HistoryWriter writer(file, {"a", "b"});
    for (std::size_t i = 0; i + 1 < values.size(); i += 2) writer.write_row({values[i], values[i + 1]});
  }
  const auto history = read_history(file);
  EXPECT_EQ(history.columns, (std::vector<std::string>{"a", "b"}));
  ASSERT_EQ(history.rows.size(), values.size() / 2);
  for (std::size_t i = 0; i + 1 < values.size(); i += 2) {
    EXPECT_EQ(std::memcmp(history.rows[i / 2].data(), &values[i], 2 * sizeof(double)), 0)
        << values[i] << ", " << values[i + 1];
  }
}

TEST(History, NanSurvivesAsNan) {
  const auto file = scratch_file("nan.csv");
  HistoryWriter(file, {"x"}).write_row({std::numeric_limits<double>::quiet_NaN()});
  EXPECT_TRUE(std::isnan(read_history(file).rows.at(0).at(0)));
}

// A value that is not there (min_active_gap with nothing active) is an
// empty field, which CSV readers take as missing, and reads back as NaN.
TEST(History, NanIsWrittenAsAnEmptyField) {
  const auto file = scratch_file("nan_empty.csv");
  HistoryWriter(file, {"a", "b", "c"}).write_row({1.0, std::numeric_limits<double>::quiet_NaN(), 3.0});
  EXPECT_EQ(test::slurp(file), "a,b,c\n1,,3\n");
  const History h = read_history(file);
  EXPECT_EQ(h.rows.at(0).at(0), 1.0);
  EXPECT_TRUE(std::isnan(h.rows.at(0).at(1)));
}

TEST(History, HeaderAndRowsAreFlushedImmediately) {
  const auto file = scratch_file("flush.csv");
  HistoryWriter writer(file, {"time", "energy"});
  EXPECT_EQ(test::slurp(file), "time,energy\n");
  writer.write_row({0.5, -2.0});
  EXPECT_EQ(test::slurp(file), "time,energy\n0.5,-2\n");  // while the writer is still open
}

TEST(History, ColumnByName) {
  const auto file = scratch_file("column.csv");
  {
    HistoryWriter writer(file, {"t", "e"});
    writer.write_row({0, 10});
    writer.write_row({1, 11});
  }
  const auto history = read_history(file);
  EXPECT_EQ(history.column("e"), (std::vector<double>{10, 11}));
  EXPECT_EQ(history.column("t"), (std::vector<double>{0, 1}));
  try {
    (void)history.column("momentum");
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'momentum'"), std::string::npos) << e.what();
  }
}

TEST(History, WrongRowLengthThrowsError) {
  HistoryWriter writer(scratch_file("length.csv"), {"a", "b", "c"});
  EXPECT_THROW(writer.write_row({1.0, 2.0}), Error);
  EXPECT_THROW(writer.write_row({1.0, 2.0, 3.0, 4.0}), Error);
}

TEST(History, UnwritableFileThrowsError) {
  EXPECT_THROW(HistoryWriter(scratch_file("no_such_dir") / "h.csv", {"a"}), Error);
}

TEST(History, BadColumnNameThrowsError) {
  EXPECT_THROW(HistoryWriter(scratch_file("badname.csv"), {"a,b"}), Error);
  EXPECT_THROW(HistoryWriter(scratch_file("badname.csv"), {""}), Error);
}

TEST(History, MalformedRowNamesFileAndLine) {
  const auto file = scratch_file("malformed.csv");
  const auto expect_line = [&](const std::string& text, int line) {
    write_text(file, text);
    try {
      read_history(file);
      ADD_FAILURE() << "no exception for\n" << text;
    } catch (const InputError& e) {
      const auto prefix = file.string() + ":" + std::to_string(line) + ": ";
      EXPECT_EQ(std::string(e.what()).rfind(prefix, 0), 0u) << e.what();
    }
  };
  expect_line("a,b\n1,2\n3\n", 3);
  expect_line("a,b\n1,2\n3,4,5\n", 3);
  expect_line("a,b\n1,x\n", 2);
  expect_line("a,b\n1,2.5.1\n", 2);
  expect_line("a,b\n\n", 2);
  expect_line("", 1);
}

TEST(History, ResumesAfterAStepBeyond32Bits) {
  // Steps past 2^31 (long runs, issue 11): the row of the restart step is
  // found and kept, later rows are dropped.
  const auto file = scratch_file("resume_big.csv");
  write_text(file, "step,x\n2999999999,1\n3000000000,2\n3000000001,3\n");
  resume_history(file, 3'000'000'000LL);
  {
    HistoryWriter writer(file, {"step", "x"});
    writer.write_row({3000000001.0, 4.0});
  }
  const History h = read_history(file);
  EXPECT_EQ(h.column("step"), (std::vector<double>{2999999999.0, 3000000000.0, 3000000001.0}));
  EXPECT_EQ(h.column("x"), (std::vector<double>{1.0, 2.0, 4.0}));
}

TEST(History, MissingFileThrowsInputError) {
  EXPECT_THROW(read_history(scratch_file("does_not_exist.csv")), InputError);
}

}  // namespace
}  // namespace conserve::io
