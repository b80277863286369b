// Lagrange multipliers (contact/lagrange/, issue 46): the constraints
// elimination holds, imposed by extra unknowns, give elimination's
// trajectory to the solvers' tolerance, conserve as it does, and the
// number of equations follows the active set.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "contact_checks.hpp"
#include "support/contact_run.hpp"
#include "support/files.hpp"
#include "support/contact_scenarios.hpp"

namespace conserve::time {
namespace {

using test::ContactRun;

struct Parting {
  double worst = 0.0;   ///< largest |u_L − u_E| / (largest |u_E − u_0|) over the steps
  int contact_steps = 0;
  int equations_seen = 0;  ///< distinct equation counts of the multiplier run
  double energy = 0.0;     ///< the multiplier run's relative energy drift
};

/// Steps `toml` with elimination and with multipliers side by side.
template <int D>
Parting side_by_side(const std::string& toml) {
  ContactRun<D> elimination(toml);
  ContactRun<D> lagrange(test::with_method(toml, "lagrange"));
  EXPECT_EQ(lagrange.method->name(), "lagrange");
  const Eigen::VectorXd u0 = elimination.state.u;
  const Diagnostics d0 = lagrange.diagnostics();
  const int steps = static_cast<int>(std::round(elimination.scenario.time.end / elimination.scenario.time.step));
  const int free = elimination.problem.model.num_dofs() - static_cast<int>(elimination.problem.model.prescribed.dofs.size());
  Parting p;
  double motion = 0.0, e_ref = std::abs(d0.total);
  std::vector<int> counts;
  for (int n = 0; n < steps; ++n) {
    elimination.step();
    lagrange.step();
    motion = std::max(motion, (elimination.state.u - u0).cwiseAbs().maxCoeff());
    p.worst = std::max(p.worst, (lagrange.state.u - elimination.state.u).cwiseAbs().maxCoeff() / motion);
    const int held = static_cast<int>(elimination.contacts->constraints().size());
    p.contact_steps += held > 0;
    // The last solve's system: the free unknowns and one multiplier per
    // constrained direction of the active set it was solved with.
    int multipliers = 0;
    for (const auto& c : lagrange.contacts->constraints()) multipliers += c.kind == contact::Kind::stick ? D : 1;
    if (lagrange.last.contact.passes == 1) EXPECT_EQ(lagrange.last.contact.equations, free + multipliers);
    if (std::find(counts.begin(), counts.end(), lagrange.last.contact.equations) == counts.end())
      counts.push_back(lagrange.last.contact.equations);
    const Diagnostics d = lagrange.diagnostics();
    e_ref = std::max(e_ref, d.kinetic + d.strain);
    p.energy = std::max(p.energy, std::abs(d.total - d0.total) / e_ref);
  }
  p.equations_seen = static_cast<int>(counts.size());
  return p;
}

const char* kDirect = "[solver]\nmethod = \"direct\"\n";

// The comparisons run the paper's scheme. With impacts located, a step
// ends where a Newton iterate first shows the crossing (time/integrator.cpp),
// and the two methods' iterates differ: on the 2D glancing impact the first
// split instants differ by 7.6e-5 Δt, and the runs part by 3.9e-5 of the
// motion, each within its gap tolerance.

TEST(LagrangeContact, EliminationsTrajectoryThroughAnImpact2d) {
  const Parting p = side_by_side<2>(test::paper(test::glancing_spheres(2, "frictionless", 0.1)) + kDirect);
  std::printf("[ measured ] multipliers vs elimination, glancing impact 2D: parted by %.1e of the motion; E %.1e; "
              "%d equation counts\n",
              p.worst, p.energy, p.equations_seen);
  EXPECT_GT(p.contact_steps, 5);
  EXPECT_LT(p.worst, 1e-8);
  EXPECT_LT(p.energy, 1e-10);
  EXPECT_GT(p.equations_seen, 2);
}

TEST(LagrangeContact, EliminationsTrajectoryThroughAnImpact3d) {
  const Parting p = side_by_side<3>(test::paper(test::glancing_spheres(3, "frictionless", 0.1)) + kDirect);
  std::printf("[ measured ] multipliers vs elimination, glancing impact 3D: parted by %.1e of the motion; E %.1e; "
              "%d equation counts\n",
              p.worst, p.energy, p.equations_seen);
  EXPECT_GT(p.contact_steps, 5);
  EXPECT_LT(p.worst, 1e-8);
  EXPECT_LT(p.energy, 1e-10);
}

// With another law (and its discrete gradient) the two methods still solve
// the same equations.
TEST(LagrangeContact, EliminationsTrajectoryWithNeoHookean) {
  std::string toml = test::paper(test::glancing_spheres(2, "frictionless", 0.1)) + kDirect;
  for (std::size_t at = toml.find("[body.material]\n"); at != std::string::npos;
       at = toml.find("[body.material]\n", at + 1))
    toml.insert(at + 16, "model = \"neo_hookean\"\n");
  const Parting p = side_by_side<2>(toml);
  std::printf("[ measured ] multipliers vs elimination, neo-Hookean discs: parted by %.1e of the motion; E %.1e\n",
              p.worst, p.energy);
  EXPECT_GT(p.contact_steps, 5);
  EXPECT_LT(p.worst, 1e-8);
  EXPECT_LT(p.energy, 1e-10);
}

// The paper's §6.1 (three quasi-rigid cylinders on a plane): the middle
// cylinder is master of both others and slave of the plane, a chain that
// elimination composes and the multipliers pass on. The first contact step
// agrees to round-off; from the next the active sets, which round-off
// decides on these quasi-rigid bodies (tens of slaves within 1e-13 m of
// zero gap), part; both keep E.
TEST(LagrangeContact, ChainOfThreeCylinders) {
  std::string toml = test::slurp(std::string(CONSERVE_SOURCE_DIR) + "/examples/cylinders/three_cylinders.toml");
  toml.replace(toml.find("end = 1.2"), 9, "end = 0.04");
  toml += kDirect;
  ContactRun<3> elimination(toml);
  ContactRun<3> lagrange(test::with_method(toml, "lagrange"));
  const Diagnostics d0 = lagrange.diagnostics();
  elimination.step();
  lagrange.step();
  ASSERT_GT(elimination.contacts->constraints().size(), 10U);
  const double first = (lagrange.state.u - elimination.state.u).cwiseAbs().maxCoeff() /
                       (elimination.state.u - elimination.problem.initial.u).cwiseAbs().maxCoeff();
  double energy = 0.0;
  for (int n = 1; n < 20; ++n) {
    lagrange.step();
    energy = std::max(energy, std::abs(lagrange.diagnostics().total - d0.total) / std::abs(d0.total));
  }
  std::printf("[ measured ] multipliers vs elimination, 6.1's first step: %.1e of the motion; E over 20 steps %.1e\n",
              first, energy);
  EXPECT_LT(first, 1e-10);
  EXPECT_LT(energy, 1e-10);
}

TEST(LagrangeContact, EliminationsTrajectoryWithStick) {
  const Parting p = side_by_side<3>(test::ball_on_plane("stick", 0.12) + kDirect);
  std::printf("[ measured ] multipliers vs elimination, ball with stick: parted by %.1e of the motion; E %.1e\n",
              p.worst, p.energy);
  EXPECT_GT(p.contact_steps, 10);
  EXPECT_LT(p.worst, 1e-8);
  EXPECT_LT(p.energy, 1e-10);
}

// The multipliers' system tangent, B's own variation included, against
// differences at the glancing spheres' solution once they touch (the
// Coulomb case: Friction.MultipliersTangentOfSlippingSlaves...).
template <int D>
void system_tangent_is_consistent(const std::string& kind) {
  ContactRun<D> run(test::with_method(test::glancing_spheres(D, kind, 0.1), "lagrange"));
  test::run_until_contact(run, D, 150);
  test::expect_second_order(test::system_tangent_order(run), std::to_string(D) + "D, " + kind);
}

TEST(LagrangeContact, SystemTangentMatchesDifferencesFrictionless2d) { system_tangent_is_consistent<2>("frictionless"); }
TEST(LagrangeContact, SystemTangentMatchesDifferencesFrictionless3d) { system_tangent_is_consistent<3>("frictionless"); }
TEST(LagrangeContact, SystemTangentMatchesDifferencesStick2d) { system_tangent_is_consistent<2>("stick"); }
TEST(LagrangeContact, SystemTangentMatchesDifferencesStick3d) { system_tangent_is_consistent<3>("stick"); }

}  // namespace
}  // namespace conserve::time
