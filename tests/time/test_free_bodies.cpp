// Free rigid bodies (time/free_bodies.hpp, issue 52): the step's tangent
// with the bodies' unknowns appended, by the Taylor test; a body spinning
// about a non-principal axis in free flight keeps E, L and J and turns as
// Euler's equations say; a free rigid body thrown at a deformable one
// keeps the system's E, L and J through the impact.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "support/contact_run.hpp"
#include "support/contact_scenarios.hpp"
#include "support/taylor.hpp"
#include "time/step_problem.hpp"

namespace conserve::time {
namespace {

using test::ContactRun;

/// A brick (0.3 × 0.2 × 0.1 m, 1000 kg/m³) flying and spinning about an
/// axis that is none of its principal ones.
std::string spinning_brick(double end) {
  return R"(dimension = 3
[time]
step = 1e-3
end = )" + std::to_string(end) + R"(
[[body]]
name = "brick"
rigid = true
free = true
velocity = [0.3, -0.2, 0.1]
angular_velocity = [2.0, 15.0, 3.0]
[body.material]
young = 1e6
poisson = 0.3
density = 1000.0
[body.mesh]
generator = "box"
lx = 0.3
ly = 0.2
lz = 0.1
size = 0.05
)";
}

/// The Taylor test of the step's system (nodal and the bodies' unknowns)
/// at the predictor of the next step, along random directions of the
/// bodies' unknowns and the free nodal ones.
template <int D>
void check_tangent(ContactRun<D>& run) {
  const auto& model = run.problem.model;
  const double dt = run.scenario.time.step;
  FreeBodies<D> bodies(*run.assembler);
  const assembly::DirichletMask mask(run.assembler->pattern().make_matrix(), model.held_dofs());
  SparseMatrix K = run.assembler->pattern().make_matrix();
  Eigen::VectorXd u = run.state.u + dt * run.state.v;
  bodies.begin(run.state, dt);
  bodies.predict(u);
  StepProblem<D> base(*run.assembler, mask, fem::StressScheme::conserving, run.state, dt, u, K);
  base.add_bodies(&bodies);
  Eigen::VectorXd r0;
  base.residual(r0);
  const SparseMatrix A = base.tangent();
  bodies.save();
  const Eigen::VectorXd u0 = u;
  const auto residual_at = [&](const Eigen::VectorXd& q) {
    bodies.restore();
    u = u0;
    StepProblem<D> p(*run.assembler, mask, fem::StressScheme::conserving, run.state, dt, u, K);
    p.add_bodies(&bodies);
    p.update(q);
    Eigen::VectorXd r;
    p.residual(r);
    return r;
  };
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int direction = 0; direction < 3; ++direction) {
    Eigen::VectorXd d = Eigen::VectorXd::Zero(A.rows());
    for (Eigen::Index i = 0; i < d.size(); ++i)
      if (i >= model.num_dofs() || !mask.masked(static_cast<int>(i))) d[i] = unit(rng);
    const test::TaylorOrder t =
        test::taylor_order(residual_at, Eigen::VectorXd::Zero(A.rows()), d, A * d, 1e-4 * model.size());
    std::printf("[ measured ] the system's tangent with free bodies, direction %d: %s\n", direction,
                test::describe(t).c_str());
    test::expect_second_order(t, "direction " + std::to_string(direction));
  }
}

TEST(FreeBodies, TangentOfASpinningBrick) {
  ContactRun<3> run(spinning_brick(0.01));
  for (int n = 0; n < 5; ++n) run.step();
  check_tangent<3>(run);
}

}  // namespace
}  // namespace conserve::time

namespace conserve::time {
namespace {

/// Euler's equations of a torque-free body, Π' = Π × I₀⁻¹Π (convected)
/// and R' = R (I₀⁻¹Π)^, by RK4 with `steps` steps to `end`; the spatial
/// angular velocity R I₀⁻¹ Π at the end.
Vec3 euler_reference(const Mat3& inertia, const Vec3& spin, double end, int steps) {
  const Mat3 inverse = inertia.inverse();
  const auto skew = [](const Vec3& w) {
    Mat3 s;
    s << 0.0, -w.z(), w.y(), w.z(), 0.0, -w.x(), -w.y(), w.x(), 0.0;
    return s;
  };
  Mat3 R = Mat3::Identity();
  Vec3 P = inertia * spin;  // R = 1 at the start: convected = spatial
  const double h = end / steps;
  const auto rate = [&](const Mat3& r, const Vec3& p, Mat3& dr, Vec3& dp) {
    const Vec3 omega = inverse * p;
    dr = r * skew(omega);
    dp = p.cross(omega);
  };
  for (int k = 0; k < steps; ++k) {
    Mat3 r1, r2, r3, r4;
    Vec3 p1, p2, p3, p4;
    rate(R, P, r1, p1);
    rate(R + 0.5 * h * r1, P + 0.5 * h * p1, r2, p2);
    rate(R + 0.5 * h * r2, P + 0.5 * h * p2, r3, p3);
    rate(R + h * r3, P + h * p3, r4, p4);
    R += h / 6.0 * (r1 + 2.0 * r2 + 2.0 * r3 + r4);
    P += h / 6.0 * (p1 + 2.0 * p2 + 2.0 * p3 + p4);
  }
  return R * (inverse * P);
}

struct Spin {
  Vec3 omega = Vec3::Zero();  ///< at the end
  double energy = 0.0, linear = 0.0, angular = 0.0;
};

Spin spin_to(double end, double dt) {
  std::string toml = test::to_round_off(spinning_brick(end));
  toml.replace(toml.find("step = 1e-3"), 11, "step = " + std::to_string(dt));
  ContactRun<3> run(toml);
  const Diagnostics d0 = run.diagnostics();
  Spin s;
  double e_ref = 0.0, l_ref = 0.0;
  while (run.state.time < end - 1e-9 * dt) {
    run.step();
    const Diagnostics d = run.diagnostics();
    e_ref = std::max(e_ref, d.kinetic + d.strain);
    l_ref = std::max(l_ref, d.momentum_magnitude);
    s.energy = std::max(s.energy, std::abs(d.total - d0.total) / e_ref);
    s.linear = std::max(s.linear, (d.linear - d0.linear).cwiseAbs().maxCoeff() / l_ref);
    s.angular = std::max(s.angular, (d.angular - d0.angular).cwiseAbs().maxCoeff() / (l_ref * run.problem.model.size()));
  }
  s.omega = run.state.rigid.at(0).spin;
  return s;
}

// A brick spinning about an axis that is none of its principal ones (its
// angular velocity wobbles): E, L and J to round-off, and ω(t) against
// Euler's equations converging at second order in Δt.
TEST(FreeBodies, SpinningAboutANonPrincipalAxisFollowsEulersEquations) {
  const double end = 0.5;
  ContactRun<3> probe(spinning_brick(end));
  const FreeBodies<3> bodies(*probe.assembler);
  const Vec3 reference = euler_reference(bodies.inertia(0), Vec3(2.0, 15.0, 3.0), end, 200000);
  const Spin coarse = spin_to(end, 2e-3), fine = spin_to(end, 1e-3);
  const double e_coarse = (coarse.omega - reference).norm(), e_fine = (fine.omega - reference).norm();
  std::printf("[ measured ] free brick spinning 0.5 s: |ω - ω_Euler| %.3e (Δt = 2 ms), %.3e (1 ms): order %.2f; "
              "drift E %.2e L %.2e J %.2e (1 ms); ω_Euler = (%.4f, %.4f, %.4f) rad/s\n",
              e_coarse, e_fine, std::log2(e_coarse / e_fine), fine.energy, fine.linear, fine.angular, reference.x(),
              reference.y(), reference.z());
  EXPECT_GT((reference - Vec3(2.0, 15.0, 3.0)).norm(), 1.0);  // it wobbles: the axis moved
  EXPECT_LT(e_fine, 1e-2 * reference.norm());
  EXPECT_GT(std::log2(e_coarse / e_fine), 1.8);
  EXPECT_LT(fine.energy, 1e-10);
  EXPECT_LT(fine.linear, 1e-10);
  EXPECT_LT(fine.angular, 1e-10);
}

}  // namespace
}  // namespace conserve::time

namespace conserve::time {
namespace {

/// A free rigid steel-dense sphere (R = 0.05 m) thrown at 2 m/s, spinning,
/// off-centre at a free rubber block (no gravity, nothing held): the
/// block's top face is the slave, the sphere's surface the master.
std::string sphere_at_block(const std::string& kind) {
  return R"(dimension = 3
[time]
step = 5e-4
end = 0.04
[[body]]
name = "block"
[body.material]
model = "neo_hookean"
young = 2.0e6
poisson = 0.3
density = 1100.0
[body.mesh]
generator = "box"
lx = 0.2
ly = 0.2
lz = 0.08
size = 0.025
[[body]]
name = "ball"
rigid = true
free = true
translate = [0.02, -0.01, 0.0905]
velocity = [0.3, 0.0, -2.0]
angular_velocity = [0.0, 20.0, 5.0]
[body.material]
young = 2.0e11
poisson = 0.3
density = 7800.0
[body.mesh]
generator = "sphere"
radius = 0.05
size = 0.02
[[contact]]
slave = "block:zmax"
master = "ball:surface"
kind = ")" + kind + "\"\n";
}

/// A free rigid disc (R = 0.05 m) thrown at a free elastic ring (2D).
std::string disc_at_ring(const std::string& kind) {
  return R"(dimension = 2
[time]
step = 5e-4
end = 0.06
[[body]]
name = "ring"
[body.material]
young = 1.0e6
poisson = 0.3
density = 1000.0
[body.mesh]
generator = "annulus"
inner_radius = 0.08
outer_radius = 0.1
size = 0.01
[[body]]
name = "disc"
rigid = true
free = true
translate = [-0.1555, 0.02]
velocity = [3.0, 0.0]
angular_velocity = 10.0
[body.material]
young = 2.0e11
poisson = 0.3
density = 3000.0
[body.mesh]
generator = "disc"
radius = 0.05
size = 0.01
[[contact]]
slave = "ring:outer"
master = "disc:circle"
kind = ")" + kind + "\"\n";
}

struct Impact {
  double energy = 0.0, linear = 0.0, angular = 0.0, behind = 0.0;
  int contact_steps = 0;
  double ball_speed_change = 0.0;  ///< |Δv| of the free body over the run [m/s]
};

template <int D>
Impact impact(const std::string& toml) {
  ContactRun<D> run(toml);
  const Diagnostics d0 = run.diagnostics();
  const Vec3 v0 = run.state.rigid.at(0).velocity;
  Impact r;
  double e_ref = 0.0, l_ref = 0.0;
  while (run.state.time < run.scenario.time.end - 1e-9 * run.scenario.time.step) {
    run.step();
    const Diagnostics d = run.diagnostics();
    e_ref = std::max(e_ref, d.kinetic + d.strain);
    l_ref = std::max(l_ref, d.momentum_magnitude);
    r.energy = std::max(r.energy, std::abs(d.total - d0.total) / e_ref);
    r.linear = std::max(r.linear, (d.linear - d0.linear).cwiseAbs().maxCoeff() / l_ref);
    r.angular = std::max(r.angular, (d.angular - d0.angular).cwiseAbs().maxCoeff() / (l_ref * run.problem.model.size()));
    r.behind = std::max(r.behind, run.last.contact.slave_penetration);
    r.contact_steps += !run.method->contact_forces().empty();
  }
  r.ball_speed_change = (run.state.rigid.at(0).velocity - v0).norm();
  return r;
}

void expect_conserved(const Impact& r, const std::string& what) {
  std::printf("[ measured ] %s: %d steps in contact, the free body's velocity changed by %.3f m/s; drift E %.2e L "
              "%.2e J %.2e; deepest slave %.2e m\n",
              what.c_str(), r.contact_steps, r.ball_speed_change, r.energy, r.linear, r.angular, r.behind);
  EXPECT_GT(r.contact_steps, 3) << what;
  EXPECT_GT(r.ball_speed_change, 0.1) << what;  // the impact happened
  EXPECT_LT(r.energy, 1e-10) << what;
  EXPECT_LT(r.linear, 1e-10) << what;
  EXPECT_LT(r.angular, 1e-10) << what;
  EXPECT_LT(r.behind, 1e-12) << what;
}

TEST(FreeBodies, RigidSphereThrownAtABlockKeepsEnergyAndMomenta3d) {
  for (const char* kind : {"frictionless", "stick"})
    expect_conserved(impact<3>(test::to_round_off(sphere_at_block(kind))), std::string("sphere at a block, ") + kind);
}

TEST(FreeBodies, RigidDiscThrownAtARingKeepsEnergyAndMomenta2d) {
  for (const char* kind : {"frictionless", "stick"})
    expect_conserved(impact<2>(test::to_round_off(disc_at_ring(kind))), std::string("disc at a ring, ") + kind);
}

}  // namespace
}  // namespace conserve::time
