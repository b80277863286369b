// Penalty contact through the stepper (contact/penalty/, issue 46): with
// the discrete-gradient force a glancing impact of two deformable bodies
// conserves the total energy including the springs', L and J, with every
// law; the mid-point force (the negative control) does not; stick conserves
// once the springs' energy let go at release is counted; the penetration
// falls as ε grows; the elimination's constraints and the penalty's
// couplings come back from their bytes; and the history's `equations` is
// the linear system's size.
#include <gtest/gtest.h>

#include <random>

#include <cmath>
#include <cstdio>
#include <string>

#include "contact/penalty/penalty.hpp"
#include "core/error.hpp"
#include "support/contact_run.hpp"
#include "support/taylor.hpp"
#include "support/contact_scenarios.hpp"

namespace conserve::time {
namespace {

using test::ContactRun;

using test::Drift;
using test::measure;

template <int D>
Drift glancing(const std::string& keys, const std::string& model_keys = "") {
  std::string toml = test::with_method(test::glancing_spheres(D, "frictionless", 0.1), "penalty", keys);
  if (!model_keys.empty()) {
    for (std::size_t at = toml.find("[body.material]\n"); at != std::string::npos;
         at = toml.find("[body.material]\n", at + 1))
      toml.insert(at + 16, model_keys);
  }
  ContactRun<D> run(toml);
  EXPECT_EQ(run.method->name(), "penalty");
  return measure<D>(run);
}

void print(const char* what, const Drift& r) {
  std::printf("[ measured ] %s: E %.2e  L %.2e  J %.2e  (E + released %.2e; %d steps with springs, largest %.3g J; "
              "penetration %.3g m)\n",
              what, r.energy, r.linear, r.angular, r.counted, r.contact_steps, r.spring, r.penetration);
}

// Two deformable discs: E with the springs' energy, L and J to round-off.
TEST(PenaltyContact, GlancingImpactConservesEnergyAndMomenta2d) {
  const Drift r = glancing<2>("");
  print("penalty, glancing impact 2D", r);
  EXPECT_GT(r.contact_steps, 5);
  EXPECT_GT(r.spring, 0.0);
  EXPECT_LT(r.energy, 1e-10);
  EXPECT_LT(r.linear, 1e-10);
  EXPECT_LT(r.angular, 1e-10);
  EXPECT_EQ(r.released, 0.0);
}

TEST(PenaltyContact, GlancingImpactConservesEnergyAndMomenta3d) {
  const Drift r = glancing<3>("");
  print("penalty, glancing impact 3D", r);
  EXPECT_GT(r.contact_steps, 5);
  EXPECT_LT(r.energy, 1e-10);
  EXPECT_LT(r.linear, 1e-10);
  EXPECT_LT(r.angular, 1e-10);
  EXPECT_EQ(r.released, 0.0);
}

// The negative control: the penalty force at the mid-point configuration.
TEST(PenaltyContact, MidPointForceDoesNotConserve) {
  const Drift r = glancing<3>("penalty_force = \"midpoint\"\n");
  print("penalty, mid-point force, glancing impact 3D", r);
  EXPECT_GT(r.contact_steps, 5);
  EXPECT_GT(r.energy, 1e-6);
}

TEST(PenaltyContact, GlancingImpactConservesWithEveryLaw) {
  for (const char* law : {"model = \"neo_hookean\"\n"}) {
    const Drift r = glancing<3>("", law);
    print("neo_hookean, glancing impact 3D", r);
    EXPECT_LT(r.energy, 1e-10);
    EXPECT_LT(r.linear, 1e-10);
  }
  // Mooney–Rivlin takes its own constants.
  std::string toml = test::with_method(test::glancing_spheres(2, "frictionless", 0.1), "penalty");
  for (std::size_t at = toml.find("young = "); at != std::string::npos; at = toml.find("young = ", at + 1)) {
    const std::size_t end = toml.find("poisson", at);
    const std::size_t line = toml.find('\n', end);
    toml.replace(at, line - at, "model = \"mooney_rivlin\"\nc10 = 3.0e5\nc01 = 1.0e5\nbulk = 8.0e6");
  }
  ContactRun<2> run(toml);
  const Drift r = measure<2>(run);
  print("mooney_rivlin, glancing impact 2D", r);
  EXPECT_GT(r.contact_steps, 5);
  EXPECT_LT(r.energy, 1e-10);
  EXPECT_LT(r.angular, 1e-10);
}

// Stick: the springs let go of what they store when their slaves leave;
// with that counted the energy is conserved.
TEST(PenaltyContact, StickConservesWithTheReleasedEnergyCounted) {
  ContactRun<3> run(test::with_method(test::ball_on_plane("stick", 0.12), "penalty"));
  const Drift r = measure<3>(run);
  print("penalty, stick, ball on the plane 3D", r);
  EXPECT_GT(r.contact_steps, 10);
  EXPECT_LT(r.counted, 1e-10);
}

// Penetration falls about as 1/ε.
TEST(PenaltyContact, PenetrationFallsAsThePenaltyGrows) {
  ContactRun<3> probe(test::with_method(test::glancing_spheres(3, "frictionless", 0.1), "penalty"));
  const double automatic = dynamic_cast<contact::PenaltyMethod<3>&>(*probe.method).penalty(0);
  double last = 0.0;
  for (double factor : {1.0, 10.0, 100.0}) {
    const Drift r = glancing<3>("penalty = " + std::to_string(factor * automatic) + "\n");
    std::printf("[ measured ] ε = %g × %.3g Pa/m: penetration %.3g m, E %.2e\n", factor, automatic, r.penetration,
                r.energy);
    EXPECT_LT(r.energy, 1e-10);
    if (last > 0.0) EXPECT_LT(r.penetration, last / 3.0) << factor;
    last = r.penetration;
  }
}

// `equations`: the unknowns of the step's last solve, prescribed and
// eliminated ones left out (elimination), all of the bodies' (penalty).
TEST(PenaltyContact, EquationsCountTheSolvedUnknowns) {
  ContactRun<2> elimination(test::glancing_spheres(2, "frictionless", 0.05));
  ContactRun<2> penalty(test::with_method(test::glancing_spheres(2, "frictionless", 0.05), "penalty"));
  const int free = elimination.problem.model.num_dofs() - static_cast<int>(elimination.problem.model.prescribed.dofs.size());
  bool seen = false;
  for (int n = 0; n < 40; ++n) {
    elimination.step();
    penalty.step();
    const int held = static_cast<int>(elimination.contacts->constraints().size());
    // The last solve's system: its active set is the step's unless the
    // step released or activated after it (then it is solved again).
    EXPECT_EQ(elimination.last.contact.equations, free - held) << "step " << n + 1;
    EXPECT_EQ(penalty.last.contact.equations, free);
    seen = seen || held > 0;
  }
  EXPECT_TRUE(seen);
}

// A method's state comes back from its bytes (Method::save/load, what
// retries and checkpoints use), and bytes that are not a state are refused.
template <class Run>
void check_round_trip(Run& run, int steps) {
  for (int n = 0; n < steps; ++n) run.step();
  const std::string bytes = run.method->save();
  ASSERT_GT(bytes.size(), 16U);
  run.method->load(bytes, "test");
  EXPECT_EQ(run.method->save(), bytes);
  EXPECT_THROW(run.method->load(bytes.substr(0, bytes.size() - 3), "test"), InputError);
  EXPECT_THROW(run.method->load(bytes + "x", "test"), InputError);
}

TEST(PenaltyContact, MethodStateRoundTripsThroughItsBytes) {
  ContactRun<2> elimination(test::glancing_spheres(2, "frictionless", 0.05));
  check_round_trip(elimination, 30);
  ASSERT_FALSE(elimination.contacts->constraints().empty());
  ContactRun<3> stick(test::with_method(test::ball_on_plane("stick", 0.12), "penalty"));
  check_round_trip(stick, 100);
  ASSERT_FALSE(stick.method->contact_forces().empty());
}

}  // namespace
}  // namespace conserve::time

namespace conserve::time {
namespace {

// The penalty's tangent (automatic differentiation, over the facets'
// faces and across changes of the nearest part) by the Taylor test of its
// force, through the Coupling a solve uses, at the predictor of steps of
// the glancing impact of two discs, along random directions.
template <int D>
void check_penalty_tangent() {
  ContactRun<D> run(test::with_method(test::glancing_spheres(D, "frictionless", 0.1), "penalty"));
  const double dt = run.scenario.time.step;
  const int n = run.problem.model.num_dofs();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int checked = 0;
  for (int step = 0; step < 60; ++step) {
    run.step();
    if (step % 6 != 5) continue;
    run.method->begin_step(run.state.step + 1, dt, run.state);
    const Eigen::VectorXd u = run.state.u + dt * run.state.v;
    const auto coupling = run.method->coupling(run.state.u, u);
    if (coupling->plain()) continue;
    const SparseMatrix K = run.assembler->pattern().make_matrix();  // zero: the contact part alone
    auto force = [&](const Eigen::VectorXd& at) {
      Eigen::VectorXd g = Eigen::VectorXd::Zero(n), m = Eigen::VectorXd::Zero(n), r;
      coupling->residual(at, g, m, r);
      return r;
    };
    SparseMatrix A;
    coupling->tangent(u, K, force(u), A);
    Eigen::VectorXd d(n);
    for (int i = 0; i < n; ++i) d[i] = unit(rng);
    // Steps from 1e-6 of the model's size down: the larger ones may cross
    // the kinks of ⟨−g⟩ and of the nearest part's changes (order 1 from
    // 1e-4 there), the order is read at the smallest steps above round-off.
    const test::TaylorOrder t = test::taylor_order(force, u, d, A * d, 1e-6 * run.problem.model.size());
    std::printf("[ measured ] penalty tangent %dD, step %d: %s\n", D, step + 1, test::describe(t).c_str());
    test::expect_second_order(t, "step " + std::to_string(step + 1));
    ++checked;
  }
  EXPECT_GT(checked, 3);
}

TEST(PenaltyContact, TangentMatchesFiniteDifferences2d) { check_penalty_tangent<2>(); }
TEST(PenaltyContact, TangentMatchesFiniteDifferences3d) { check_penalty_tangent<3>(); }

}  // namespace
}  // namespace conserve::time
