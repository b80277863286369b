// Newton's start (time/predictor.hpp): the rigid part of a body's velocity,
// and what starting from it buys on a vibrating body at a step far above
// its periods. The step's solution must not depend on the start. Also the
// energy give-back of a push-out (PersistentVelocity::restore_energy),
// which scales the same bodies' non-rigid velocity.
#include <gtest/gtest.h>
#include <unsupported/Eigen/KroneckerProduct>

#include <algorithm>
#include <cstdio>
#include <random>
#include <string>

#include "contact/elimination/persistent_velocity.hpp"
#include "core/error.hpp"
#include "support/contact_run.hpp"
#include "time/predictor.hpp"

namespace conserve::time {
namespace {

/// Two free bodies of the given dimension (a disc or a ball and a block),
/// both moving, neither touching: the model the projection works on.
std::string two_bodies(int dim, const std::string& extra = "") {
  const std::string d = std::to_string(dim);
  const std::string first = dim == 2 ? "generator = \"disc\"\nradius = 0.1\nsize = 0.04\n"
                                     : "generator = \"sphere\"\nradius = 0.1\nsize = 0.05\n";
  const std::string block = dim == 2 ? "generator = \"rectangle\"\nlx = 0.2\nly = 0.1\nsize = 0.05\n"
                                     : "generator = \"box\"\nlx = 0.2\nly = 0.1\nlz = 0.1\nsize = 0.05\n";
  return "dimension = " + d + "\n[time]\nstep = 1e-3\nend = 1e-3\n" +
         "[[body]]\nname = \"round\"\n[body.material]\nyoung = 1e6\npoisson = 0.3\ndensity = 1000.0\n"
         "[body.mesh]\n" + first +
         "[[body]]\nname = \"block\"\ntranslate = [0.5, 0.3" + (dim == 3 ? ", 0.1" : "") +
         "]\n[body.material]\nyoung = 1e6\npoisson = 0.3\ndensity = 3000.0\n[body.mesh]\n" + block + extra;
}

/// v_c + ω × (x − o) at every node of `body`, in 3D components (2D: ω_z).
template <int D>
void add_rigid(const model::Model<D>& model, const model::Body& body, const Eigen::VectorXd& u, const Vec3& v_c,
               const Vec3& omega, Eigen::VectorXd& v) {
  for (int n = body.first_node; n < body.first_node + body.num_nodes; ++n) {
    Vec3 x = Vec3::Zero();
    x.head<D>() = model.X.col(n) + u.segment<D>(n * D);
    v.segment<D>(n * D) += (v_c + omega.cross(x - Vec3(0.1, -0.2, 0.3))).template head<D>();
  }
}

template <int D>
Eigen::VectorXd node_masses(const assembly::Assembler<D>& assembler) {
  const Eigen::VectorXd sums = assembler.mass_times(Eigen::VectorXd::Ones(assembler.model().num_dofs()));
  return sums(Eigen::seq(0, Eigen::last, D));
}

/// Σ m_A V_A and Σ m_A x_A × V_A of `body` (3D components).
template <int D>
std::pair<Vec3, Vec3> momenta(const model::Model<D>& model, const model::Body& body, const Eigen::VectorXd& m,
                              const Eigen::VectorXd& u, const Eigen::VectorXd& v) {
  Vec3 L = Vec3::Zero(), J = Vec3::Zero();
  for (int n = body.first_node; n < body.first_node + body.num_nodes; ++n) {
    Vec3 x = Vec3::Zero(), w = Vec3::Zero();
    x.head<D>() = model.X.col(n) + u.segment<D>(n * D);
    w.head<D>() = v.segment<D>(n * D);
    L += m[n] * w;
    J += m[n] * x.cross(w);
  }
  return {L, J};
}

template <int D>
void check_projection() {
  test::ContactRun<D> run(two_bodies(D));
  const auto& model = run.problem.model;
  const Eigen::VectorXd m = node_masses(*run.assembler);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  // A deformed configuration, so that the fit is not at the reference one.
  const Eigen::VectorXd u = Eigen::VectorXd::NullaryExpr(model.num_dofs(), [&] { return 0.01 * uniform(rng); });
  const Vec3 omega = D == 3 ? Vec3(3.0, -2.0, 5.0) : Vec3(0.0, 0.0, 5.0);
  const Vec3 v_c = D == 3 ? Vec3(1.0, 2.0, -0.5) : Vec3(1.0, 2.0, 0.0);
  Eigen::VectorXd rigid = Eigen::VectorXd::Zero(model.num_dofs());
  for (const auto& body : model.bodies) add_rigid<D>(model, body, u, v_c, omega, rigid);

  const RigidMotion<D> motion(model, m);
  Eigen::VectorXd projected = rigid;
  motion.project(u, projected);
  EXPECT_LT((projected - rigid).lpNorm<Eigen::Infinity>(), 1e-13) << "a rigid field is its own rigid part";

  // A rigid field plus a vibration: the rigid part keeps both momenta, is
  // rigid itself, and what it leaves out is orthogonal to every rigid
  // field in the lumped-mass product.
  const Eigen::VectorXd vibration =
      Eigen::VectorXd::NullaryExpr(model.num_dofs(), [&] { return 0.5 * uniform(rng); });
  const Eigen::VectorXd v = rigid + vibration;
  Eigen::VectorXd part = v;
  motion.project(u, part);
  const double moved = (part - v).norm();
  ASSERT_GT(moved, 0.1) << "the vibration was not taken out";
  Eigen::VectorXd again = part;
  motion.project(u, again);
  EXPECT_LT((again - part).lpNorm<Eigen::Infinity>(), 1e-13) << "the rigid part is not rigid";
  for (const auto& body : model.bodies) {
    const auto [L, J] = momenta<D>(model, body, m, u, v);
    const auto [L_part, J_part] = momenta<D>(model, body, m, u, part);
    EXPECT_LT((L_part - L).norm(), 1e-13 * L.norm()) << body.name;
    EXPECT_LT((J_part - J).norm(), 1e-13 * (J.norm() + L.norm())) << body.name;
    for (int k = 0; k < (D == 3 ? 6 : 3); ++k) {
      Eigen::VectorXd mode = Eigen::VectorXd::Zero(model.num_dofs());
      Vec3 t = Vec3::Zero(), w = Vec3::Zero();
      if (k < D) t[k] = 1.0; else w[D == 3 ? k - 3 : 2] = 1.0;
      add_rigid<D>(model, body, u, t, w, mode);
      double product = 0.0;
      for (int n = 0; n < model.num_nodes(); ++n)
        product += m[n] * mode.segment<D>(n * D).dot((v - part).segment<D>(n * D));
      EXPECT_LT(std::abs(product), 1e-12 * m.sum() * v.norm()) << body.name << " rigid mode " << k;
    }
  }
}

TEST(RigidMotion, IsTheLumpedMassProjectionOnRigidFields2d) { check_projection<2>(); }
TEST(RigidMotion, IsTheLumpedMassProjectionOnRigidFields3d) { check_projection<3>(); }

// A body with a prescribed component is not free: its velocity is left as
// it is, while the other body's is projected.
TEST(RigidMotion, LeavesBodiesWithPrescribedMotionAlone) {
  test::ContactRun<3> run(two_bodies(3, "[[boundary]]\nbody = \"block\"\ngroup = \"xmin\"\ncomponents = [\"x\"]\n"));
  const auto& model = run.problem.model;
  ASSERT_FALSE(model.prescribed.dofs.empty());
  const RigidMotion<3> motion(model, node_masses(*run.assembler));
  const Eigen::VectorXd v = Eigen::VectorXd::LinSpaced(model.num_dofs(), -1.0, 2.0);
  Eigen::VectorXd projected = v;
  motion.project(Eigen::VectorXd::Zero(model.num_dofs()), projected);
  const auto& round = model.bodies[0];
  const auto& block = model.bodies[1];
  EXPECT_GT((projected - v).segment(round.first_node * 3, round.num_nodes * 3).norm(), 0.1);
  EXPECT_EQ((projected - v).segment(block.first_node * 3, block.num_nodes * 3).norm(), 0.0);
}

/// The §6.1 disc (steel-stiff, Δt far above its periods), stretched
/// 0.02 % and let go spinning: it vibrates through the run.
std::string vibrating_disc(const std::string& predictor) {
  return "dimension = 3\n[time]\nstep = 2.0e-3\nend = 0.05\n[newton]\npredictor = \"" + predictor +
         "\"\n[[body]]\nname = \"disc\"\nvelocity = [1.0, 0.5, 0.0]\nangular_velocity = [0.0, 0.0, 20.0]\n"
         "initial_deformation = [[1.0002, 0, 0], [0, 1, 0], [0, 0, 1]]\n"
         "[body.material]\nyoung = 2.1e9\npoisson = 0.3\ndensity = 2500.0\n"
         "[body.mesh]\ngenerator = \"cylinder\"\nradius = 0.1\nlength = 0.005\nsize = 0.02\n";
}

// Each step is taken from the same state at the same Δt from both
// starts. The rigid start converges in every one; where the velocity
// start converges too, the ends agree to the Newton tolerance and the
// rigid start took fewer iterations.
TEST(RigidMotion, StartsAVibratingBodyCloserToItsStep) {
  test::ContactRun<3> rigid(vibrating_disc("rigid")), velocity(vibrating_disc("velocity"));
  const double dt = rigid.scenario.time.step;
  int it_rigid = 0, it_velocity = 0, steps = 0, failed = 0;
  double apart = 0.0, speed = 0.0;
  while (rigid.state.time < rigid.scenario.time.end - 1e-9) {
    model::State from_velocity = rigid.state;
    const int iterations = rigid.integrator->step(rigid.state, dt).iterations;  // throws if it fails
    ++steps;
    try {
      it_velocity += velocity.integrator->step(from_velocity, dt).iterations;
    } catch (const SolverError&) {
      ++failed;
      continue;
    }
    it_rigid += iterations;
    speed = std::max(speed, rigid.state.v.lpNorm<Eigen::Infinity>());
    apart = std::max(apart, (rigid.state.u - from_velocity.u).lpNorm<Eigen::Infinity>() / dt);
  }
  std::printf("[ measured ] vibrating disc, %d steps: the velocity start failed %d; on the others Newton took %d "
              "iterations from the rigid start and %d from the velocity start; largest difference of the ends "
              "%.2e m/s · Δt of %.2e m/s\n",
              steps, failed, it_rigid, it_velocity, apart, speed);
  ASSERT_EQ(steps, 25);
  ASSERT_GE(steps - failed, 10);
  EXPECT_LT(apart, 1e-8 * speed);
  EXPECT_LT(it_rigid, it_velocity);
}

// The work of a pushed-out slave's force is taken out of the bodies'
// deformation velocity (Constraint::push): K falls by exactly that work,
// L and J (Σ_A x_A × (M V)_A, the consistent mass) are untouched, and an
// amount above what the deformation velocity can give is refused with V
// left as it was. The update multiplies by M through the nodes' scalar
// mass when M = M_AB ⊗ I_D, as the assembler's is; `coupled` adds a
// coupling between two components of one node, so that the general
// product is taken instead, and must keep the same properties.
template <int D>
void check_restore_energy(bool coupled = false) {
  test::ContactRun<D> run(two_bodies(D));
  const auto& model = run.problem.model;
  const SparseMatrix& node_mass = run.assembler->node_mass();
  SparseMatrix identity(D, D);
  identity.setIdentity();
  SparseMatrix M = Eigen::kroneckerProduct(node_mass, identity);  // the dofs' mass
  if (coupled) {
    const double m = 0.1 * M.coeff(0, 0);
    const std::vector<Eigen::Triplet<double>> coupling{{0, 1, m}, {1, 0, m}};
    SparseMatrix C(M.rows(), M.cols());
    C.setFromTriplets(coupling.begin(), coupling.end());
    M += C;
  }
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const Eigen::VectorXd u = Eigen::VectorXd::NullaryExpr(model.num_dofs(), [&] { return 0.01 * uniform(rng); });
  Eigen::VectorXd v = Eigen::VectorXd::NullaryExpr(model.num_dofs(), [&] { return 0.2 * uniform(rng); });
  const Vec3 omega = D == 3 ? Vec3(3.0, -2.0, 5.0) : Vec3(0.0, 0.0, 5.0);
  for (const auto& body : model.bodies) add_rigid<D>(model, body, u, Vec3(1.0, 2.0, 0.0), omega, v);
  const contact::Positions<D> x = model.X + u.reshaped(D, model.num_nodes());
  auto moments = [&](const Eigen::VectorXd& w) {
    const Eigen::VectorXd p = M * w;
    Vec3 L = Vec3::Zero(), J = Vec3::Zero();
    for (int n = 0; n < model.num_nodes(); ++n) {
      Vec3 xn = Vec3::Zero(), pn = Vec3::Zero();
      xn.head<D>() = x.col(n);
      pn.head<D>() = p.segment<D>(n * D);
      L += pn;
      J += xn.cross(pn);
    }
    return std::pair{L, J};
  };
  const double K = 0.5 * v.dot(M * v);
  const auto [L0, J0] = moments(v);
  const contact::PersistentVelocity<D> restorer(model, coupled ? M : node_mass);
  for (double work : {1e-5 * K, -1e-5 * K}) {  // K_def ≈ 1e-3 K here
    Eigen::VectorXd w = v;
    ASSERT_TRUE(restorer.restore_energy(x, work, w));
    const auto [L, J] = moments(w);
    std::printf("[ measured ] restore_energy %dD, work %+.3e J: K error %.2e, |ΔL| %.2e, |ΔJ| %.2e, |ΔV| %.2e\n", D,
                work, std::abs(0.5 * w.dot(M * w) - (K - work)) / K, (L - L0).norm(), (J - J0).norm(),
                (w - v).norm());
    EXPECT_LT(std::abs(0.5 * w.dot(M * w) - (K - work)), 1e-14 * K);
    EXPECT_LT((L - L0).norm(), 1e-13 * L0.norm());
    EXPECT_LT((J - J0).norm(), 1e-13 * (J0.norm() + L0.norm()));
    EXPECT_GT((w - v).norm(), 1e-4 * v.norm());  // guard: V did change
  }
  Eigen::VectorXd w = v;
  EXPECT_FALSE(restorer.restore_energy(x, K, w));  // more than the deformation velocity carries
  EXPECT_EQ(w, v);
}

TEST(PersistentVelocity, RestoreEnergyKeepsMomenta2d) { check_restore_energy<2>(); }
TEST(PersistentVelocity, RestoreEnergyKeepsMomenta3d) { check_restore_energy<3>(); }
TEST(PersistentVelocity, RestoreEnergyKeepsMomentaWithAMassNotOfNodalForm) { check_restore_energy<3>(true); }

}  // namespace
}  // namespace conserve::time
