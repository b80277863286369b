#pragma once
/// The run statistics, declared once: each is a column of history.csv
/// and, accumulated over the steps (sum, largest, smallest or mean), keys
/// of summary.json; checkpoints carry the accumulations and the end-of-run
/// line reads them. Those of every run are statistics()' entries; a
/// contact method adds its own (contact::Method::statistics), declared
/// with the method.
#include <string>
#include <string_view>
#include <tuple>
#include <utility>
#include <vector>

#include "contact/method.hpp"
#include "solver/newton.hpp"
#include "time/diagnostics.hpp"
#include "time/integrator.hpp"

namespace conserve::simulation {

/// What one step did, for the history.
struct StepRecord {
  solver::NewtonReport newton;
  contact::StepContactStats contact;
  std::vector<time::SupportReaction> supports;  ///< per support (model::Prescribed::supports); empty: none yet
};

/// What one step produced, as the statistics read it.
struct StepFigures {
  const StepRecord& record;              ///< Newton report and contact figures
  const time::Diagnostics& diagnostics;  ///< energies, momenta, smallest det F
  int active_contacts = 0;               ///< constraints at the step's end
  double contact_force = 0.0;            ///< the sum of their normal forces [N]
};

struct Statistic {
  /// history.csv column; empty for a statistic of summary.json only.
  std::string_view column;
  double (*value)(const StepFigures&);
  using Summary = RunValue;  ///< core/statistic.hpp
  /// Its run values in summary.json (none, one or two).
  std::vector<Summary> summary = {};
};

/// The statistics of every run, in history.csv's column order (after the
/// momenta J_z; then the contact method's own, then the drifts).
const std::vector<Statistic>& statistics();

/// A run's history.csv columns of statistics: statistics()' then the
/// contact method's `own`.
std::vector<std::string> statistic_columns(const std::vector<contact::MethodStatistic>& own);
/// Their values for a step, in the same order (an own statistic the step
/// has no value of is 0).
std::vector<double> statistic_values(const StepFigures& figures, const std::vector<contact::MethodStatistic>& own);

/// A run's accumulation of statistics() and its contact method's own: one
/// value per summary key, and the steps taken (the initial state is added
/// but not counted).
class RunStatistics {
 public:
  RunStatistics() : RunStatistics(std::vector<contact::MethodStatistic>()) {}
  explicit RunStatistics(std::vector<contact::MethodStatistic> own);
  /// Adds a step's figures; `taken` is false for the initial state.
  void add(const StepFigures& figures, bool taken);
  /// The run value of summary key `key` (throws std::out_of_range for an unknown key).
  [[nodiscard]] double value(std::string_view key) const;
  /// Whether the run has summary key `key` (a contact method's own
  /// statistics are there only with that method).
  [[nodiscard]] bool has(std::string_view key) const;
  /// (key, run value, is a count), in statistics() order: summary.json's.
  [[nodiscard]] std::vector<std::tuple<std::string, double, bool>> summary() const;

  /// For checkpoints: the summary keys, their accumulated values (sums for
  /// means) and the steps taken.
  [[nodiscard]] std::vector<std::string> keys() const;
  std::vector<double> accumulated;
  double steps = 0.0;

 private:
  /// One accumulation: common statistic `statistic` (own one `statistic`
  /// − statistics().size() beyond them), its run value `entry`.
  struct Slot {
    std::size_t statistic;
    std::size_t entry;
  };
  [[nodiscard]] const RunValue& entry(const Slot& slot) const;
  std::vector<contact::MethodStatistic> own_;
  std::vector<Slot> slots_;
};

}  // namespace conserve::simulation
