// Every law conserves E, L and J in the conserving step (docs/theory.md,
// "Materials: the discrete gradient"): a free body, spinning about a skew
// axis from a stretched and sheared start with strains of 30 % and more,
// 500 steps in 3D and in plane strain, drifts ≤ 1e-10; the plain mid-point
// stress S(C(F_{n+½})) is the negative control.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstdio>

#include "fem/simplex.hpp"
#include "material/law_cases.hpp"
#include "model/initial_state.hpp"
#include "simulation/stepper.hpp"
#include "support/grid_mesh.hpp"
#include "time/diagnostics.hpp"
#include "time/integrator.hpp"

namespace conserve::time {
namespace {

struct Drift {
  double energy = 0.0, linear = 0.0, angular = 0.0;
  double max_strain = 0.0;  ///< largest |principal Green–Lagrange strain| of any cell over the run
  double mean_iterations = 0.0;
};

/// The largest |eigenvalue of E| over the cells (over a quadratic cell's
/// points) at displacements u.
template <int D>
double max_strain(const assembly::Assembler<D>& assembler, const Eigen::VectorXd& u) {
  double worst = 0.0;
  const auto add = [&](const Mat<D>& F) {
    const Mat<D> E = 0.5 * (F.transpose() * F - Mat<D>::Identity());
    worst = std::max(worst, Eigen::SelfAdjointEigenSolver<Mat<D>>(E).eigenvalues().cwiseAbs().maxCoeff());
  };
  const auto& model = assembler.model();
  for (int c = 0; c < model.num_cells(); ++c) {
    if (model.order == 1) {
      add(fem::deformation_gradient<D>(assembler.cell_positions(c, u), model.geometry[c]));
      continue;
    }
    const auto x = assembler.template positions<fem::Quadratic<D>::kNodes>(c, u);
    for (int q = 0; q < fem::Quadratic<D>::kPoints; ++q) add(x * model.quadratic[c].at(q).grad.transpose());
  }
  return worst;
}

/// The cells of the runs: linear, or quadratic with curved edges.
struct Cells {
  int order = 1;
  bool lumped = false;
  bool mean_dilatation = false;  ///< quadratic cells with the cell's mean J (fem/mean_dilatation.hpp)
};

template <int D>
Drift run(const material::test::LawCase& law, fem::StressScheme scheme, int steps, Cells cells = {},
          bool isochoric = false) {
  model::Model<D> model;
  auto mesh = D == 3 ? test::box_mesh(5, 2, 2, 1.0, 0.4, 0.3) : test::rectangle_mesh(8, 3, 1.0, 0.4);
  if (cells.order == 2) mesh = test::quadratic_mesh(mesh, 0.03);
  model::add_body<D>(model, mesh, "block", material::test::make(law), 1000.0, 1.0);
  model.bodies[0].mean_dilatation = cells.mean_dilatation;
  const assembly::Assembler<D> assembler(model, cells.lumped);
  solver::NewtonSettings newton = simulation::newton_settings(io::NewtonSpec{}, io::SolverSpec{});
  newton.max_iterations = 25;
  Integrator<D> integrator(assembler, scheme, newton, nullptr, 10, simulation::linear_settings(io::SolverSpec{}));
  model::State state = model::rest_state<D>(model);
  model::InitialMotion motion;
  motion.deformation << (D == 3 ? 1.15 : 1.25), 0.1, 0.0, -0.05, 0.9, 0.05, 0.0, 0.05, 1.05;
  if (isochoric) {  // the same shape at det F = 1 (in plane in 2D): no pressure wave in a near-incompressible body
    const double det = motion.deformation.topLeftCorner<D, D>().determinant();
    motion.deformation.topLeftCorner<D, D>() /= std::pow(det, 1.0 / D);
  }
  motion.velocity << 1.0, 0.5, 0.25;
  motion.angular_velocity = D == 3 ? Vec3(1.0, 2.0, 6.0) : Vec3(0.0, 0.0, 7.0);
  model::set_initial_motion<D>(model, 0, motion, state);
  const Diagnostics d0 = diagnostics<D>(assembler, state);
  Drift drift;
  drift.max_strain = max_strain<D>(assembler, state.u);
  for (int n = 0; n < steps; ++n) {
    drift.mean_iterations += integrator.step(state, 0.01).iterations / static_cast<double>(steps);
    const Diagnostics d = diagnostics<D>(assembler, state);
    drift.energy = std::max(drift.energy, std::abs(d.total - d0.total) / std::abs(d0.total));
    drift.linear = std::max(drift.linear, (d.linear - d0.linear).cwiseAbs().maxCoeff() / d0.linear.norm());
    drift.angular = std::max(drift.angular, (d.angular - d0.angular).cwiseAbs().maxCoeff() / d0.angular.norm());
    drift.max_strain = std::max(drift.max_strain, max_strain<D>(assembler, state.u));
  }
  std::printf(
      "[ measured ] %s %s%dD %s, %d steps: drift E %.2e L %.2e J %.2e, largest strain %.2f, %.2f Newton it/step\n",
      law.model.c_str(),
      cells.order == 2 ? (cells.mean_dilatation ? "quadratic mean-dilatation "
                          : cells.lumped        ? "quadratic lumped "
                                                : "quadratic ")
                       : "",
      D, scheme == fem::StressScheme::conserving ? "conserving" : "midpoint", steps, drift.energy, drift.linear,
      drift.angular, drift.max_strain, drift.mean_iterations);
  return drift;
}

template <int D>
void check_every_law() {
  for (const auto& law : material::test::law_cases(5.0e4)) {
    const Drift d = run<D>(law, fem::StressScheme::conserving, 500);
    EXPECT_GE(d.max_strain, 0.3) << law.model;  // large deformation indeed
    EXPECT_LT(d.energy, 1e-10) << law.model;
    EXPECT_LT(d.linear, 1e-10) << law.model;
    EXPECT_LT(d.angular, 1e-10) << law.model;
    const Drift control = run<D>(law, fem::StressScheme::midpoint, 100);
    EXPECT_GT(control.energy, 1e-6) << law.model << ": the mid-point stress should not conserve energy";
    EXPECT_LT(control.angular, 1e-10) << law.model;  // momenta need only f's form
  }
}

TEST(MaterialConservation, FreeBodyEveryLaw3d) { check_every_law<3>(); }
TEST(MaterialConservation, FreeBodyEveryLaw2d) { check_every_law<2>(); }

// The same on curved quadratic cells (10-node tetrahedra, 6-node
// triangles), with the consistent mass and, for one law, the lumped one.
template <int D>
void check_every_law_quadratic() {
  for (const auto& law : material::test::law_cases(5.0e4)) {
    for (const bool lumped : {false, true}) {
      if (lumped && law.model != "neo_hookean") continue;
      const Drift d = run<D>(law, fem::StressScheme::conserving, 200, {2, lumped});
      EXPECT_GE(d.max_strain, 0.3) << law.model;
      EXPECT_LT(d.energy, 1e-10) << law.model;
      EXPECT_LT(d.linear, 1e-10) << law.model;
      EXPECT_LT(d.angular, 1e-10) << law.model;
    }
    const Drift control = run<D>(law, fem::StressScheme::midpoint, 100, {2, false});
    EXPECT_GT(control.energy, 1e-6) << law.model << ": the mid-point stress should not conserve energy";
  }
}

TEST(MaterialConservation, QuadraticFreeBodyEveryLaw3d) { check_every_law_quadratic<3>(); }
TEST(MaterialConservation, QuadraticFreeBodyEveryLaw2d) { check_every_law_quadratic<2>(); }

// With the mean dilatation (the joint discrete gradient): the same bounds,
// and the mid-point control, at ν = 0.3 and, from an isochoric start,
// 0.49 (β = √(μ/κ) 0.68 and 0.14 in 3D) for 100 steps (in 2D at 0.49,
// Newton fails at step 196 with the mean and at step 61 without it). Not
// SVK at 0.49: its Newton iteration fails at step 2 with the mean (14
// it/step without it); its volumetric energy λ/2 (tr E)² softens in
// compression, not a law for near-incompressible solids. With the pure mean (β = 0) the 2D run failed at step 2: the
// cells' conformal modes, without stiffness, took up the stretch's release.
template <int D>
void check_every_law_mean_dilatation(double poisson) {
  for (const auto& law : material::test::law_cases(5.0e4, poisson)) {
    if (poisson > 0.4 && law.model == "svk") continue;
    const bool isochoric = poisson > 0.4;
    const Drift d = run<D>(law, fem::StressScheme::conserving, isochoric ? 100 : 200, {2, false, true}, isochoric);
    EXPECT_GE(d.max_strain, 0.2) << law.model;
    EXPECT_LT(d.energy, 1e-10) << law.model;
    EXPECT_LT(d.linear, 1e-10) << law.model;
    EXPECT_LT(d.angular, 1e-10) << law.model;
    // (the mid-point step's energy grows: at 0.49 a cell inverts after 48 steps)
    const Drift control = run<D>(law, fem::StressScheme::midpoint, isochoric ? 30 : 100, {2, false, true}, isochoric);
    EXPECT_GT(control.energy, 1e-6) << law.model << ": the mid-point stress should not conserve energy";
  }
}

TEST(MaterialConservation, MeanDilatationFreeBodyEveryLaw3d) {
  check_every_law_mean_dilatation<3>(0.3);
  check_every_law_mean_dilatation<3>(0.49);
}
TEST(MaterialConservation, MeanDilatationFreeBodyEveryLaw2d) {
  check_every_law_mean_dilatation<2>(0.3);
  check_every_law_mean_dilatation<2>(0.49);
}

}  // namespace
}  // namespace conserve::time
