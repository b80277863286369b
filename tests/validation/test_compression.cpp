// Uniaxial compression by a slow rigid plate (issue 52, must-show 2): a
// block (E = 1 MPa, ν = 0.3, 0.1 m) on a frictionless held base (z held,
// x and y free) is compressed by a rigid plate coming down at 1 mm/s
// (ramped in over 50 ms, about 16 wave transits). Quasi-static, small
// strain (≤ 0.3 %): the plate's reaction against its indentation is
// E A δ / L, and the base holds what the plate pushes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "support/contact_run.hpp"

namespace conserve::test {
namespace {

constexpr double kYoung = 1e6, kSide = 0.1, kGap = 1e-4;

const char* kCompression = R"(dimension = 3
[time]
step = 2e-3
end = 0.4
[[curve]]
name = "ramp"
points = [[0.0, 0.0], [0.05, 1.0]]
[[body]]
name = "block"
[body.material]
young = 1.0e6
poisson = 0.3
density = 1000.0
[body.mesh]
generator = "box"
lx = 0.1
ly = 0.1
lz = 0.1
size = 0.025
[[boundary]]
body = "block"
group = "zmin"
components = ["z"]
[[body]]
name = "plate"
rigid = true
translate = [0.0, 0.0, 0.0751]
velocity = [0.0, 0.0, -0.001]
velocity_curve = "ramp"
[body.mesh]
generator = "box"
lx = 0.14
ly = 0.14
lz = 0.05
size = 0.07
[[contact]]
slave = "block:zmax"
master = "plate:zmin"
kind = "frictionless"
)";

/// The least-squares slope of y against x through the points.
double slope(const std::vector<double>& x, const std::vector<double>& y) {
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) n += 1, sx += x[i], sy += y[i], sxx += x[i] * x[i], sxy += x[i] * y[i];
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

TEST(Compression, ReactionAgainstIndentationIsEADeltaOverL) {
  ContactRun<3> run(kCompression);
  // Supports: block:zmin (0), plate (1).
  ASSERT_EQ(run.problem.model.prescribed.supports.size(), 2u);
  std::vector<double> delta, plate, base;
  while (run.state.time < run.scenario.time.end - 1e-9) {
    run.step();
    const double d = -run.state.u[run.problem.model.prescribed.dofs.back()] - kGap;  // the plate's top node: rigid
    if (d < 0.5 * kGap) continue;
    delta.push_back(d);
    plate.push_back(-run.last.supports[1].force.z());
    base.push_back(run.last.supports[0].force.z());
  }
  ASSERT_GT(delta.size(), 50u);
  const double stiffness = kYoung * kSide * kSide / kSide;  // E A / L
  const double k_plate = slope(delta, plate), k_base = slope(delta, base);
  const double expected = stiffness * delta.back();
  std::printf("[ measured ] uniaxial compression to %.2e m: plate %.3f N, base %.3f N, E A d / L %.3f N; slopes "
              "%.4g and %.4g N/m against E A / L %.4g N/m (%.2f %%, %.2f %%)\n",
              delta.back(), plate.back(), base.back(), expected, k_plate, k_base, stiffness,
              100.0 * (k_plate / stiffness - 1.0), 100.0 * (k_base / stiffness - 1.0));
  EXPECT_NEAR(k_plate, stiffness, 0.02 * stiffness);
  EXPECT_NEAR(k_base, stiffness, 0.02 * stiffness);
  EXPECT_NEAR(plate.back(), expected, 0.02 * expected);
  EXPECT_NEAR(base.back(), plate.back(), 0.02 * plate.back());
}

}  // namespace
}  // namespace conserve::test
