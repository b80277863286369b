// No slave node ends a converged step behind its master (issue 11): with Δt
// swept over six values, in frictionless contact where the slaves slide
// across many facets of a curved faceted master (concave: a disc inside a
// ring; convex: two spinning spheres), and in full stick with a disc rolling on
// a floor. The deepest penetration of any slave, active or not, measured
// at the end of every step with the activation search's own rules, stays at
// round-off (1e-12 of the model size), and the conservation the contact kind
// promises holds to 1e-10. With impacts located and the persistent velocity
// the slaves are held within 1e-3 of a facet of the surface and slide into
// its concave vertices and edges, where one constraint cannot keep a slave
// in front of both facets (the crease pair, docs/theory.md).
#include <gtest/gtest.h>

#include <cstdio>

#include "contact_checks.hpp"
#include "support/contact_scenarios.hpp"

namespace conserve::time {
namespace {

using test::ContactRun;

struct Sweep {
  double penetration = 0.0;  ///< deepest penetration over the run / model size
  double energy = 0.0;       ///< max |E − E0| / max(K + W)
  double linear = 0.0;       ///< max |L − L0| / max Σ|p_A|
  double angular = 0.0;      ///< max |J − J0| / (max Σ|p_A| · size)
  int activations = 0, releases = 0, contact_steps = 0;
};

template <int D>
Sweep run_sweep(const std::string& toml) {
  ContactRun<D> run(toml);
  const double size = run.problem.model.size();
  const Diagnostics d0 = run.diagnostics();
  // To the end time, whatever the steps taken (cutbacks, located impacts).
  const double end = run.scenario.time.end - 1e-9 * run.scenario.time.step;
  double e_ref = 0.0, p_ref = 0.0;
  Sweep s;
  double de = 0.0, dl = 0.0, dj = 0.0;
  for (int n = 0; n == 0 || run.state.time < end; ++n) {
    if (n > 0) run.step();
    const Diagnostics d = run.diagnostics();
    const Eigen::VectorXd p = run.assembler->mass_times(run.state.v);
    double momentum = 0.0;
    for (int a = 0; a < run.problem.model.num_nodes(); ++a) momentum += p.segment<D>(a * D).norm();
    e_ref = std::max(e_ref, d.kinetic + d.strain);
    p_ref = std::max(p_ref, momentum);
    de = std::max(de, std::abs(d.total - d0.total));
    dl = std::max(dl, (d.linear - d0.linear).norm());
    dj = std::max(dj, (d.angular - d0.angular).norm());
    s.penetration = std::max(s.penetration, run.contacts->slave_penetration(run.state.u).depth / size);
    if (n == 0) continue;
    s.activations += run.integrator->contact_stats().activations;
    s.releases += run.integrator->contact_stats().releases;
    s.contact_steps += !run.contacts->constraints().empty();
  }
  s.energy = de / e_ref;
  s.linear = dl / p_ref;
  s.angular = dj / (p_ref * size);
  return s;
}

/// Runs `make(Δt)` for six step sizes; checks and prints every one.
template <int D, class Make>
void sweep(const char* what, const std::vector<double>& steps, Make make, bool momenta) {
  ASSERT_GE(steps.size(), 6u);
  for (double dt : steps) {
    const Sweep s = run_sweep<D>(make(dt));
    std::printf("[ measured ] %s, Δt = %.1e s: max penetration %.2e × size, drift E %.2e L %.2e J %.2e, "
                "%d contact steps, %d activations, %d releases\n",
                what, dt, s.penetration, s.energy, s.linear, s.angular, s.contact_steps, s.activations, s.releases);
    EXPECT_GT(s.contact_steps, 10) << "Δt = " << dt;
    EXPECT_LE(s.penetration, 1e-12) << "Δt = " << dt;
    EXPECT_LE(s.energy, 1e-10) << "Δt = " << dt;
    if (!momenta) continue;
    EXPECT_LE(s.linear, 1e-10) << "Δt = " << dt;
    EXPECT_LE(s.angular, 1e-10) << "Δt = " << dt;
  }
}

TEST(NonPenetration, FrictionlessDiscSlidingInsideRing2d) {
  sweep<2>("frictionless disc inside a ring (concave master)", {2e-4, 3e-4, 5e-4, 7e-4, 1e-3, 1.5e-3},
           [](double dt) { return test::disc_inside_ring("frictionless", dt, 0.25); }, true);
}

TEST(NonPenetration, FrictionlessSpinningSpheres3d) {
  sweep<3>("frictionless spinning spheres (convex master)", {3e-4, 5e-4, 8e-4, 1e-3, 1.2e-3, 1.6e-3},
           [](double dt) { return test::spinning_spheres("frictionless", dt, 0.1); }, true);
}

// Written first: before the crease pair, the run at Δt = 6e-3 s ended a
// step with an active slave 1.3e-5 × the model size behind the ring facet
// next to its own, its constraint kept on its facet after the two facet
// switches a solve allows. The crease's second constraint is now activated
// as any slave is; in these runs its gap is above the tolerance each time,
// so the step is split where the slave reaches that facet (no pair is
// formed; ActiveSet::crease).
TEST(NonPenetration, LocatedDiscSlidingInsideRing2d) {
  sweep<2>(
      "located frictionless disc inside a ring (concave master)", {2e-3, 3e-3, 4e-3, 5e-3, 6e-3, 8e-3},
      [](double dt) { return test::located(test::disc_inside_ring("frictionless", dt, 0.25)); }, true);
}

// Written first: before the crease pair this run ended steps with an
// active slave up to 4.2e-5 × the model size behind a shell facet next to
// its own.
TEST(NonPenetration, LocatedSphereSlidingInsideShell3d) {
  const Sweep s = run_sweep<3>(test::located(test::sphere_inside_shell("frictionless", 4e-3, 0.15)));
  std::printf(
      "[ measured ] located frictionless sphere inside a shell, Δt = 4e-3 s: max penetration %.2e × size, "
      "drift E %.2e L %.2e J %.2e, %d contact steps, %d activations, %d releases\n",
      s.penetration, s.energy, s.linear, s.angular, s.contact_steps, s.activations, s.releases);
  EXPECT_GT(s.contact_steps, 10);
  EXPECT_LE(s.penetration, 1e-12);
  EXPECT_LE(s.energy, 1e-10);
  EXPECT_LE(s.linear, 1e-10);
  EXPECT_LE(s.angular, 1e-10);
}

TEST(NonPenetration, StickDiscRollingOnFloor2d) {
  sweep<2>("stick disc rolling on a rigid floor", {5e-4, 7e-4, 1e-3, 1.5e-3, 2e-3, 3e-3},
           [](double dt) { return test::disc_rolling_on_floor(dt, 0.6); }, false);
}

}  // namespace
}  // namespace conserve::time
