// Two passes against a driven rigid tool (docs/theory.md, "A rigid tool in
// two passes"): the tool's nodes have no unknowns, so each of their
// constraints on the block's facets is held by a node of the facet. A flat
// punch pressed into a coarse plate whose facets its corners cut: no node
// of either side behind the other's facets, the energy with the punch's
// work kept, and the force–indentation curve that of a fine one-pass
// reference; one pass as the control.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <cstdio>
#include <string>
#include <vector>

#include "contact_checks.hpp"
#include "support/files.hpp"

namespace conserve::time {
namespace {

using test::ContactRun;

/// examples/punch/punch_plate.toml to `end`, the plate meshed at `size`,
/// its contact in `passes` passes.
std::string punch(double size, int passes, double end) {
  std::string text = test::slurp(std::string(CONSERVE_SOURCE_DIR) + "/examples/punch/punch_plate.toml");
  auto replace = [&](const std::string& from, const std::string& to) {
    const std::size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
  };
  replace("size = 0.01\n", "size = " + std::to_string(size) + "\n");
  replace("end = 0.08", "end = " + std::to_string(end));
  replace("kind = \"frictionless\"", "kind = \"frictionless\"\npasses = " + std::to_string(passes));
  return text;
}

/// The constraints of the second pass held (by a node of the plate's facet) at the run's state.
int held_by_the_plate(const ContactRun<2>& run) {
  int held = 0;
  for (const auto& c : run.contacts->constraints()) held += c.eliminated >= 0;
  return held;
}

// The punch's corners (rigid nodes, driven) held out of the plate's 20 mm
// facets they cut: no node of either side behind the other's facets, the
// energy with the punch's work kept; one pass lets them sink.
TEST(DrivenTwoPass, PunchCornersStayOutOfACoarsePlate) {
  // The plate starts at rest: E's drift is measured against the run's
  // largest K + W, not the running one of test::measure.
  auto run = [](int passes, double& energy, double& penetration, double& master_penetration, int& steps) {
    ContactRun<2> r(punch(0.02, passes, 0.05));
    const double e0 = r.diagnostics().total;
    double e_ref = 0.0, change = 0.0;
    while (r.state.time < r.scenario.time.end - 1e-9 * r.scenario.time.step) {
      r.step();
      const time::Diagnostics d = r.diagnostics();
      e_ref = std::max(e_ref, d.kinetic + d.strain);
      change = std::max(change, std::abs(d.total - e0));
      penetration = std::max(penetration, r.last.contact.slave_penetration);
      master_penetration = std::max(master_penetration, r.last.contact.master_penetration);
      steps += held_by_the_plate(r) > 0;
    }
    energy = change / e_ref;
    return std::make_pair(r.integrator->supports().back().force.y(), r.cutbacks);
  };
  double energy = 0.0, penetration = 0.0, master_penetration = 0.0;
  int held_steps = 0;
  const auto [force_two, retried] = run(2, energy, penetration, master_penetration, held_steps);
  double energy_one = 0.0, penetration_one = 0.0, master_one = 0.0;
  int none = 0;
  const auto [force_one, retried_one] = run(1, energy_one, penetration_one, master_one, none);
  std::printf(
      "[ measured ] punch on a coarse plate, two passes: %d steps with corners held by the plate, %d retried; "
      "drift E (with the punch's work) %.2e; deepest node behind: plate's %.2e m, punch's %.2e m (one pass: "
      "%.2e m); punch force at the end %.4g N (one pass %.4g N)\n",
      held_steps, retried, energy, penetration, master_penetration, master_one, force_two, force_one);
  EXPECT_GT(held_steps, 100);
  EXPECT_LE(energy, 1e-10);
  EXPECT_LE(penetration, 1e-8);
  EXPECT_LE(master_penetration, 1e-8);
  EXPECT_GT(master_one, 1e-4);
  EXPECT_EQ(none, 0);
}

// The reduced tangent with corner constraints held by the plate's nodes
// (their V from the zero-work kernels), by the Taylor test.
TEST(DrivenTwoPass, ReducedTangentMatchesDifferences) {
  ContactRun<2> run(punch(0.02, 2, 0.05));
  while (held_by_the_plate(run) == 0 && run.state.step < 120) run.step();
  ASSERT_GT(held_by_the_plate(run), 0) << "no corner constraint";
  for (int n = 0; n < 20; ++n) run.step();
  test::expect_second_order(test::reduced_tangent_order(run), "2D, a driven punch in two passes");
}

// The multipliers holding the corners: their Newton system's tangent,
// B's variation included for a constraint held by a node of its facet.
TEST(DrivenTwoPass, MultipliersSystemTangentMatchesDifferences) {
  std::string text = punch(0.02, 2, 0.05);
  text.replace(text.find("passes = 2"), 10, "passes = 2\nmethod = \"lagrange\"");
  ContactRun<2> run(text);
  while (held_by_the_plate(run) == 0 && run.state.step < 120) run.step();
  ASSERT_GT(held_by_the_plate(run), 0) << "no corner constraint";
  for (int n = 0; n < 20; ++n) run.step();
  test::expect_second_order(test::system_tangent_order(run), "2D, a driven punch in two passes, multipliers");
}

}  // namespace
}  // namespace conserve::time
