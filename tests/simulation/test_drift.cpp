// What a scenario conserves (simulation/drift.hpp), and drifts taken as the
// largest deviation over the run's own scale: a first step from rest,
// with a tiny scale, no longer sets the run's drift.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "io/scenario.hpp"
#include "simulation/drift.hpp"

namespace conserve::simulation {
namespace {

/// A 3D box `a` and `extra` tables.
Conservation of(const std::string& extra, int dimension = 3) {
  const std::string body =
      dimension == 3 ? "[[body]]\nname = \"a\"\n[body.material]\nyoung = 1e6\npoisson = 0.3\ndensity = 1000\n"
                       "[body.mesh]\ngenerator = \"box\"\nlx = 1\nly = 1\nlz = 1\nsize = 0.5\n"
                     : "[[body]]\nname = \"a\"\n[body.material]\nyoung = 1e6\npoisson = 0.3\ndensity = 1000\n"
                       "[body.mesh]\ngenerator = \"rectangle\"\nlx = 1\nly = 1\nsize = 0.5\n";
  const std::string text =
      "dimension = " + std::to_string(dimension) + "\n[time]\nstep = 0.01\nend = 0.1\n" + extra + body;
  return conservation(io::parse_scenario(text, "case.toml"));
}

TEST(Drift, FreeBodiesConserveEverything) {
  const Conservation c = of("");
  for (int q = 0; q < kQuantities; ++q) EXPECT_TRUE(c.conserved(q)) << kQuantityNames[q];
}

TEST(Drift, GravityAlongZKeepsLxLyAndJz) {
  const Conservation c = of("[loads]\ngravity = [0, 0, -9.81]\n");
  for (const int q : {0, 1, 2, 6}) EXPECT_TRUE(c.conserved(q)) << kQuantityNames[q];
  for (const int q : {3, 4, 5}) EXPECT_EQ(c.why_not[q], "gravity") << kQuantityNames[q];
}

TEST(Drift, TwoDimensionsHaveNoLzJxJy) {
  const Conservation c = of("[loads]\ngravity = [0, -9.81]\n", 2);
  for (const int q : {3, 4, 5}) EXPECT_FALSE(c.present[q]);
  EXPECT_TRUE(c.conserved(1));
  EXPECT_EQ(c.why_not[2], "gravity");
  EXPECT_EQ(c.why_not[6], "gravity");
}

TEST(Drift, ASupportTakesItsComponentsAndEveryMoment) {
  const Conservation c = of("[[boundary]]\nbody = \"a\"\ngroup = \"zmin\"\ncomponents = [\"z\"]\n");
  EXPECT_TRUE(c.conserved(0));
  EXPECT_TRUE(c.conserved(1));
  EXPECT_TRUE(c.conserved(2));
  EXPECT_EQ(c.why_not[3], "supports");
  for (const int q : {4, 5, 6}) EXPECT_EQ(c.why_not[q], "supports") << kQuantityNames[q];
}

TEST(Drift, TheMidpointStressDoesNotConserveEnergy) {
  EXPECT_EQ(of("").why_not[0], "");
  const Conservation c = conservation(io::parse_scenario(
      "dimension = 3\n[time]\nstep = 0.01\nend = 0.1\nscheme = \"midpoint\"\n[[body]]\nname = \"a\"\n"
      "[body.material]\nyoung = 1e6\npoisson = 0.3\ndensity = 1000\n[body.mesh]\ngenerator = \"box\"\nlx = 1\n"
      "ly = 1\nlz = 1\nsize = 0.5\n",
      "case.toml"));
  EXPECT_EQ(c.why_not[0], "the mid-point stress");
  EXPECT_TRUE(c.conserved(1));
}

// Stick and Coulomb friction keep J (docs/theory.md (S2)), with every method.
TEST(Drift, StickAndCoulombKeepAngularMomentum) {
  const std::string b =
      "[[body]]\nname = \"b\"\ntranslate = [2, 0, 0]\n[body.material]\nyoung = 1e6\npoisson = 0.3\n"
      "density = 1000\n[body.mesh]\ngenerator = \"box\"\nlx = 1\nly = 1\nlz = 1\nsize = 0.5\n";
  const std::string pair = "[[contact]]\nslave = \"a:xmax\"\nmaster = \"b:xmin\"\n";
  for (const char* kind : {"kind = \"stick\"\n", "kind = \"stick\"\nmethod = \"penalty\"\n",
                           "kind = \"coulomb\"\nfriction = 0.3\n"}) {
    const Conservation c = of(b + pair + kind);
    for (int q = 0; q < kQuantities; ++q) EXPECT_TRUE(c.conserved(q)) << kind << kQuantityNames[q];
  }
}

time::Diagnostics state(double kinetic, double total, double lx) {
  time::Diagnostics d;
  d.kinetic = kinetic;
  d.total = total;
  d.linear.x() = lx;
  d.momentum_magnitude = std::abs(lx) + 1.0;
  return d;
}

// From rest, a deviation of 1e-20 J at a first step whose K is 1e-18 J
// would be a drift of 1e-2 against that step's scale; against the run's
// (1 J later) it is 1e-20.
TEST(Drift, TheRunsScaleNotTheFirstSteps) {
  const DriftTracker tracker(1.0, state(0.0, 0.0, 0.0), of(""));
  DriftState s;
  const Drifts first = tracker.add(state(1e-18, 1e-20, 0.0), s);
  EXPECT_DOUBLE_EQ(first.energy, 1e-2);  // so far: that step's own scale
  tracker.add(state(1.0, 5e-21, 0.0), s);
  EXPECT_DOUBLE_EQ(tracker.drift(0, s), 1e-20);
  EXPECT_DOUBLE_EQ(tracker.reference(0, s), 1.0);
}

TEST(Drift, AQuantityNotConservedHasNoDrift) {
  const DriftTracker tracker(1.0, state(1.0, 1.0, 0.0), of("[loads]\ngravity = [9.81, 0, 0]\n"));
  DriftState s;
  const Drifts d = tracker.add(state(1.0, 1.0, 3.0), s);
  EXPECT_TRUE(std::isnan(tracker.drift(1, s)));  // L_x: gravity
  EXPECT_EQ(d.linear, 0.0);                      // L_y, L_z: conserved, unchanged
  EXPECT_EQ(d.energy, 0.0);
}

}  // namespace
}  // namespace conserve::simulation
