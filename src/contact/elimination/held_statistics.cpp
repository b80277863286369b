#include "contact/elimination/held_statistics.hpp"

namespace conserve::contact {
namespace {

struct Entry {
  MethodStatistic statistic;
  double (*value)(const HeldCounts&);
};

const std::vector<Entry>& entries() {
  using C = const HeldCounts&;
  static const std::vector<Entry> all = {
      {{"max_activation_gap", {{"max_activation_gap", Over::max}}}, [](C c) { return c.max_activation_gap; }},
      {{"held", {{"held", Over::sum, true}}}, [](C c) { return double(c.held); }},
      {{"chatter", {{"chatter", Over::sum, true}}}, [](C c) { return double(c.chatter); }},
      {{"loaded_releases", {{"loaded_releases", Over::sum, true}}}, [](C c) { return double(c.loaded_releases); }},
      {{"rate_steps", {{"rate_steps", Over::sum, true}}}, [](C c) { return double(c.rate_steps); }},
      {{"pushes", {{"pushes", Over::sum, true}}}, [](C c) { return double(c.pushes); }},
      {{"creases", {{"creases", Over::sum, true}}}, [](C c) { return double(c.creases); }},
      {{"repeats", {{"repeats", Over::sum, true}}}, [](C c) { return double(c.repeats); }},
      {{"push_work", {{"push_work", Over::sum}}}, [](C c) { return c.push_work; }},
      {{"velocity_update_failures", {{"velocity_update_failures", Over::sum, true}}},
       [](C c) { return double(c.velocity.failure != nullptr); }},
      {{"pushes_given_up", {{"pushes_given_up", Over::sum, true}}}, [](C c) { return double(c.pushes_given_up); }},
  };
  return all;
}

}  // namespace

const std::vector<MethodStatistic>& held_statistics() {
  static const std::vector<MethodStatistic> all = [] {
    std::vector<MethodStatistic> s;
    for (const Entry& e : entries()) s.push_back(e.statistic);
    return s;
  }();
  return all;
}

std::vector<double> held_values(const HeldCounts& counts) {
  std::vector<double> v;
  v.reserve(entries().size());
  for (const Entry& e : entries()) v.push_back(e.value(counts));
  return v;
}

}  // namespace conserve::contact
