#include "simulation/statistics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

namespace conserve::simulation {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

const contact::StepContactStats& contact_of(const StepFigures& f) { return f.record.contact; }

/// The step's value of the contact method's own statistic `i` (0 when the
/// step has none: the initial state).
double own_value(const StepFigures& f, std::size_t i) {
  const std::vector<double>& own = contact_of(f).own;
  return i < own.size() ? own[i] : 0.0;
}

/// Before any step: 0 for sums, means and counts, NaN for other extremes.
double initial(const Statistic::Summary& entry) {
  return (entry.over == Over::max || entry.over == Over::min) && !entry.count ? kNaN : 0.0;
}

}  // namespace

// The columns of history.csv between the momenta and the drifts, in order.
const std::vector<Statistic>& statistics() {
  using F = const StepFigures&;
  static const std::vector<Statistic> all = {
      {"newton_iterations", [](F f) { return double(f.record.newton.iterations); },
       {{"mean_newton_iterations", Over::mean}, {"max_newton_iterations", Over::max, true}}},
      {"residual", [](F f) { return f.record.newton.final_residual(); }},
      {"active_contacts", [](F f) { return double(f.active_contacts); }},
      {"activations", [](F f) { return double(contact_of(f).activations); }, {{"activations", Over::sum, true}}},
      {"releases", [](F f) { return double(contact_of(f).releases); }, {{"releases", Over::sum, true}}},
      {"active_set_passes", [](F f) { return double(contact_of(f).passes); }},
      {"contact_force", [](F f) { return f.contact_force; }},
      {"min_active_gap", [](F f) { return contact_of(f).min_active_gap; }, {{"min_active_gap", Over::min}}},
      {"max_active_gap", [](F f) { return contact_of(f).max_active_gap; }, {{"max_active_gap", Over::max}}},
      {"max_penetration", [](F f) { return std::max(contact_of(f).slave_penetration, contact_of(f).master_penetration); },
       {{"max_penetration", Over::max}}},
      {"slave_penetration", [](F f) { return contact_of(f).slave_penetration; }, {{"slave_penetration", Over::max}}},
      {"master_penetration", [](F f) { return contact_of(f).master_penetration; },
       {{"master_penetration", Over::max}}},
      {"impact_splits", [](F f) { return double(contact_of(f).splits); }, {{"impact_splits", Over::sum, true}}},
      {"", [](F f) { return double(contact_of(f).split_passes); }, {{"impact_split_passes", Over::sum, true}}},
      {"min_det_F", [](F f) { return f.diagnostics.min_det_F; }, {{"min_det_F", Over::min}}},
      {"contact_energy", [](F f) { return f.diagnostics.contact; }, {{"max_contact_energy", Over::max}}},
      {"contact_released", [](F f) { return contact_of(f).contact_released; }, {{"contact_released", Over::sum}}},
      {"dissipated", [](F f) { return f.diagnostics.dissipated; }, {{"dissipated", Over::max}}},
      {"sticking", [](F f) { return double(contact_of(f).sticking); }},
      {"slipping", [](F f) { return double(contact_of(f).slipping); }},
      {"load_work", [](F f) { return f.diagnostics.load_work; }},
      {"support_work", [](F f) { return f.diagnostics.support_work; }},
      {"equations", [](F f) { return double(contact_of(f).equations); },
       {{"mean_equations", Over::mean}, {"max_equations", Over::max, true}}},
  };
  return all;
}

std::vector<std::string> statistic_columns(const std::vector<contact::MethodStatistic>& own) {
  std::vector<std::string> c;
  for (const Statistic& s : statistics())
    if (!s.column.empty()) c.emplace_back(s.column);
  for (const contact::MethodStatistic& s : own)
    if (!s.column.empty()) c.emplace_back(s.column);
  return c;
}

std::vector<double> statistic_values(const StepFigures& figures, const std::vector<contact::MethodStatistic>& own) {
  std::vector<double> v;
  for (const Statistic& s : statistics())
    if (!s.column.empty()) v.push_back(s.value(figures));
  for (std::size_t i = 0; i < own.size(); ++i)
    if (!own[i].column.empty()) v.push_back(own_value(figures, i));
  return v;
}

RunStatistics::RunStatistics(std::vector<contact::MethodStatistic> own) : own_(std::move(own)) {
  for (std::size_t i = 0; i < statistics().size() + own_.size(); ++i) {
    const std::size_t entries =
        i < statistics().size() ? statistics()[i].summary.size() : own_[i - statistics().size()].summary.size();
    for (std::size_t e = 0; e < entries; ++e) slots_.push_back({i, e});
  }
  for (const Slot& s : slots_) accumulated.push_back(initial(entry(s)));
}

const RunValue& RunStatistics::entry(const Slot& slot) const {
  const std::size_t common = statistics().size();
  return slot.statistic < common ? statistics()[slot.statistic].summary[slot.entry]
                                 : own_[slot.statistic - common].summary[slot.entry];
}

void RunStatistics::add(const StepFigures& figures, bool taken) {
  if (taken) steps += 1.0;
  const std::size_t common = statistics().size();
  for (std::size_t k = 0; k < slots_.size(); ++k) {
    const Slot& s = slots_[k];
    const Over over = entry(s).over;
    const double v = s.statistic < common ? statistics()[s.statistic].value(figures)
                                          : own_value(figures, s.statistic - common);
    double& a = accumulated[k];
    switch (over) {
      case Over::sum:
      case Over::mean:
        if (taken) a += v;
        break;
      case Over::max:
        if (!std::isnan(v)) a = std::isnan(a) ? v : std::max(a, v);
        break;
      case Over::min:
        if (!std::isnan(v)) a = std::isnan(a) ? v : std::min(a, v);
        break;
      case Over::none:
        break;
    }
  }
}

double RunStatistics::value(std::string_view key) const {
  for (std::size_t k = 0; k < slots_.size(); ++k) {
    const RunValue& e = entry(slots_[k]);
    if (e.key != key) continue;
    return e.over == Over::mean ? accumulated[k] / std::max(steps, 1.0) : accumulated[k];
  }
  throw std::out_of_range("no run statistic " + std::string(key));
}

bool RunStatistics::has(std::string_view key) const {
  return std::any_of(slots_.begin(), slots_.end(), [&](const Slot& s) { return entry(s).key == key; });
}

std::vector<std::tuple<std::string, double, bool>> RunStatistics::summary() const {
  std::vector<std::tuple<std::string, double, bool>> out;
  for (const Slot& s : slots_) {
    const std::string key(entry(s).key);
    out.emplace_back(key, value(key), entry(s).count);
  }
  return out;
}

std::vector<std::string> RunStatistics::keys() const {
  std::vector<std::string> out;
  for (const Slot& s : slots_) out.emplace_back(entry(s).key);
  return out;
}

}  // namespace conserve::simulation
