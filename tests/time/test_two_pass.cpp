// Two-pass and self-contact (docs/theory.md, "Two passes"): each side's nodes are
// held out of the other's facets. Slaves of the two passes that are each
// other's master nodes form cycles, eliminated together; constraints that
// repeat each other (slaves on each other's nodes) are left out. Checked
// on equal elastic balls meeting head-on (the meshes' nodes meet
// exactly: every constraint of the second pass repeats one of the first)
// and glancing: no node of either side behind the other's facets, E, L
// and J kept; one pass as the control. Steps retried (Newton not
// converging at an iterate where two slaves pass each other) are printed.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "contact_checks.hpp"
#include "support/files.hpp"

namespace conserve::time {
namespace {

using test::ContactRun;
using time::Diagnostics;

/// Two equal elastic balls (R = 0.05 m, 2D discs or 3D spheres) meeting at
/// 4 m/s (3 and −1 m/s), their centres `offset` apart across the line of
/// approach.
std::string equal_balls(int dim, double offset, int passes, double end, const std::string& method = "elimination") {
  const bool d3 = dim == 3;
  const std::string y = std::to_string(offset / 2.0);
  auto vec = [&](const std::string& a, const std::string& b) { return "[" + a + ", " + b + (d3 ? ", 0.0]" : "]"); };
  std::string body;
  for (int side = 0; side < 2; ++side) {
    const std::string sign = side == 0 ? "-" : "";
    body += R"(
[[body]]
name = ")" + std::string(side == 0 ? "a" : "b") +
            R"("
translate = )" +
            vec(sign + "0.0505", (side == 0 ? "" : "-") + y) + R"(
velocity = )" +
            vec(side == 0 ? "3.0" : "-1.0", "0.0") + R"(
[body.material]
young = 1.0e6
poisson = 0.3
density = 1000.0
[body.mesh]
generator = ")" +
            (d3 ? "sphere" : "disc") + R"("
radius = 0.05
size = )" + (d3 ? "0.02" : "0.01") +
            "\n";
  }
  return "dimension = " + std::to_string(dim) + R"(
[time]
step = 5e-4
end = )" +
         std::to_string(end) + "\n" + body + R"(
[[contact]]
slave = "a"
master = "b"
kind = "frictionless"
passes = )" +
         std::to_string(passes) + "\nmethod = \"" + method + "\"\n";
}

template <int D>
test::Drift collide(int passes, double offset, double end, int& cutbacks) {
  ContactRun<D> run(equal_balls(D, offset, passes, end));
  const test::Drift r = test::measure(run);
  cutbacks = run.cutbacks;
  std::printf(
      "[ measured ] %dD, offset %.3f m, %d pass(es): %d steps in contact, %d retried; drift E %.2e L %.2e "
      "J %.2e; deepest node behind: slave side %.2e m, master side %.2e m\n",
      D, offset, passes, r.contact_steps, cutbacks, r.energy, r.linear, r.angular, r.penetration, r.master_penetration);
  return r;
}

template <int D>
void expect_two_pass_holds(double offset, double end) {
  int cutbacks = 0;
  const test::Drift two = collide<D>(2, offset, end, cutbacks);
  EXPECT_GT(two.contact_steps, 10);
  EXPECT_LE(two.penetration, 1e-8);
  EXPECT_LE(two.master_penetration, 1e-8);
  EXPECT_LE(two.energy, 1e-10);
  EXPECT_LE(two.linear, 1e-10);
  EXPECT_LE(two.angular, 1e-10);
  const test::Drift one = collide<D>(1, offset, end, cutbacks);  // the control
  EXPECT_GT(one.master_penetration, 1e-5);
}

TEST(TwoPass, EqualDiscsHeadOnKeepBothSidesOut) { expect_two_pass_holds<2>(0.0, 0.04); }
TEST(TwoPass, EqualDiscsGlancingKeepBothSidesOut) { expect_two_pass_holds<2>(0.04, 0.04); }
TEST(TwoPass, EqualSpheresHeadOnKeepBothSidesOut) { expect_two_pass_holds<3>(0.0, 0.03); }
TEST(TwoPass, EqualSpheresGlancingKeepBothSidesOut) { expect_two_pass_holds<3>(0.02, 0.03); }

// The penalty's two passes: each side's nodes pushed out of the other's
// facets by their own springs, the energy (with the springs') kept.
TEST(TwoPass, PenaltyPushesBothSidesOut) {
  test::Drift pass[2];
  for (int passes = 1; passes <= 2; ++passes) {
    ContactRun<2> run(equal_balls(2, 0.04, passes, 0.04, "penalty"));
    pass[passes - 1] = test::measure(run);
    std::printf(
        "[ measured ] penalty, %d pass(es): drift E %.2e L %.2e J %.2e; deepest node behind: slave side "
        "%.2e m, master side %.2e m\n",
        passes, pass[passes - 1].energy, pass[passes - 1].linear, pass[passes - 1].angular,
        pass[passes - 1].penetration, pass[passes - 1].master_penetration);
  }
  EXPECT_LE(pass[1].energy, 1e-10);
  EXPECT_LE(pass[1].linear, 1e-10);
  EXPECT_LE(pass[1].angular, 1e-10);
  EXPECT_LT(pass[1].master_penetration, 0.7 * pass[0].master_penetration);
}

// The multipliers' two passes: the constraints elimination holds, its
// repeats and left-out constraints with λ = 0. Both sides kept out, E, L
// and J kept; the trajectory elimination's while neither retries a step
// (a located impact's time differs by the solvers' tolerance, about 1e-7 s
// here, and a retried step then makes the two runs' steps differ; head-on,
// node on node, the multipliers retry from the second step in contact).
TEST(TwoPass, MultipliersHoldBothSidesAsEliminationDoes) {
  for (const double offset : {0.0, 0.04}) {
    ContactRun<2> lagrange(equal_balls(2, offset, 2, 0.04, "lagrange"));
    ContactRun<2> elimination(equal_balls(2, offset, 2, 0.04));
    double differ = 0.0;
    int compared = 0;
    while (lagrange.cutbacks == 0 && elimination.cutbacks == 0 && compared < 40) {
      lagrange.step();
      elimination.step();
      if (lagrange.cutbacks > 0 || elimination.cutbacks > 0) break;
      differ = std::max(differ, (lagrange.state.u - elimination.state.u).lpNorm<Eigen::Infinity>());
      compared += !lagrange.contacts->constraints().empty();
    }
    ContactRun<2> run(equal_balls(2, offset, 2, 0.04, "lagrange"));
    const test::Drift r = test::measure(run);
    std::printf(
        "[ measured ] multipliers, discs offset %.2f m, two passes: %d steps in contact, %d retried; drift E %.2e "
        "L %.2e J %.2e; deepest node behind %.2e m, %.2e m; against elimination over %d steps in contact before "
        "a retry: %.1e m\n",
        offset, r.contact_steps, run.cutbacks, r.energy, r.linear, r.angular, r.penetration, r.master_penetration,
        compared, differ);
    EXPECT_GT(r.contact_steps, 10);
    EXPECT_LE(r.penetration, 1e-8);
    EXPECT_LE(r.master_penetration, 1e-8);
    EXPECT_LE(r.energy, 1e-10);
    EXPECT_LE(r.linear, 1e-10);
    EXPECT_LE(r.angular, 1e-10);
    if (offset == 0.0) continue;  // head-on: the multipliers retry the second step in contact
    EXPECT_GE(compared, 5);
    EXPECT_LE(differ, 1e-4);
  }
}

// The reduced tangent with slaves of both passes in cycles, at an iterate
// of a step in contact, by the Taylor test.
TEST(TwoPass, ReducedTangentWithCyclesMatchesDifferences2d) {
  ContactRun<2> run(equal_balls(2, 0.04, 2, 0.04));
  test::run_until_contact(run, 6, 200);
  for (int n = 0; n < 3; ++n) run.step();
  int second = 0;
  for (const auto& c : run.contacts->constraints()) second += run.contacts->pairs()[c.pair].second_pass;
  ASSERT_GT(second, 0) << "no constraint of the second pass";
  test::expect_second_order(test::reduced_tangent_order(run), "2D, two passes");
}

// Self-contact: the ring's inner face held off itself once the plates
// have flattened it; the energy with the plates' work, and L_x (the
// plates push along y only), kept.
TEST(SelfContact, CrushedRingsInnerFaceHoldsItselfOff) {
  // examples/crush/ring_fold.toml: a thin ring (R = 0.1 m, wall 10 mm)
  // crushed between plates closing at 1 m/s each, its inner face paired
  // with itself.
  ContactRun<2> run(test::slurp(std::string(CONSERVE_SOURCE_DIR) + "/examples/crush/ring_fold.toml"));
  const Diagnostics d0 = run.diagnostics();
  double e_ref = 0.0, energy = 0.0, linear_x = 0.0, penetration = 0.0, l_ref = 0.0;
  int self_steps = 0;
  while (run.state.time < run.scenario.time.end - 1e-9 * run.scenario.time.step) {
    run.step();
    const Diagnostics d = run.diagnostics();
    e_ref = std::max(e_ref, d.kinetic + d.strain);
    l_ref = std::max(l_ref, d.momentum_magnitude);
    energy = std::max(energy, std::abs(d.total - d0.total));
    linear_x = std::max(linear_x, std::abs(d.linear.x() - d0.linear.x()));
    penetration = std::max({penetration, run.last.contact.slave_penetration, run.last.contact.master_penetration});
    bool self = false;
    for (const auto& c : run.contacts->constraints()) self = self || run.contacts->pairs()[c.pair].self;
    self_steps += self;
  }
  std::printf(
      "[ measured ] crushed ring: %d steps with self-contact, %d retried; drift E (with the plates' work) "
      "%.2e, L_x %.2e; deepest node behind %.2e m\n",
      self_steps, run.cutbacks, energy / e_ref, linear_x / l_ref, penetration);
  EXPECT_GT(self_steps, 5);
  EXPECT_LE(energy / e_ref, 1e-10);
  EXPECT_LE(linear_x / l_ref, 1e-10);
  EXPECT_LE(penetration, 1e-8);
}

/// `rows` × `rows` elastic discs (R = 12 mm) dropped into a rigid box
/// under gravity, every contact from one [general_contact] table.
std::string discs_in_a_box(int rows, double end) {
  std::string text = "dimension = 2\n[time]\nstep = 1e-3\nend = " + std::to_string(end) +
                     "\n[loads]\ngravity = [0.0, -9.81]\n[general_contact]\n";
  const double half = 0.015 * rows + 0.005;
  const std::string walls[3][5] = {{"floor", "0.0", "-0.01", std::to_string(2 * half), "0.02"},
                                   {"left", std::to_string(-half - 0.01), "0.2", "0.02", "0.44"},
                                   {"right", std::to_string(half + 0.01), "0.2", "0.02", "0.44"}};
  for (const auto& w : walls)
    text += "[[body]]\nname = \"" + w[0] + "\"\nrigid = true\ntranslate = [" + w[1] + ", " + w[2] +
            "]\n[body.mesh]\ngenerator = \"rectangle\"\nlx = " + w[3] + "\nly = " + w[4] + "\nsize = 0.02\n";
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < rows; ++i)
      text += "[[body]]\nname = \"d" + std::to_string(j * rows + i) + "\"\ntranslate = [" +
              std::to_string(-half + 0.015 + 0.03 * i + (j % 2 ? 0.005 : 0.0)) + ", " +
              std::to_string(0.015 + 0.03 * j) +
              "]\nvelocity = [0.0, -0.5]\n[body.material]\nyoung = 1.0e6\npoisson = 0.3\ndensity = 1000.0\n"
              "[body.mesh]\ngenerator = \"disc\"\nradius = 0.012\nsize = 0.006\n";
  return text;
}

// General contact: one table pairs every disc with every other (two
// passes), with the walls and with itself; the energy with gravity's
// potential is kept and no node of any side ends behind a facet.
TEST(GeneralContact, DiscsPouredIntoABoxKeepEnergyAndStayOut) {
  ContactRun<2> run(discs_in_a_box(3, 0.05));
  EXPECT_EQ(run.contacts->pairs().size(), 3u * 9u + 2u * 36u + 9u);  // walls, disc pairs (two passes), selves
  const test::Drift r = test::measure(run);
  std::printf(
      "[ measured ] 9 discs in a box: %d steps in contact, %d retried; drift E %.2e; deepest node behind: "
      "%.2e m, %.2e m\n",
      r.contact_steps, run.cutbacks, r.energy, r.penetration, r.master_penetration);
  EXPECT_GT(r.contact_steps, 10);
  EXPECT_LE(r.energy, 1e-10);
  EXPECT_LE(r.penetration, 1e-8);
  EXPECT_LE(r.master_penetration, 1e-8);
}

/// The paper's §6.1 (examples/cylinders/three_cylinders.toml: thin
/// cylinders, 5 mm tall, sliding into each other) to `end`, its contacts
/// replaced by `contacts`.
std::string thin_cylinders(const std::string& contacts, double end) {
  std::string text = test::slurp(std::string(CONSERVE_SOURCE_DIR) + "/examples/cylinders/three_cylinders.toml");
  text = text.substr(0, text.find("[[contact]]")) + contacts;
  const std::size_t at = text.find("end = ");
  return text.substr(0, at) + "end = " + std::to_string(end) + text.substr(text.find('\n', at));
}

// General contact on thin bodies: every cylinder's whole boundary against
// the others' and its own. A node is behind its own far facets by the
// thickness and behind the top of a cylinder whose side it presses: neither
// is its contact (self-contact needs a node that came from in front; the
// nearest facet is the side). The run is the one of the pairs written out
// in two passes, step for step.
TEST(GeneralContact, ThinCylindersMoveAsTheirPairsInTwoPasses) {
  const double end = 0.01;
  ContactRun<3> general(thin_cylinders("[general_contact]\nkind = \"frictionless\"\n", end));
  ContactRun<3> pairs(thin_cylinders(R"([[contact]]
slave = "c1:side"
master = "c2:side"
kind = "frictionless"
passes = 2
[[contact]]
slave = "c2:side"
master = "c3:side"
kind = "frictionless"
passes = 2
[[contact]]
slave = "c1:zmin"
master = "plane:surface"
kind = "frictionless"
[[contact]]
slave = "c2:zmin"
master = "plane:surface"
kind = "frictionless"
[[contact]]
slave = "c3:zmin"
master = "plane:surface"
kind = "frictionless"
)",
                                     end));
  const Diagnostics d0 = general.diagnostics();
  double differ = 0.0, energy = 0.0, penetration = 0.0;
  int self = 0, steps = 0, in_contact = 0;
  while (general.state.time < end - 1e-9) {
    general.step();
    pairs.step();
    ++steps;
    ASSERT_EQ(general.state.time, pairs.state.time);
    differ = std::max(differ, (general.state.u - pairs.state.u).lpNorm<Eigen::Infinity>());
    energy = std::max(energy, std::abs(general.diagnostics().total - d0.total) / d0.total);
    penetration =
        std::max({penetration, general.last.contact.slave_penetration, general.last.contact.master_penetration});
    for (const auto& c : general.contacts->constraints()) self += general.contacts->pairs()[c.pair].self;
    in_contact += !general.contacts->constraints().empty();
  }
  std::printf(
      "[ measured ] thin cylinders, general contact against pairs: %d steps (%d in contact), largest "
      "difference %.1e m; E drift %.1e; deepest node behind %.1e m; self-contact constraints %d\n",
      steps, in_contact, differ, energy, penetration, self);
  EXPECT_GT(in_contact, 3);
  EXPECT_EQ(self, 0);
  EXPECT_LE(differ, 1e-12);  // identical here; a 1e-10 share of the 1 cm the cylinders move
  EXPECT_LE(energy, 1e-10);
  EXPECT_LE(penetration, 1e-8);
}

}  // namespace
}  // namespace conserve::time
