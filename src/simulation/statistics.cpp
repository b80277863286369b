#include "simulation/statistics.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace conserve::simulation {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

const contact::StepContactStats& contact_of(const StepFigures& f) { return f.record.contact; }

/// One accumulation slot: statistic `statistic`'s summary entry `entry`.
struct Slot {
  std::size_t statistic;
  std::size_t entry;
};

const std::vector<Slot>& slots() {
  static const std::vector<Slot> all = [] {
    std::vector<Slot> s;
    for (std::size_t i = 0; i < statistics().size(); ++i)
      for (std::size_t e = 0; e < statistics()[i].summary.size(); ++e) s.push_back({i, e});
    return s;
  }();
  return all;
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
      {"max_activation_gap", [](F f) { return contact_of(f).max_activation_gap; },
       {{"max_activation_gap", Over::max}}},
      {"contact_force", [](F f) { return f.contact_force; }},
      {"min_active_gap", [](F f) { return contact_of(f).min_active_gap; }, {{"min_active_gap", Over::min}}},
      {"max_active_gap", [](F f) { return contact_of(f).max_active_gap; }, {{"max_active_gap", Over::max}}},
      {"max_penetration", [](F f) { return std::max(contact_of(f).slave_penetration, contact_of(f).master_penetration); },
       {{"max_penetration", Over::max}}},
      {"slave_penetration", [](F f) { return contact_of(f).slave_penetration; }, {{"slave_penetration", Over::max}}},
      {"master_penetration", [](F f) { return contact_of(f).master_penetration; },
       {{"master_penetration", Over::max}}},
      {"held", [](F f) { return double(contact_of(f).held); }, {{"held", Over::sum, true}}},
      {"chatter", [](F f) { return double(contact_of(f).chatter); }, {{"chatter", Over::sum, true}}},
      {"loaded_releases", [](F f) { return double(contact_of(f).loaded_releases); }, {{"loaded_releases", Over::sum, true}}},
      {"impact_splits", [](F f) { return double(contact_of(f).splits); }, {{"impact_splits", Over::sum, true}}},
      {"", [](F f) { return double(contact_of(f).split_passes); }, {{"impact_split_passes", Over::sum, true}}},
      {"rate_steps", [](F f) { return double(contact_of(f).rate_steps); }, {{"rate_steps", Over::sum, true}}},
      {"pushes", [](F f) { return double(contact_of(f).pushes); }, {{"pushes", Over::sum, true}}},
      {"creases", [](F f) { return double(contact_of(f).creases); }, {{"creases", Over::sum, true}}},
      {"push_work", [](F f) { return contact_of(f).push_work; }, {{"push_work", Over::sum}}},
      {"velocity_update_failures", [](F f) { return double(contact_of(f).velocity.failure != nullptr); },
       {{"velocity_update_failures", Over::sum, true}}},
      {"pushes_given_up", [](F f) { return double(contact_of(f).pushes_given_up); }, {{"pushes_given_up", Over::sum, true}}},
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

RunStatistics::RunStatistics() {
  for (const Slot& s : slots()) accumulated.push_back(initial(statistics()[s.statistic].summary[s.entry]));
}

void RunStatistics::add(const StepFigures& figures, bool taken) {
  if (taken) steps += 1.0;
  for (std::size_t k = 0; k < slots().size(); ++k) {
    const Slot& s = slots()[k];
    const Over over = statistics()[s.statistic].summary[s.entry].over;
    const double v = statistics()[s.statistic].value(figures);
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
  for (std::size_t k = 0; k < slots().size(); ++k) {
    const auto& entry = statistics()[slots()[k].statistic].summary[slots()[k].entry];
    if (entry.key != key) continue;
    return entry.over == Over::mean ? accumulated[k] / std::max(steps, 1.0) : accumulated[k];
  }
  throw std::out_of_range("no run statistic " + std::string(key));
}

std::vector<std::tuple<std::string, double, bool>> RunStatistics::summary() const {
  std::vector<std::tuple<std::string, double, bool>> out;
  for (const Slot& s : slots()) {
    const Statistic& stat = statistics()[s.statistic];
    const std::string key(stat.summary[s.entry].key);
    out.emplace_back(key, value(key), stat.summary[s.entry].count);
  }
  return out;
}

std::vector<std::string> RunStatistics::keys() {
  std::vector<std::string> out;
  for (const Slot& s : slots()) out.emplace_back(statistics()[s.statistic].summary[s.entry].key);
  return out;
}

}  // namespace conserve::simulation
