#include <gtest/gtest.h>
#include <unsupported/Eigen/KroneckerProduct>

#include <cstdio>
#include <random>
#include <string>

#include "assembly/assembler.hpp"
#include "assembly/dirichlet.hpp"
#include "material/svk_law.hpp"
#include "support/grid_mesh.hpp"
#include "support/taylor.hpp"

namespace conserve::assembly {
namespace {

template <int D>
model::Model<D> small_model() {
  model::Model<D> m;
  const auto mesh = D == 3 ? test::box_mesh(3, 2, 2, 0.6, 0.4, 0.4) : test::rectangle_mesh(4, 3, 0.8, 0.6);
  model::add_body<D>(m, mesh, "a", std::make_shared<const material::Svk>(material::Lame::from_young_poisson(1e5, 0.3)),
                     1200.0, 0.5);
  model::add_body<D>(m, mesh, "b", std::make_shared<const material::Svk>(material::Lame::from_young_poisson(3e5, 0.2)),
                     800.0, 0.5);
  return m;
}

// The assembled tangent ∂f_int/∂u_{n+1} of two bodies by the Taylor test of
// the internal force along random directions of u_{n+1} (a remainder of
// order 2, support/taylor.hpp).
template <int D>
void check_global_tangent(const model::Model<D>& model) {
  const Assembler<D> assembler(model, false);
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-0.05, 0.05);
  Eigen::VectorXd u_n(model.num_dofs()), u_np1(model.num_dofs());
  for (int i = 0; i < model.num_dofs(); ++i) u_n[i] = u(rng), u_np1[i] = u(rng);
  Eigen::VectorXd f;
  SparseMatrix K = assembler.pattern().make_matrix();
  assembler.internal_force_tangent(u_n, u_np1, fem::StressScheme::conserving, f, K);
  ASSERT_GT(K.norm(), 1e3);  // non-zero guard
  Eigen::VectorXd f_check;
  assembler.internal_force(u_n, u_np1, fem::StressScheme::conserving, f_check);
  EXPECT_LT((f - f_check).norm(), 1e-12 * f.norm());
  auto force = [&](const Eigen::VectorXd& at) {
    Eigen::VectorXd out;
    assembler.internal_force(u_n, at, fem::StressScheme::conserving, out);
    return out;
  };
  for (int direction = 0; direction < 3; ++direction) {
    const Eigen::VectorXd d = test::random_direction(rng, model.num_dofs());
    const test::TaylorOrder t = test::taylor_order(force, u_np1, d, K * d, 1e-3 * model.size());
    std::printf("[ measured ] assembled tangent %dD, direction %d: %s\n", D, direction + 1, test::describe(t).c_str());
    test::expect_second_order(t, "direction " + std::to_string(direction + 1));
  }
}

TEST(Assembler, GlobalTangentMatchesFiniteDifferences2d) { check_global_tangent<2>(small_model<2>()); }
TEST(Assembler, GlobalTangentMatchesFiniteDifferences3d) { check_global_tangent<3>(small_model<3>()); }

// The same with curved quadratic cells of a nearly incompressible
// neo-Hookean body with the mean dilatation (fem/mean_dilatation.hpp).
template <int D>
model::Model<D> mean_dilatation_model() {
  model::Model<D> m;
  const auto mesh = test::quadratic_mesh(
      D == 3 ? test::box_mesh(3, 2, 2, 0.6, 0.4, 0.4) : test::rectangle_mesh(4, 3, 0.8, 0.6), 0.03);
  model::add_body<D>(m, mesh, "a", material::make_law("neo_hookean", {{"young", 1e5}, {"poisson", 0.4999}}), 1200.0,
                     0.5);
  m.bodies[0].mean_dilatation = true;
  return m;
}
TEST(Assembler, MeanDilatationTangentMatchesFiniteDifferences2d) {
  check_global_tangent<2>(mean_dilatation_model<2>());
}
TEST(Assembler, MeanDilatationTangentMatchesFiniteDifferences3d) {
  check_global_tangent<3>(mean_dilatation_model<3>());
}

template <int D>
void check_mass(bool lumped) {
  const model::Model<D> model = small_model<D>();
  const Assembler<D> assembler(model, lumped);
  double total = 0.0;
  for (const auto& g : model.geometry) total += g.volume;
  const double expected = D * (1200.0 + 800.0) * total / 2.0;  // two equal bodies, D components
  const Eigen::MatrixXd M(assembler.node_mass());
  EXPECT_NEAR(D * M.sum(), expected, 1e-12 * expected);
  if (lumped) EXPECT_NEAR(D * M.diagonal().sum(), expected, 1e-12 * expected);
}

TEST(Assembler, MassTotalIsExact) {
  check_mass<2>(false);
  check_mass<2>(true);
  check_mass<3>(false);
  check_mass<3>(true);
}

TEST(Assembler, BodiesAreUncoupled) {
  const model::Model<3> model = small_model<3>();
  const Assembler<3> assembler(model, false);
  const int split = model.bodies[1].first_node;
  const Eigen::MatrixXd M(assembler.node_mass());
  EXPECT_EQ(M.topRightCorner(split, M.cols() - split).norm(), 0.0);
}

// add_mass puts c M_AB on the diagonal of each D × D block of the
// pattern's matrix (M = M_AB ⊗ I_D) and nothing elsewhere; find() gives
// every entry's position in the pattern, and −1 outside it.
template <int D>
void check_mass_in_pattern() {
  const model::Model<D> model = small_model<D>();
  const Assembler<D> assembler(model, false);
  SparseMatrix K = assembler.pattern().make_matrix();
  assembler.add_mass(2.0, K);
  const Eigen::MatrixXd node(assembler.node_mass());
  ASSERT_GT(node.norm(), 0.0);
  const Eigen::MatrixXd expected = Eigen::kroneckerProduct(2.0 * node, Eigen::MatrixXd::Identity(D, D));
  EXPECT_EQ((Eigen::MatrixXd(K) - expected).norm(), 0.0);
  int outside = 0;
  for (int col = 0; col < K.cols(); ++col) {
    for (int p = K.outerIndexPtr()[col]; p < K.outerIndexPtr()[col + 1]; ++p)
      EXPECT_EQ(assembler.pattern().find(K.innerIndexPtr()[p], col), p);
    for (int row = 0; row < K.rows(); ++row)
      if (node(row / D, col / D) == 0.0 && assembler.pattern().find(row, col) < 0) ++outside;
  }
  EXPECT_GT(outside, 0);  // the two bodies do not couple
  EXPECT_EQ(assembler.pattern().find(0, model.bodies[1].first_node * D), -1);
}

TEST(Assembler, MassGoesOnTheBlockDiagonalsOfThePattern) {
  check_mass_in_pattern<2>();
  check_mass_in_pattern<3>();
}

TEST(Dirichlet, MaskedRowsAndColumnsAreIdentity) {
  const model::Model<2> model = small_model<2>();
  const Assembler<2> assembler(model, false);
  SparseMatrix K = assembler.pattern().make_matrix();
  assembler.add_mass(1.0, K);
  const DirichletMask mask(K, {0, 3, 7});
  mask.apply(K, 2.5);
  const Eigen::MatrixXd Kd(K);
  for (int d : {0, 3, 7}) {
    Eigen::VectorXd e = Eigen::VectorXd::Unit(K.rows(), d) * 2.5;
    EXPECT_EQ((Kd.col(d) - e).norm(), 0.0);
    EXPECT_EQ((Kd.row(d).transpose() - e).norm(), 0.0);
  }
  Eigen::VectorXd r = Eigen::VectorXd::Ones(K.rows());
  mask.apply(r);
  EXPECT_EQ(r[3], 0.0);
  EXPECT_EQ(r[4], 1.0);
}

}  // namespace
}  // namespace conserve::assembly
