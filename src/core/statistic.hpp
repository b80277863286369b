#pragma once
/// How a run statistic turns into run values: shared by the common
/// statistics (simulation/statistics.hpp) and those a contact method
/// declares for itself (contact::Method::statistics).
#include <string_view>

namespace conserve {

/// How summary.json forms a run value from a statistic's steps.
enum class Over {
  none,
  sum,
  max,   ///< the largest value that is not NaN (NaN while there is none; 0 for a count)
  min,   ///< the smallest value that is not NaN (NaN while there is none; 0 for a count)
  mean,  ///< the sum over the steps taken divided by their number
};

/// One run value of a statistic: its summary.json key and how it is formed.
struct RunValue {
  std::string_view key;  ///< summary.json key; empty: none
  Over over = Over::none;
  bool count = false;  ///< written as a whole number
};

}  // namespace conserve
