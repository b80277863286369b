#pragma once
/// The run statistics, declared once: each is a column of history.csv
/// and, accumulated over the steps (sum, largest, smallest or mean), keys
/// of summary.json; checkpoints carry the accumulations and the end-of-run
/// line reads them. Adding one is one entry of statistics().
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

/// How summary.json forms a run value from a statistic's steps.
enum class Over {
  none,
  sum,
  max,   ///< the largest value that is not NaN (NaN while there is none; 0 for a count)
  min,   ///< the smallest value that is not NaN (NaN while there is none; 0 for a count)
  mean,  ///< the sum over the steps taken divided by their number
};

struct Statistic {
  /// history.csv column; empty for a statistic of summary.json only.
  std::string_view column;
  double (*value)(const StepFigures&);
  struct Summary {
    std::string_view key;  ///< summary.json key; empty: none
    Over over = Over::none;
    bool count = false;  ///< written as a whole number
  };
  /// Its run values in summary.json (none, one or two).
  std::vector<Summary> summary = {};
};

/// Every statistic, in history.csv's column order (after the momenta J_z,
/// before the drifts).
const std::vector<Statistic>& statistics();

/// A run's accumulation of statistics(): one value per summary key, and
/// the steps taken (the initial state is added but not counted).
class RunStatistics {
 public:
  RunStatistics();
  /// Adds a step's figures; `taken` is false for the initial state.
  void add(const StepFigures& figures, bool taken);
  /// The run value of summary key `key` (throws std::out_of_range for an unknown key).
  [[nodiscard]] double value(std::string_view key) const;
  /// (key, run value, is a count), in statistics() order: summary.json's.
  [[nodiscard]] std::vector<std::tuple<std::string, double, bool>> summary() const;

  /// For checkpoints: the summary keys, their accumulated values (sums for
  /// means) and the steps taken.
  [[nodiscard]] static std::vector<std::string> keys();
  std::vector<double> accumulated;
  double steps = 0.0;
};

}  // namespace conserve::simulation
