// Surface loads (time/surface_loads.hpp) on free bodies: a constant
// nominal traction keeps E with its potential; a follower pressure that
// follows a curve keeps E − load_work, and L and J (no resultant, no
// moment on a closed surface); a traction with a curve keeps E − load_work;
// on linear cells and on quadratic ones (loads integrated with the P2
// shape functions).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "support/contact_run.hpp"

namespace conserve::time {
namespace {

using test::ContactRun;

/// A free, spinning elastic box (3D) or rectangle (2D) of cells of `order`,
/// no gravity, with `loads`.
std::string free_body(int dim, const std::string& loads, int order) {
  const bool d3 = dim == 3;
  return "dimension = " + std::to_string(dim) +
         "\n[time]\nstep = 2e-3\nend = 0.1\n[newton]\nresidual_tolerance = 1e-15\n[output]\nvtu_every = 0\n"
         "[[curve]]\nname = \"ramp\"\npoints = [[0, 0], [0.05, 1], [0.08, 0.2]]\n"
         "[[body]]\nname = \"block\"\n" +
         (d3 ? "angular_velocity = [0.5, 1.0, 3.0]\n" : "angular_velocity = 3.0\n") +
         "[body.material]\nmodel = \"neo_hookean\"\nyoung = 1.0e5\npoisson = 0.3\ndensity = 1000.0\n[body.mesh]\n" +
         (d3 ? "generator = \"box\"\nlx = 0.4\nly = 0.3\nlz = 0.2\nsize = 0.1\n"
             : "generator = \"rectangle\"\nlx = 0.4\nly = 0.3\nsize = 0.05\n") +
         "order = " + std::to_string(order) + "\n" + loads;
}

struct Balance {
  double energy = 0.0, linear = 0.0, angular = 0.0;  ///< largest relative drifts
  double work = 0.0;                                  ///< load_work at the end [J]
  double potential = 0.0;                             ///< the largest |potential| [J]
};

template <int D>
Balance run(const std::string& toml) {
  ContactRun<D> run(toml);
  const Diagnostics d0 = run.diagnostics();
  Balance b;
  double e_ref = d0.kinetic + d0.strain, l_ref = d0.momentum_magnitude;
  while (run.state.time < run.scenario.time.end - 1e-12) {
    run.step();
    const Diagnostics d = run.diagnostics();
    e_ref = std::max(e_ref, d.kinetic + d.strain);
    l_ref = std::max(l_ref, d.momentum_magnitude);
    b.energy = std::max(b.energy, std::abs(d.total - d0.total) / e_ref);
    b.linear = std::max(b.linear, (d.linear - d0.linear).norm() / l_ref);
    b.angular = std::max(b.angular, (d.angular - d0.angular).norm() / (l_ref * run.problem.model.size()));
    b.potential = std::max(b.potential, std::abs(d.potential));
    b.work = d.load_work;
  }
  return b;
}

template <int D>
void check_loads(int order) {
  const Balance traction =
      run<D>(free_body(D, D == 3 ? "[[load]]\nbody = \"block\"\ngroup = \"xmin\"\ntraction = [2.0e3, 1.0e3, -5.0e2]\n"
                                 : "[[load]]\nbody = \"block\"\ngroup = \"xmin\"\ntraction = [2.0e3, 1.0e3]\n", order));
  const Balance pressure =
      run<D>(free_body(D, "[[load]]\nbody = \"block\"\npressure = 2.0e4\ncurve = \"ramp\"\n", order));
  const Balance ramped =
      run<D>(free_body(D, D == 3 ? "[[load]]\nbody = \"block\"\ngroup = \"xmin\"\ntraction = [2.0e3, 1.0e3, -5.0e2]\n"
                                   "curve = \"ramp\"\n"
                                 : "[[load]]\nbody = \"block\"\ngroup = \"xmin\"\ntraction = [2.0e3, 1.0e3]\n"
                                   "curve = \"ramp\"\n", order));
  std::string gravity = free_body(D, "", order);
  gravity.insert(gravity.find("[[curve]]"), D == 3 ? "[loads]\ngravity = [0.0, -3.0, -9.81]\ngravity_curve = \"ramp\"\n"
                                                   : "[loads]\ngravity = [-3.0, -9.81]\ngravity_curve = \"ramp\"\n");
  const Balance ramped_gravity = run<D>(gravity);
  std::printf("[ measured ] %dD order %d gravity with a curve: E - load_work %.2e (load_work %.3e J)\n", D, order,
              ramped_gravity.energy, ramped_gravity.work);
  EXPECT_GT(std::abs(ramped_gravity.work), 1e-2);
  EXPECT_EQ(ramped_gravity.potential, 0.0);  // its work is counted, not a potential
  EXPECT_LT(ramped_gravity.energy, 1e-10);
  std::printf("[ measured ] %dD order %d constant traction: E + potential drift %.2e (potential up to %.2e J); follower "
              "pressure with a curve: E - load_work %.2e, L %.2e, J %.2e (load_work %.3e J); traction with a curve: "
              "E - load_work %.2e (load_work %.3e J)\n",
              D, order, traction.energy, traction.potential, pressure.energy, pressure.linear, pressure.angular, pressure.work,
              ramped.energy, ramped.work);
  EXPECT_GT(traction.potential, 1.0);  // the traction did work
  EXPECT_LT(traction.energy, 1e-10);
  EXPECT_GT(std::abs(pressure.work), 1e-3);
  EXPECT_LT(pressure.energy, 1e-10);
  EXPECT_LT(pressure.linear, 1e-10);
  EXPECT_LT(pressure.angular, 1e-10);
  EXPECT_GT(std::abs(ramped.work), 1e-2);
  EXPECT_LT(ramped.energy, 1e-10);
}

TEST(SurfaceLoads, ConserveWithTheirPotentialOrWork2d) { check_loads<2>(1); }
TEST(SurfaceLoads, ConserveWithTheirPotentialOrWork3d) { check_loads<3>(1); }
TEST(SurfaceLoads, ConserveWithTheirPotentialOrWorkQuadratic2d) { check_loads<2>(2); }
TEST(SurfaceLoads, ConserveWithTheirPotentialOrWorkQuadratic3d) { check_loads<3>(2); }

}  // namespace
}  // namespace conserve::time
