// Prescribed displacements: the prescribed values come out exactly, and a
// fixed support does no work, so energy is still conserved.
#include <gtest/gtest.h>

#include <cstdio>

#include "material/svk_law.hpp"
#include "model/initial_state.hpp"
#include "support/grid_mesh.hpp"
#include "time/diagnostics.hpp"
#include "simulation/stepper.hpp"
#include "time/integrator.hpp"

namespace conserve::time {
namespace {

/// An integrator with the settings `conserve run` uses by default.
template <int D>
Integrator<D> default_integrator(const assembly::Assembler<D>& assembler) {
  return Integrator<D>(assembler, fem::StressScheme::conserving,
                       simulation::newton_settings(io::NewtonSpec{}, io::SolverSpec{}), nullptr, 10,
                       simulation::linear_settings(io::SolverSpec{}));
}

template <int D>
model::Model<D> cantilever(double rate) {
  model::Model<D> m;
  const auto mesh = D == 3 ? test::box_mesh(6, 2, 2, 1.0, 0.2, 0.2) : test::rectangle_mesh(8, 2, 1.0, 0.2);
  // E = 2e6 Pa: a soft beam that sags ~0.2 m under its weight; at 2e5 Pa
  // (a static sag of ~2 m) its cells at the support turn inside out.
  model::add_body<D>(m, mesh, "beam", std::make_shared<const material::Svk>(material::Lame::from_young_poisson(2e6, 0.3)), 1000.0, 1.0);
  m.gravity(D - 1) = -9.81;
  for (int n : model::group_nodes(m.bodies[0], "xmin"))
    for (int k = 0; k < D; ++k) {
      m.prescribed.dofs.push_back(model::dof<D>(n, k));
      m.prescribed.value.push_back(0.0);
      m.prescribed.rate.push_back(k == 0 ? rate : 0.0);
    }
  return m;
}

template <int D>
void check_fixed_support_conserves_energy() {
  const model::Model<D> model = cantilever<D>(0.0);
  const assembly::Assembler<D> assembler(model, false);
  Integrator<D> integrator = default_integrator<D>(assembler);
  model::State state = model::rest_state<D>(model);
  const double E0 = diagnostics<D>(assembler, state).total;  // 0: at rest, undeformed
  double drift = 0.0, swing = 0.0;
  for (int n = 0; n < 200; ++n) {
    integrator.step(state, 0.005);
    const Diagnostics d = diagnostics<D>(assembler, state);
    drift = std::max(drift, std::abs(d.total - E0));
    swing = std::max(swing, d.kinetic);
    for (int dof : model.prescribed.dofs) ASSERT_EQ(state.u[dof], 0.0);
  }
  std::printf("[ measured ] %dD cantilever under gravity, 200 steps: |E - E0| / max K = %.2e\n", D, drift / swing);
  EXPECT_GT(swing, 1e-3);  // it really swings
  EXPECT_LT(drift / swing, 1e-10);
}

TEST(Prescribed, FixedSupportConservesEnergy2d) { check_fixed_support_conserves_energy<2>(); }
TEST(Prescribed, FixedSupportConservesEnergy3d) { check_fixed_support_conserves_energy<3>(); }

TEST(Prescribed, MovingSupportFollowsItsLawExactly) {
  const model::Model<3> model = cantilever<3>(0.1);
  const assembly::Assembler<3> assembler(model, false);
  Integrator<3> integrator = default_integrator<3>(assembler);
  model::State state = model::rest_state<3>(model);
  for (int n = 0; n < 20; ++n) integrator.step(state, 0.01);
  for (std::size_t i = 0; i < model.prescribed.dofs.size(); ++i)
    EXPECT_EQ(state.u[model.prescribed.dofs[i]], model.prescribed.value[i] + model.prescribed.rate[i] * state.time);
  EXPECT_GT(state.u.norm(), 0.01);  // the free part followed
}

}  // namespace
}  // namespace conserve::time

namespace conserve::model {
namespace {

// A curve is linear between its points and constant beyond them; its
// integral is exact (trapezoids of the pieces).
TEST(Curve, ValuesSlopesAndIntegral) {
  const Curve c{{0.5, 1.0, 2.0}, {0.0, 2.0, -1.0}};
  EXPECT_EQ(c.at(0.0), 0.0);
  EXPECT_EQ(c.at(0.75), 1.0);
  EXPECT_EQ(c.at(1.5), 0.5);
  EXPECT_EQ(c.at(3.0), -1.0);
  EXPECT_EQ(c.slope(0.75), 4.0);
  EXPECT_EQ(c.slope(1.0), -3.0);  // the right derivative at a point
  EXPECT_EQ(c.slope(2.5), 0.0);
  EXPECT_DOUBLE_EQ(c.integral(0.5), 0.0);
  EXPECT_DOUBLE_EQ(c.integral(1.0), 0.5);                  // 0.5 · 0.5 · 2
  EXPECT_DOUBLE_EQ(c.integral(1.5), 0.5 + 0.5 * 1.25);     // + 0.5 · (2 + 0.5) / 2
  EXPECT_DOUBLE_EQ(c.integral(3.0), 0.5 + 0.5 - 1.0);      // + 1 · (2 − 1)/2 − 1 · 1
  const Curve early{{-1.0, 1.0}, {1.0, 3.0}};  // from before t = 0
  EXPECT_DOUBLE_EQ(early.integral(1.0), 0.5 * (2.0 + 3.0));
}

// A rigid motion keeps every distance, turns by |ω| ∫c about its axis
// through the moving centre, and gives each node the velocity
// v c_v + ω c_ω × (x − c − d).
TEST(RigidMotion, TurnsAboutItsCentreWithTheExactVelocity) {
  Eigen::Matrix<double, 3, Eigen::Dynamic> X(3, 4);
  X << 0, 1, 0, 0.3, 0, 0, 1, 0.2, 0, 0, 0, 1;
  Prescribed p;
  p.curves.push_back(Curve{{0.0, 1.0}, {0.0, 2.0}});  // c(t) = 2t on [0, 1]
  RigidMotion m{.first_node = 0, .num_nodes = 4};
  m.center = Vec3(0.5, 0.5, 0.0);
  m.velocity = Vec3(1.0, 0.0, 0.0);
  m.omega = Vec3(0.0, 0.0, 3.0);
  m.omega_curve = 0;
  p.rigid.push_back(m);
  for (int d = 0; d < 12; ++d) p.dofs.push_back(d), p.value.push_back(0.0), p.rate.push_back(0.0);
  const double t = 0.6;
  Eigen::VectorXd u = Eigen::VectorXd::Zero(12), v = Eigen::VectorXd::Zero(12);
  apply_prescribed<3>(p, X, t, u, &v);
  const Eigen::Matrix<double, 3, Eigen::Dynamic> x = X + u.reshaped(3, 4);
  const double angle = 3.0 * t * t;  // |ω| ∫_0^t 2s ds
  const Vec3 d = m.velocity * t, c = m.center + d;
  for (int a = 0; a < 4; ++a) {
    for (int b = 0; b < 4; ++b) EXPECT_NEAR((x.col(a) - x.col(b)).norm(), (X.col(a) - X.col(b)).norm(), 1e-15);
    const Vec3 r0 = X.col(a) - m.center, r = x.col(a) - c;
    EXPECT_NEAR(r.z(), r0.z(), 1e-15);
    EXPECT_NEAR(r.x(), std::cos(angle) * r0.x() - std::sin(angle) * r0.y(), 1e-15);
    EXPECT_NEAR(r.y(), std::sin(angle) * r0.x() + std::cos(angle) * r0.y(), 1e-15);
    const Vec3 velocity = m.velocity + (m.omega * 2.0 * t).cross(r);
    EXPECT_NEAR((v.segment<3>(3 * a) - velocity).norm(), 0.0, 1e-14);
  }
}

}  // namespace
}  // namespace conserve::model
