// Conservation of the mid-point scheme without contact (paper (18)–(26);
// docs/theory.md, "The conserving step (18)–(26)"):
// free bodies conserve E, L and J to the Newton tolerance; under gravity E
// (with Π_ext) is conserved; the plain mid-point stress is shown not to be.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

#include "material/svk_law.hpp"
#include "model/initial_state.hpp"
#include "support/contact_run.hpp"
#include "support/grid_mesh.hpp"
#include "time/diagnostics.hpp"
#include "simulation/stepper.hpp"
#include "time/integrator.hpp"

namespace conserve::time {
namespace {

struct Drift {
  double energy = 0.0;          ///< max |E − E0| / |E0|
  Vec3 linear = Vec3::Zero();   ///< per component, max |L_i − L_i0| / |L0|
  Vec3 angular = Vec3::Zero();  ///< per component, max |J_i − J_i0| / |J0|
  double mean_iterations = 0.0;
  double max_strain_fraction = 0.0;  ///< max W / E over the run (large-deformation evidence)
  std::vector<std::vector<double>> residual_histories;
};

template <int D>
model::Model<D> free_body_model(const Vec3& gravity) {
  model::Model<D> m;
  const auto mesh = D == 3 ? test::box_mesh(5, 2, 2, 1.0, 0.4, 0.3) : test::rectangle_mesh(8, 3, 1.0, 0.4);
  model::add_body<D>(m, mesh, "block", std::make_shared<const material::Svk>(material::Lame::from_young_poisson(5.0e4, 0.3)), 1000.0, 1.0);
  m.gravity = gravity.head<D>();
  return m;
}

template <int D>
Drift run_free_body(fem::StressScheme scheme, const Vec3& gravity, int steps, bool reuse = true,
                    int* factorizations = nullptr, solver::Method method = solver::Method::krylov) {
  const model::Model<D> model = free_body_model<D>(gravity);
  const assembly::Assembler<D> assembler(model, false);
  // The program's defaults ([newton], [solver]), with what this test varies.
  solver::NewtonSettings newton = simulation::newton_settings(io::NewtonSpec{}, io::SolverSpec{});
  newton.max_iterations = 25;
  newton.floor_limit = 1e-13;
  newton.modified_newton = reuse;
  solver::LinearSolverSettings linear = simulation::linear_settings(io::SolverSpec{});
  linear.method = method;
  Integrator<D> integrator(assembler, scheme, newton, nullptr, 10, linear);
  model::State state = model::rest_state<D>(model);
  model::InitialMotion motion;
  motion.deformation << 1.15, 0.1, 0.0, -0.05, 0.9, 0.05, 0.0, 0.05, 1.05;
  motion.velocity << 1.0, 0.5, 0.25;
  motion.angular_velocity = D == 3 ? Vec3(0.5, 1.0, 3.0) : Vec3(0.0, 0.0, 3.0);
  model::set_initial_motion<D>(model, 0, motion, state);
  const Diagnostics d0 = diagnostics<D>(assembler, state);
  Drift drift;
  for (int n = 0; n < steps; ++n) {
    const solver::NewtonReport report = integrator.step(state, 0.01);
    drift.mean_iterations += report.iterations / static_cast<double>(steps);
    drift.residual_histories.push_back(report.residual_norms);
    const Diagnostics d = diagnostics<D>(assembler, state);
    drift.energy = std::max(drift.energy, std::abs(d.total - d0.total) / std::abs(d0.total));
    drift.linear = drift.linear.cwiseMax((d.linear - d0.linear).cwiseAbs() / d0.linear.norm());
    drift.angular = drift.angular.cwiseMax((d.angular - d0.angular).cwiseAbs() / d0.angular.norm());
    drift.max_strain_fraction = std::max(drift.max_strain_fraction, d.strain / d.total);
  }
  if (factorizations) *factorizations = integrator.timings().linear_setups;
  return drift;
}

void print(const char* name, const Drift& d) {
  std::printf("[ measured ] %s: E %.2e  L (%.2e %.2e %.2e)  J (%.2e %.2e %.2e)  W/E max %.2f  Newton %.2f it/step\n",
              name, d.energy, d.linear.x(), d.linear.y(), d.linear.z(), d.angular.x(), d.angular.y(), d.angular.z(),
              d.max_strain_fraction, d.mean_iterations);
}

TEST(Conservation, FreeBody3d) {
  const Drift d = run_free_body<3>(fem::StressScheme::conserving, Vec3::Zero(), 250);
  print("free body 3D, 250 steps", d);
  EXPECT_GT(d.max_strain_fraction, 0.05);  // the body really deforms
  EXPECT_LT(d.energy, 1e-10);
  EXPECT_LT(d.linear.maxCoeff(), 1e-10);
  EXPECT_LT(d.angular.maxCoeff(), 1e-10);
}

TEST(Conservation, FreeBody2d) {
  const Drift d = run_free_body<2>(fem::StressScheme::conserving, Vec3::Zero(), 250);
  print("free body 2D, 250 steps", d);
  EXPECT_GT(d.max_strain_fraction, 0.05);
  EXPECT_LT(d.energy, 1e-10);
  EXPECT_LT(d.linear.maxCoeff(), 1e-10);
  EXPECT_LT(d.angular.maxCoeff(), 1e-10);
}

TEST(Conservation, Gravity3d) {
  const Drift d = run_free_body<3>(fem::StressScheme::conserving, Vec3(0, 0, -9.81), 250);
  print("gravity 3D, 250 steps", d);
  EXPECT_LT(d.energy, 1e-10);
}

TEST(Conservation, Gravity2d) {
  const Drift d = run_free_body<2>(fem::StressScheme::conserving, Vec3(0, -9.81, 0), 250);
  print("gravity 2D, 250 steps", d);
  EXPECT_LT(d.energy, 1e-10);
}

// Negative control: the same runs with S(E_{n+½}) do not conserve energy
// (momenta are still conserved: they only need f_int's form F_{n+½} S ∇N).
// The predictor u_n + Δt V_n + ½Δt² g is the step of an unstressed body
// in flight under gravity: Newton starts at a residual within tolerance.
// Without the gravity term (the old predictor) every step needed an
// iteration whose residual was the weight's inertia, M g.
TEST(Predictor, RigidFlightUnderGravityConvergesAtThePredictor) {
  const model::Model<3> model = free_body_model<3>(Vec3(0.0, 0.0, -9.81));
  const assembly::Assembler<3> assembler(model, false);
  solver::NewtonSettings newton = simulation::newton_settings(io::NewtonSpec{}, io::SolverSpec{});
  newton.max_iterations = 25;
  newton.floor_limit = 1e-13;
  Integrator<3> integrator(assembler, fem::StressScheme::conserving, newton, nullptr, 10,
                           simulation::linear_settings(io::SolverSpec{}));
  model::State state = model::rest_state<3>(model);
  model::InitialMotion motion;
  motion.velocity << 1.0, 0.5, 2.0;
  model::set_initial_motion<3>(model, 0, motion, state);
  const Diagnostics d0 = diagnostics<3>(assembler, state);
  for (int n = 0; n < 20; ++n) {
    const solver::NewtonReport report = integrator.step(state, 0.01);
    EXPECT_EQ(report.iterations, 0) << "step " << n + 1;
    EXPECT_LE(report.residual_norms.front(), report.tolerance);
  }
  const Diagnostics d = diagnostics<3>(assembler, state);
  EXPECT_LT(std::abs(d.total - d0.total), 1e-12 * std::abs(d0.total));
  // The body fell as ½ g t² (exactly, up to round-off, at t = 0.2 s).
  const double dz = state.u[2] - 0.2 * 2.0;
  EXPECT_NEAR(dz, -0.5 * 9.81 * 0.2 * 0.2, 1e-12);
}

TEST(Conservation, MidpointStressDriftsNegativeControl3d) {
  const Drift d = run_free_body<3>(fem::StressScheme::midpoint, Vec3::Zero(), 250);
  print("NEGATIVE CONTROL midpoint stress 3D", d);
  EXPECT_GT(d.energy, 1e-6);
  EXPECT_LT(d.linear.maxCoeff(), 1e-10);
}

TEST(Conservation, MidpointStressDriftsNegativeControl2d) {
  const Drift d = run_free_body<2>(fem::StressScheme::midpoint, Vec3::Zero(), 250);
  print("NEGATIVE CONTROL midpoint stress 2D", d);
  EXPECT_GT(d.energy, 1e-6);
}

// Modified Newton (factorization reuse) changes the cost, not the result:
// conservation depends on the residual only.
TEST(Conservation, FactorizationReuseConservesAndSavesFactorizations3d) {
  int full = 0, reused = 0;
  const Drift a = run_free_body<3>(fem::StressScheme::conserving, Vec3(0, 0, -9.81), 250, false, &full);
  const Drift b = run_free_body<3>(fem::StressScheme::conserving, Vec3(0, 0, -9.81), 250, true, &reused);
  print("gravity 3D, factorization reuse", b);
  std::printf("[ measured ] factorizations: full Newton %d (%.2f it/step), reuse %d (%.2f it/step)\n", full,
              a.mean_iterations, reused, b.mean_iterations);
  EXPECT_LT(b.energy, 1e-10);
  EXPECT_LT(reused, full / 2);
}

// Quadratic convergence: with e_k = r_k / r_0, a consistent tangent gives
// e_{k+1} ≤ C e_k² with C of order one; an inconsistent one (linear
// convergence, e_{k+1} ≈ ρ e_k) makes e_{k+1}/e_k² grow like 1/e_k. Exact
// linear solves (the LU): inexact Newton is not quadratic by design.
TEST(Newton, ConvergesQuadratically) {
  const auto lu = solver::Method::direct;
  for (const Drift& d : {run_free_body<3>(fem::StressScheme::conserving, Vec3::Zero(), 40, false, nullptr, lu),
                         run_free_body<2>(fem::StressScheme::conserving, Vec3::Zero(), 40, false, nullptr, lu)}) {
    double worst = 0.0;
    int samples = 0;
    for (const auto& r : d.residual_histories) {
      for (std::size_t k = 1; k + 1 < r.size(); ++k) {
        const double e = r[k] / r[0], e_next = r[k + 1] / r[0];
        if (e_next < 1e-10) continue;  // round-off floor
        worst = std::max(worst, e_next / (e * e));
        ++samples;
      }
    }
    std::printf("[ measured ] Newton: %.2f iterations/step, max e_{k+1}/e_k^2 = %.3f (%d samples)\n", d.mean_iterations,
                worst, samples);
    ASSERT_GT(samples, 40);
    EXPECT_LT(worst, 10.0);
    EXPECT_LT(d.mean_iterations, 6.0);
  }
}

// Where a body lies, or how far it has gone, must not matter. The paper's
// §6.1 disc (E = 2.1e9 Pa, Δt far above its vibration periods: a
// stiffness K ~ 4e7 N/m per node), spinning in free flight.
//
// Shifted 1 km, it must take the steps it takes at the origin. Deformation
// gradients formed from absolute positions, F = Σ x_A ⊗ ∇N_A, carry the
// round-off ε|x|/h of the positions; at 1 km that is 1e-11 in F, a residual
// K ε|x| far above the Newton tolerance, and the shifted disc could not
// take a single step.
std::string stiff_disc(double offset, double speed) {
  return "dimension = 3\n[time]\nstep = 2.0e-3\nend = 0.05\n"
         "[[body]]\nname = \"disc\"\ntranslate = [" +
         std::to_string(offset) + ", " + std::to_string(-offset) + ", 0.0]\nvelocity = [" + std::to_string(speed) +
         ", 0.5, 0.0]\nangular_velocity = [0.0, 0.0, 20.0]\n"
         "[body.material]\nyoung = 2.1e9\npoisson = 0.3\ndensity = 2500.0\n"
         "[body.mesh]\ngenerator = \"cylinder\"\nradius = 0.1\nlength = 0.005\nsize = 0.02\n";
}

struct DiscRun {
  double drift = 0.0;  ///< max |E − E0| / E0
  int iterations = 0, steps = 0;
  std::vector<double> times;
};

DiscRun run_disc(test::ContactRun<3>& run) {
  const Diagnostics d0 = run.diagnostics();
  DiscRun r;
  while (run.state.time < run.scenario.time.end - 1e-9) {
    r.iterations += run.step().iterations;
    ++r.steps;
    r.times.push_back(run.state.time);
    r.drift = std::max(r.drift, std::abs(run.diagnostics().total - d0.total) / d0.total);
  }
  return r;
}

TEST(Conservation, StiffDiscStepsFarFromTheOriginAsAtIt) {
  test::ContactRun<3> near(stiff_disc(0.0, 1.0)), far(stiff_disc(1000.0, 1.0));
  const DiscRun n = run_disc(near), f = run_disc(far);
  const double apart = (far.state.v - near.state.v).lpNorm<Eigen::Infinity>();
  std::printf(
      "[ measured ] stiff disc, 25 steps: E drift %.2e at the origin, %.2e at 1 km; Newton iterations %d and %d; "
      "largest velocity difference at the end %.2e m/s\n",
      n.drift, f.drift, n.iterations, f.iterations, apart);
  EXPECT_EQ(n.steps, 25);
  EXPECT_EQ(f.times, n.times) << "the disc 1 km away cut its steps back";
  EXPECT_LT(n.drift, 1e-11);
  EXPECT_LT(f.drift, 1e-11);
  EXPECT_LT(apart, 1e-9);  // the same motion (nodal speeds ~2 m/s)
  EXPECT_LE(f.iterations, n.iterations + 25);
}

// The same disc at 2e4 m/s travels 1 km in the run: its displacements are
// stored to ε|u| ~ 2e-13 m, and the residual cannot fall below K ε|u| ~ 1e-5
// N. The round-off floor must know that, or every step fails at its
// tolerance (it did: 186 cutbacks in 50 steps).
TEST(Conservation, StiffDiscStepsAfterTravellingFar) {
  test::ContactRun<3> fast(stiff_disc(0.0, 2.0e4));
  const DiscRun r = run_disc(fast);
  std::printf("[ measured ] stiff disc at 2e4 m/s, 1 km: %d steps, E drift %.2e, %d Newton iterations\n", r.steps,
              r.drift, r.iterations);
  EXPECT_EQ(r.steps, 25) << "steps were cut back";
  EXPECT_LT(r.drift, 1e-12);  // of E ≈ 7.8e7 J, the translation's
  EXPECT_GT(fast.state.u[0], 999.0);
}

}  // namespace
}  // namespace conserve::time
