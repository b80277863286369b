// The step's residual as a sum of terms (time/step_terms.hpp): each term's
// derivative by the Taylor test of its value, the sum against
// the paper's (20) written out, and a term added from outside summed by
// StepProblem into both the residual and the tangent.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>

#include "material/neo_hookean.hpp"
#include "material/svk_law.hpp"
#include "model/initial_state.hpp"
#include "support/grid_mesh.hpp"
#include "support/taylor.hpp"
#include "contact/surface.hpp"
#include "time/step_problem.hpp"
#include "time/surface_loads.hpp"

namespace conserve::time {
namespace {

/// A stretched, spinning box under gravity at the start of a step, and an
/// iterate u_{n+1} off the step's solution.
struct Fixture {
  model::Model<3> model;
  std::unique_ptr<assembly::Assembler<3>> assembler;
  model::State start;
  Eigen::VectorXd u_np1;
  static constexpr double dt = 0.01;

  /// order 2: the box's 10-node tetrahedra with curved edges (test::quadratic_mesh).
  explicit Fixture(int order = 1) {
    const mesh::Mesh box = test::box_mesh(3, 2, 2, 1.0, 0.4, 0.3);
    model::add_body<3>(model, order == 1 ? box : test::quadratic_mesh(box, 0.05), "block",
                       std::make_shared<const material::Svk>(material::Lame::from_young_poisson(5.0e4, 0.3)), 1000.0, 1.0);
    model.gravity = Vec3(0.0, 0.0, -9.81);
    assembler = std::make_unique<assembly::Assembler<3>>(model, false);
    start = model::rest_state<3>(model);
    model::InitialMotion motion;
    motion.deformation << 1.15, 0.1, 0.0, -0.05, 0.9, 0.05, 0.0, 0.05, 1.05;
    motion.velocity << 1.0, 0.5, 0.25;
    motion.angular_velocity = Vec3(0.5, 1.0, 3.0);
    model::set_initial_motion<3>(model, 0, motion, start);
    u_np1 = start.u + dt * start.v;
    for (Eigen::Index i = 0; i < u_np1.size(); ++i) u_np1[i] += 1e-3 * std::sin(1.7 * static_cast<double>(i));
  }
};

/// The Taylor test (support/taylor.hpp) of a term's value at u along a
/// random direction, against its derivative times the direction.
test::TaylorOrder derivative_order(StepTerm<3>& term, const Eigen::VectorXd& u, const SparseMatrix& pattern) {
  SparseMatrix K = pattern;
  std::fill(K.valuePtr(), K.valuePtr() + K.nonZeros(), 0.0);
  term.add_derivative(u, K);
  auto value = [&](const Eigen::VectorXd& x) {
    Eigen::VectorXd g = Eigen::VectorXd::Zero(x.size()), m = Eigen::VectorXd::Zero(x.size());
    term.add_value(x, g, m);
    return g;
  };
  std::mt19937 rng(3);
  const Eigen::VectorXd d = test::random_direction(rng, u.size());
  return test::taylor_order(value, u, d, K * d, 1e-3);
}

// The inertia is linear in u_{n+1}: its remainder has no order but is
// round-off at every step; the body force is constant, its derivative and
// remainder exactly zero; the internal force's remainder is of order 2.
TEST(StepTerms, EachDerivativeMatchesDifferencesOfItsValue) {
  Fixture f;
  StepTerms<3> terms = elastodynamic_terms(*f.assembler, fem::StressScheme::conserving);
  ASSERT_EQ(terms.size(), 3u);
  for (const auto& term : terms) {
    term->begin(f.start, Fixture::dt);
    const test::TaylorOrder t = derivative_order(*term, f.u_np1, f.assembler->pattern().make_matrix());
    const std::string name(term->name());
    std::printf("[ measured ] %s: %s\n", name.c_str(), test::describe(t).c_str());
    if (name == "body force") {
      EXPECT_EQ(t.slope, 0.0);  // a constant force
      EXPECT_EQ(test::largest_remainder(t), 0.0);
    } else if (name == "inertia") {
      test::expect_exact(t, name);
    } else {
      test::expect_second_order(t, name);
    }
  }
}

// A follower pressure on the whole boundary and a traction on one face
// (each with a curve), on linear and on curved quadratic facets: the
// pressure's derivative (its area vectors at the mid-point configuration)
// by the Taylor test, a remainder of order 2; the traction's is zero. On
// the closed surface the pressure has no resultant and no moment (exact
// for a P2 surface by the degree-4 rule).
void check_surface_load_derivative(int order) {
  Fixture f(order);
  f.model.prescribed.curves.push_back(model::Curve{{0.0, 1.0}, {0.5, 2.0}});
  model::SurfaceLoad pressure;
  pressure.kind = model::SurfaceLoad::Kind::pressure;
  pressure.body = 0;
  pressure.facets = contact::make_surface<3>(f.model, 0, "boundary").facets;
  ASSERT_EQ(pressure.facets.rows(), order == 1 ? 3 : 6);
  pressure.pressure = 2.0e3;
  pressure.curve = 0;
  model::SurfaceLoad traction;
  traction.body = 0;
  traction.facets = contact::make_surface<3>(f.model, 0, "xmin").facets;
  traction.traction = Vec3(1.0e3, -2.0e3, 5.0e2);
  f.model.loads = {pressure, traction};
  SurfaceLoads<3> loads(*f.assembler);
  loads.begin(f.start, Fixture::dt);
  const test::TaylorOrder t = derivative_order(loads, f.u_np1, f.assembler->pattern().make_matrix());
  std::printf("[ measured ] surface loads, order %d: %s\n", order, test::describe(t).c_str());
  test::expect_second_order(t, "surface loads");
  // The pressure alone: no resultant, no moment about the origin at the mid-point configuration.
  f.model.loads = {pressure};
  SurfaceLoads<3> alone(*f.assembler);
  alone.begin(f.start, Fixture::dt);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(f.u_np1.size()), m = g;
  alone.add_value(f.u_np1, g, m);
  const Eigen::VectorXd u_mid = 0.5 * (f.start.u + f.u_np1);
  Vec3 resultant = Vec3::Zero(), moment = Vec3::Zero();
  for (int n = 0; n < f.model.num_nodes(); ++n) {
    const Vec3 x = f.model.X.col(n) + u_mid.segment<3>(3 * n), force = -g.segment<3>(3 * n);
    resultant += force;
    moment += x.cross(force);
  }
  std::printf("[ measured ] follower pressure on a closed surface, order %d: resultant %.2e N, moment %.2e N m (of "
              "%.2e N)\n",
              order, resultant.norm(), moment.norm(), m.norm());
  EXPECT_GT(m.norm(), 1.0);
  EXPECT_LT(resultant.norm(), 1e-12 * m.norm());
  EXPECT_LT(moment.norm(), 1e-12 * m.norm());
}

TEST(StepTerms, SurfaceLoadDerivativeMatchesDifferences) { check_surface_load_derivative(1); }
TEST(StepTerms, SurfaceLoadDerivativeMatchesDifferencesOnCurvedQuadraticFacets) { check_surface_load_derivative(2); }

// (20): g = (2/Δt²) M Δu − (2/Δt) M V_n + f_int(u_n, u_{n+1}) − f_ext.
TEST(StepTerms, SumIsThePaperResidual) {
  Fixture f;
  StepTerms<3> terms = elastodynamic_terms(*f.assembler, fem::StressScheme::conserving);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(f.u_np1.size()), m = g;
  for (const auto& term : terms) {
    term->begin(f.start, Fixture::dt);
    term->add_value(f.u_np1, g, m);
  }
  const auto& a = *f.assembler;
  Eigen::VectorXd f_int;
  a.internal_force(f.start.u, f.u_np1, fem::StressScheme::conserving, f_int);
  const double dt = Fixture::dt;
  const Eigen::VectorXd expected = (2.0 / (dt * dt)) * a.mass_times(f.u_np1 - f.start.u) -
                                   (2.0 / dt) * a.mass_times(f.start.v) + f_int - a.gravity_force();
  const double error = (g - expected).norm() / expected.norm();
  std::printf("[ measured ] sum of the terms vs (20): %.2e relative\n", error);
  EXPECT_GT(expected.norm(), 1.0);
  EXPECT_LT(error, 1e-14);
  EXPECT_TRUE((m.array() >= g.cwiseAbs().array()).all());  // magnitudes bound what they sum
  // The scales: kinetic + stored energy + |f_ext·u_n|.
  double energy = 0.0;
  for (const auto& term : terms) energy += term->start_energy();
  const double kinetic = 0.5 * f.start.v.dot(a.mass_times(f.start.v));
  const double expected_energy =
      kinetic + a.strain_energy(f.start.u) + std::abs(a.gravity_force().dot(f.start.u));
  EXPECT_NEAR(energy, expected_energy, 1e-14 * expected_energy);
}

/// A linear spring to the start, k (u_{n+1} − u_n): a term from outside.
class Spring final : public StepTerm<3> {
 public:
  explicit Spring(double k) : k_(k) {}
  [[nodiscard]] std::string_view name() const override { return "spring"; }
  void begin(const model::State& start, double) override { u_n_ = start.u; }
  [[nodiscard]] double start_force() const override { return 0.0; }
  [[nodiscard]] double start_energy() const override { return 0.0; }
  void add_value(const Eigen::VectorXd& u, Eigen::VectorXd& g, Eigen::VectorXd& m) override {
    g += k_ * (u - u_n_);
    m += k_ * (u - u_n_).cwiseAbs();
  }
  void add_derivative(const Eigen::VectorXd&, SparseMatrix& K) override {
    for (Eigen::Index i = 0; i < K.rows(); ++i) K.coeffRef(i, i) += k_;
  }

 private:
  double k_;
  Eigen::VectorXd u_n_;
};

/// The fixture's elastodynamic terms begun at its start, no prescribed
/// dofs, and a matrix of the tangent's pattern.
struct Begun {
  explicit Begun(const Fixture& f)
      : mask(f.assembler->pattern().make_matrix(), {}),
        terms(elastodynamic_terms(*f.assembler, fem::StressScheme::conserving)),
        K(f.assembler->pattern().make_matrix()) {
    for (const auto& term : terms) term->begin(f.start, Fixture::dt);
  }
  assembly::DirichletMask mask;
  StepTerms<3> terms;
  SparseMatrix K;
};

TEST(StepTerms, StepProblemSumsATermAddedFromOutside) {
  Fixture f;
  Begun b(f);
  const assembly::DirichletMask& mask = b.mask;
  StepTerms<3>& terms = b.terms;
  SparseMatrix& K = b.K;
  Eigen::VectorXd u = f.u_np1, r0, r1;
  StepProblem<3> plain(*f.assembler, mask, terms, f.start, Fixture::dt, u, K);
  plain.residual(r0);
  const Eigen::MatrixXd K0(plain.tangent());

  const double k = 1.0e5;
  terms.push_back(std::make_unique<Spring>(k));
  terms.back()->begin(f.start, Fixture::dt);
  StepProblem<3> sprung(*f.assembler, mask, terms, f.start, Fixture::dt, u, K);
  sprung.residual(r1);
  const Eigen::MatrixXd K1(sprung.tangent());
  const Eigen::VectorXd spring = k * (u - f.start.u);
  EXPECT_GT(spring.norm(), 1.0);
  EXPECT_LT((r1 - r0 - spring).norm(), 1e-12 * r1.norm());
  const Eigen::MatrixXd dK = K1 - K0;
  EXPECT_LT((dK - k * Eigen::MatrixXd::Identity(dK.rows(), dK.cols())).norm(), 1e-12 * K1.norm());
}

// StepProblem::prepare_tangent: the residual that assembles the tangent in
// the same pass gives the same bits, residual and tangent, as the two
// passes; an update in between leaves the tangent to be assembled anew.
TEST(StepTerms, ResidualWithItsTangentInOnePassIsTheSameBits) {
  for (const bool svk : {true, false}) {
    SCOPED_TRACE(svk ? "SVK" : "neo-Hookean");
    Fixture f;
    if (!svk)
      f.model.bodies[0].law =
          std::make_shared<const material::NeoHookean>(material::Lame::from_young_poisson(5.0e4, 0.3));
    Begun b(f);
    Eigen::VectorXd u = f.u_np1, r0, r1;
    SparseMatrix& K = b.K;
    StepProblem<3> problem(*f.assembler, b.mask, b.terms, f.start, Fixture::dt, u, K);
    problem.residual(r0);
    const double floor0 = problem.residual_floor();
    const SparseMatrix K0 = problem.tangent();
    ASSERT_GT(K0.norm(), 0.0);
    problem.prepare_tangent();
    problem.residual(r1);
    EXPECT_EQ(0, std::memcmp(r0.data(), r1.data(), sizeof(double) * static_cast<std::size_t>(r0.size())));
    EXPECT_EQ(floor0, problem.residual_floor());
    const SparseMatrix K1 = problem.tangent();
    ASSERT_EQ(K0.nonZeros(), K1.nonZeros());
    EXPECT_EQ(0, std::memcmp(K0.valuePtr(), K1.valuePtr(), sizeof(double) * static_cast<std::size_t>(K0.nonZeros())));
    // The tangent at that iterate is not assembled a second time.
    problem.prepare_tangent();
    problem.residual(r1);
    std::fill(K.valuePtr(), K.valuePtr() + K.nonZeros(), -1.0);
    const SparseMatrix& K_again = problem.tangent();
    EXPECT_EQ(-1.0, K_again.valuePtr()[0]);
    // An update between the residual and the tangent: the tangent is that
    // of the new iterate, as without the hint.
    const Eigen::VectorXd step = 1e-4 * Eigen::VectorXd::Ones(u.size());
    problem.prepare_tangent();
    problem.residual(r1);
    problem.update(step);
    const SparseMatrix K2 = problem.tangent();
    Eigen::VectorXd u2 = f.u_np1 + step;
    SparseMatrix Kref = f.assembler->pattern().make_matrix();
    StepProblem<3> reference(*f.assembler, b.mask, b.terms, f.start, Fixture::dt, u2, Kref);
    const SparseMatrix K3 = reference.tangent();
    EXPECT_GT((Eigen::MatrixXd(K2) - Eigen::MatrixXd(K0)).norm(), 0.0);
    EXPECT_EQ(0, std::memcmp(K2.valuePtr(), K3.valuePtr(), sizeof(double) * static_cast<std::size_t>(K3.nonZeros())));
  }
}

}  // namespace
}  // namespace conserve::time
