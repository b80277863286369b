/// The run statistics are declared once (simulation/statistics.hpp): the
/// columns of history.csv, the keys of summary.json and what checkpoints
/// carry all come from the one table, and a run value is formed as its
/// table says (sums over the steps taken, extremes that skip NaN, means).
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <nlohmann/json.hpp>

#include "contact/elimination/held_statistics.hpp"
#include "simulation/output.hpp"
#include "simulation/statistics.hpp"
#include "simulation/summary.hpp"

namespace conserve::simulation {
namespace {

// The common statistics and a method's own (elimination's, declared in
// contact/elimination/held_statistics.cpp) end up in both files.
TEST(Statistics, HistoryAndSummaryComeFromOneTable) {
  const std::vector<contact::MethodStatistic>& own = contact::held_statistics();
  const std::vector<std::string> columns = history_columns({}, {}, {}, {}, own);
  RunSummary s;
  s.statistics = RunStatistics(own);
  const auto j = nlohmann::json::parse(summary_json(s, 1, RunOrigin{}));
  int columns_seen = 0, keys_seen = 0;
  auto check = [&](std::string_view column, const std::vector<RunValue>& summary) {
    if (!column.empty()) {
      EXPECT_NE(std::find(columns.begin(), columns.end(), std::string(column)), columns.end()) << column;
      ++columns_seen;
    }
    for (const auto& entry : summary) {
      EXPECT_TRUE(j.contains(std::string(entry.key))) << entry.key;
      if (entry.count) EXPECT_TRUE(j.at(std::string(entry.key)).is_number_integer()) << entry.key;
      ++keys_seen;
    }
  };
  for (const Statistic& stat : statistics()) check(stat.column, stat.summary);
  for (const contact::MethodStatistic& stat : own) check(stat.column, stat.summary);
  EXPECT_EQ(static_cast<std::size_t>(keys_seen), s.statistics.keys().size());
  EXPECT_EQ(columns.size(), history_columns().size() + own.size());  // a column each, only with the method
  EXPECT_GT(columns_seen, 20);
  EXPECT_TRUE(j.contains("pushes"));
  EXPECT_FALSE(nlohmann::json::parse(summary_json(RunSummary{}, 1, RunOrigin{})).contains("pushes"));
}

// A method's own statistic takes its step value from StepContactStats::own,
// in the method's order, and is accumulated as it declares.
TEST(Statistics, AMethodsOwnStatisticsAreAccumulatedAsItDeclares) {
  const std::vector<contact::MethodStatistic> own = {{"bounces", {{"bounces", Over::sum, true}}},
                                                     {"deepest", {{"deepest", Over::max}}}};
  RunStatistics run(own);
  const time::Diagnostics d0{};
  StepRecord initial;  // no own values yet: 0
  run.add({initial, d0, 0, 0.0}, false);
  StepRecord a, b;
  a.contact.own = {2.0, 1e-3};
  b.contact.own = {1.0, 5e-4};
  run.add({a, d0, 0, 0.0}, true);
  run.add({b, d0, 0, 0.0}, true);
  EXPECT_EQ(run.value("bounces"), 3.0);
  EXPECT_EQ(run.value("deepest"), 1e-3);
  EXPECT_EQ(statistic_values({b, d0, 0, 0.0}, own).back(), 5e-4);
  EXPECT_EQ(statistic_columns(own).back(), "deepest");
}

TEST(Statistics, RunValuesAreFormedAsDeclared) {
  RunStatistics run;
  const time::Diagnostics d0{};
  StepRecord initial;
  initial.contact.max_active_gap = std::numeric_limits<double>::quiet_NaN();
  run.add({initial, d0, 0, 0.0}, false);
  StepRecord a, b;
  a.newton.iterations = 4;
  a.contact.activations = 2;
  a.contact.min_active_gap = 1e-3;
  b.newton.iterations = 6;
  b.contact.activations = 1;
  b.contact.min_active_gap = std::numeric_limits<double>::quiet_NaN();  // none active
  run.add({a, d0, 2, 1.0}, true);
  run.add({b, d0, 0, 0.0}, true);
  EXPECT_EQ(run.value("activations"), 3.0);               // summed over the steps taken
  EXPECT_EQ(run.value("mean_newton_iterations"), 5.0);    // over the 2 steps taken, not the initial state
  EXPECT_EQ(run.value("max_newton_iterations"), 6.0);
  EXPECT_EQ(run.value("min_active_gap"), 1e-3);           // NaN skipped
  EXPECT_THROW((void)run.value("no_such_key"), std::out_of_range);
}

}  // namespace
}  // namespace conserve::simulation
