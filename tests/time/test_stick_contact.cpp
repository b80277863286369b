// Full stick contact by direct elimination (paper §4.3.1, (35)–(46);
// docs/theory.md, "Direct elimination (33)–(65)" and "The step with
// contact"): tangent, energy and momentum, no penetration, release.
#include <gtest/gtest.h>

#include <cstdio>

#include "support/contact_scenarios.hpp"
#include "contact_checks.hpp"

namespace conserve::time {
namespace {

using test::ContactRun;

TEST(StickContact, ReducedTangentMatchesFiniteDifferencesDeformableMaster) {
  ContactRun<3> run(test::paper(test::two_boxes("stick", 0.2)));
  test::run_until_contact(run, 3, 100);
  test::expect_second_order(test::reduced_tangent_order(run), "deformable master");
}

TEST(StickContact, ReducedTangentMatchesFiniteDifferencesRigidMaster) {
  ContactRun<3> run(test::paper(test::ball_on_plane("stick", 0.3)));
  test::run_until_contact(run, 3, 200);
  test::expect_second_order(test::reduced_tangent_order(run), "rigid master");
}

// The reduced tangent's products (43) against the plain sparse products,
// stick on a deformable master; pattern kept through a Newton update.
TEST(StickContact, ReducedTangentEqualsTheProducts) {
  ContactRun<3> run(test::paper(test::two_boxes("stick", 0.2)));
  test::run_until_contact(run, 3, 100);
  EXPECT_LT(test::reduced_product_error(run), 1e-14);
}

struct Record {
  double energy_drift = 0.0, penetration = 0.0;  // penetration [m]
  Vec3 linear_drift = Vec3::Zero(), angular_change = Vec3::Zero();
  int activations = 0, releases = 0, first_release_step = -1, max_passes = 0;
  std::size_t final_active = 0;
};

template <int D>
Record run_and_record(ContactRun<D>& run) {
  const Diagnostics d0 = run.diagnostics();
  const int steps = static_cast<int>(std::round(run.scenario.time.end / run.scenario.time.step));
  Record r;
  for (int n = 0; n < steps; ++n) {
    run.step();
    const Diagnostics d = run.diagnostics();
    const auto& s = run.integrator->contact_stats();
    r.energy_drift = std::max(r.energy_drift, std::abs(d.total - d0.total) / std::abs(d0.total));
    r.linear_drift = r.linear_drift.cwiseMax((d.linear - d0.linear).cwiseAbs() / d0.linear.norm());
    r.angular_change = r.angular_change.cwiseMax((d.angular - d0.angular).cwiseAbs() / d0.angular.norm());
    r.activations += s.activations;
    r.releases += s.releases;
    r.max_passes = std::max(r.max_passes, s.passes);
    if (s.releases > 0 && r.first_release_step < 0) r.first_release_step = run.state.step;
    r.penetration = std::max(r.penetration, test::slave_penetration(run));
  }
  r.final_active = run.contacts->constraints().size();
  return r;
}

TEST(StickContact, BallOnRigidPlaneConservesEnergyThroughImpact) {
  ContactRun<3> run(test::paper(test::ball_on_plane("stick", 0.3)));
  const Record r = run_and_record(run);
  std::printf("[ measured ] stick ball, 300 steps: E drift %.2e, %d activations, %d releases, first release at step %d, "
              "max penetration %.2e m, at most %d passes\n",
              r.energy_drift, r.activations, r.releases, r.first_release_step, r.penetration, r.max_passes);
  EXPECT_GT(r.activations, 10);  // there was an impact
  EXPECT_LT(r.energy_drift, 1e-9);
  EXPECT_LE(r.penetration, 1e-12 * run.problem.model.size());  // no slave behind its master
}

// Stick keeps J too, although the slaves are held at their activation
// gap γ ≠ 0 (the paper's §5 keeps E and L only): the test map reproduces
// the facet's rigid motions about the mid-point (zero_work::stick_test).
TEST(StickContact, TwoFreeBodiesConserveEnergyAndMomenta) {
  ContactRun<3> run(test::paper(test::two_boxes("stick", 0.2)));
  const Record r = run_and_record(run);
  std::printf("[ measured ] stick, two free boxes, 100 steps: E drift %.2e, L drift (%.2e %.2e %.2e), "
              "J drift (%.2e %.2e %.2e), %d activations, %d releases\n",
              r.energy_drift, r.linear_drift.x(), r.linear_drift.y(), r.linear_drift.z(), r.angular_change.x(),
              r.angular_change.y(), r.angular_change.z(), r.activations, r.releases);
  EXPECT_GT(r.activations, 3);
  EXPECT_LT(r.energy_drift, 1e-9);
  EXPECT_LT(r.linear_drift.maxCoeff(), 1e-10);
  EXPECT_LT(r.angular_change.maxCoeff(), 1e-10);  // 1e-8 with the map N ⊗ 1 + a correction along all of Δx_m
  EXPECT_LE(r.penetration, 1e-12 * run.problem.model.size());
}

// Contact is made and lost again: the boxes hit, stick, rebound apart; the
// constraints are released by tension (46) and the set ends empty.
TEST(StickContact, ContactIsMadeAndReleased) {
  ContactRun<3> run(test::paper(test::two_boxes("stick", 0.2)));
  const Record r = run_and_record(run);
  std::printf("[ measured ] first release at step %d; %d releases; %zu active at the end; at most %d passes/step\n",
              r.first_release_step, r.releases, r.final_active, r.max_passes);
  EXPECT_GT(r.first_release_step, 0);
  EXPECT_GT(r.releases, 0);
  EXPECT_EQ(r.final_active, 0u);
  EXPECT_LE(r.max_passes, run.scenario.active_set.max_passes);
}

}  // namespace
}  // namespace conserve::time

namespace conserve::time {
namespace {

// Two free discs in 2D, with the paper's scheme and with the defaults
// (persistent contact: its stick impulses are along the rate of
// x_s − F(x_m), which has no moment where the slave is held off its facet
// by γ), for each method.
void two_free_discs_keep_momenta(bool paper_scheme, const std::string& method = "elimination") {
  const std::string toml = test::with_method(test::glancing_spheres(2, "stick", 0.1), method);
  test::ContactRun<2> run(paper_scheme ? test::paper(toml) : toml);
  const Diagnostics d0 = run.diagnostics();
  double e = 0.0, l = 0.0, j = 0.0;
  int activations = 0;
  for (int n = 0; n < 200; ++n) {
    run.step();
    const Diagnostics d = run.diagnostics();
    e = std::max(e, std::abs(d.total + d.released - d0.total) / d0.total);  // the penalty's springs let go
    l = std::max(l, (d.linear - d0.linear).norm() / d0.linear.norm());
    j = std::max(j, std::abs(d.angular.z() - d0.angular.z()) / std::abs(d0.angular.z()));
    activations += run.integrator->contact_stats().activations;
  }
  std::printf("[ measured ] stick, two free discs 2D, %s, %s, 200 steps: E drift %.2e, |L| drift %.2e, J drift %.2e, "
              "%d activations\n", method.c_str(), paper_scheme ? "paper scheme" : "defaults", e, l, j, activations);
  EXPECT_GT(activations, 2);
  EXPECT_LT(e, 1e-9);
  EXPECT_LT(l, 1e-10);
  EXPECT_LT(j, 1e-10);
}

TEST(StickContact, TwoFreeDiscsConserveEnergyAndMomenta2d) { two_free_discs_keep_momenta(true); }
TEST(StickContact, TwoFreeDiscsConserveEnergyAndMomentaWithPersistentContact2d) {
  two_free_discs_keep_momenta(false);
}
TEST(StickContact, TwoFreeDiscsConserveEnergyAndMomentaByMultipliers2d) { two_free_discs_keep_momenta(false, "lagrange"); }
TEST(StickContact, TwoFreeDiscsConserveEnergyAndMomentaByPenalty2d) { two_free_discs_keep_momenta(false, "penalty"); }

}  // namespace
}  // namespace conserve::time
