// The direct-elimination map T (docs/theory.md, "Direct elimination
// (33)–(65)"): Δu_s = N Δu_m (35) or N Δu_m + τ Δξ (49), chains by
// substitution, cycles solved together, the reduced residual (41), the dummy diagonal
// β = tr(K_ss)/D (44), and the reduced tangent's Wᵀ K T (43) against the
// plain matrix products, with its pattern kept between calls.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>

#include "contact/elimination/elimination.hpp"
#include "core/error.hpp"

namespace conserve::contact {
namespace {

Constraint<3> stick(int slave, std::array<int, 3> master, double xi, double eta) {
  Constraint<3> c;
  c.slave = slave;
  c.master = master;
  c.xi << xi, eta;
  c.kind = Kind::stick;
  return c;
}

Eigen::VectorXd random_vector(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::VectorXd v(n);
  for (int i = 0; i < n; ++i) v[i] = u(rng);
  return v;
}

TEST(Elimination, StickSlaveFollowsItsMasterPoint) {
  std::vector<Constraint<3>> constraints{stick(0, {1, 2, 3}, 0.2, 0.3)};
  const Elimination<3> e(8, constraints);
  const Eigen::VectorXd q = random_vector(24, 1);
  Eigen::VectorXd du;
  e.expand(q, du);
  const Vec3 expected = 0.5 * q.segment<3>(3) + 0.2 * q.segment<3>(6) + 0.3 * q.segment<3>(9);  // (35)
  EXPECT_LT((du.segment<3>(0) - expected).norm(), 1e-15);
  EXPECT_EQ((du.tail(15) - q.tail(15)).norm(), 0.0);  // free nodes unchanged
}

TEST(Elimination, FrictionlessSlaveSlidesAlongTangents) {
  Constraint<3> c = stick(0, {1, 2, 3}, 0.2, 0.3);
  c.kind = Kind::frictionless;
  c.tangents << 1, 0, 0, 1, 0, 0;  // τ_ξ = x̂, τ_η = ŷ
  std::vector<Constraint<3>> constraints{c};
  const Elimination<3> e(4, constraints);
  const Eigen::VectorXd q = random_vector(12, 2);
  Eigen::VectorXd du;
  e.expand(q, du);
  const Vec3 expected = 0.5 * q.segment<3>(3) + 0.2 * q.segment<3>(6) + 0.3 * q.segment<3>(9) +
                        Vec3(q[0], q[1], 0.0);  // (49): slave slots 0, 1 carry Δξ, Δη; slot 2 is the dummy
  EXPECT_LT((du.segment<3>(0) - expected).norm(), 1e-15);
}

TEST(Elimination, ChainsAreComposed) {
  // Node 0 is a slave on (1, 2, 3); node 1 is itself a slave on (4, 5, 6).
  std::vector<Constraint<3>> constraints{stick(0, {1, 2, 3}, 0.25, 0.25), stick(1, {4, 5, 6}, 0.1, 0.6)};
  const Elimination<3> e(7, constraints);
  const Eigen::VectorXd q = random_vector(21, 3);
  Eigen::VectorXd du;
  e.expand(q, du);
  const Vec3 du1 = 0.3 * q.segment<3>(12) + 0.1 * q.segment<3>(15) + 0.6 * q.segment<3>(18);
  const Vec3 du0 = 0.5 * du1 + 0.25 * q.segment<3>(6) + 0.25 * q.segment<3>(9);
  EXPECT_LT((du.segment<3>(3) - du1).norm(), 1e-15);
  EXPECT_LT((du.segment<3>(0) - du0).norm(), 1e-15);
}

// Two passes and self-contact make cycles: a slave's master node is held
// on a facet of the slave. Their rows are solved together,
// (I − C_KK) Δu_K = C_K,ext Δu_ext + slips, so every constraint of the
// cycle holds; a cycle whose constraints repeat each other (the slaves on
// each other's nodes) is refused as redundant.
TEST(Elimination, CyclesAreSolvedTogether) {
  std::vector<Constraint<3>> cycle{stick(0, {1, 2, 3}, 0.2, 0.3), stick(1, {0, 5, 6}, 0.1, 0.2)};
  const Elimination<3> e(7, cycle);
  const Eigen::VectorXd q = random_vector(21, 3);
  Eigen::VectorXd du;
  e.expand(q, du);
  const Vec3 du0 = 0.5 * du.segment<3>(3) + 0.2 * q.segment<3>(6) + 0.3 * q.segment<3>(9);
  const Vec3 du1 = 0.7 * du.segment<3>(0) + 0.1 * q.segment<3>(15) + 0.2 * q.segment<3>(18);
  EXPECT_GT(du.segment<3>(0).norm(), 0.1);
  EXPECT_LT((du.segment<3>(0) - du0).norm(), 1e-15);
  EXPECT_LT((du.segment<3>(3) - du1).norm(), 1e-15);
  // Frictionless with slips: each slave's normal motion follows its facet.
  Constraint<3> a = cycle[0], b = cycle[1];
  a.kind = b.kind = Kind::frictionless;
  a.tangents << 1, 0, 0, 1, 0, 0;
  b.tangents << 1, 0, 0, 0, 1, 0;  // b's normal is ŷ
  std::vector<Constraint<3>> sliding{a, b};
  const Elimination<3> f(7, sliding);
  f.expand(q, du);
  auto point = [&](const Constraint<3>& c) {
    const Vec3 N = facet_shape<3>(c.xi);
    Vec3 p = Vec3::Zero();
    for (int k = 0; k < 3; ++k) p += N(k) * du.segment<3>(3 * c.master[k]);
    return p;
  };
  EXPECT_LT(std::abs(du.segment<3>(0).z() - point(a).z()), 1e-15);
  EXPECT_LT(std::abs(du.segment<3>(3).y() - point(b).y()), 1e-15);
  // The residual passes through the transposed rows: r = Wᵀ g.
  const Eigen::VectorXd g = random_vector(21, 4);
  Eigen::VectorXd r;
  f.reduce_residual(g, r);
  const Eigen::VectorXd expected = f.test_map().transpose() * g;
  EXPECT_GT(expected.norm(), 1.0);
  EXPECT_LT((r - expected).norm(), 1e-14);
  // Each slave on the other's node: the same constraint twice.
  std::vector<Constraint<3>> redundant{stick(0, {1, 2, 3}, 0.0, 0.0), stick(1, {0, 5, 6}, 0.0, 0.0)};
  EXPECT_THAT([&] { Elimination<3>(7, redundant); },
              ::testing::ThrowsMessage<SolverError>(::testing::HasSubstr("redundant")));
  std::vector<Constraint<3>> twice{stick(0, {1, 2, 3}, 0.2, 0.2), stick(0, {4, 5, 6}, 0.2, 0.2)};
  EXPECT_THROW(Elimination<3>(7, twice), SolverError);
}

// A slave holding two frictionless constraints (a node on two slave
// surfaces): its motion keeps both gaps to first order, n_kᵀ(Δu_s − N_k
// Δu_mk) = 0, slides along n_1 × n_2 with slot 0, and its residual is split
// between the two masters by the least-squares forces f = G⁻¹[n_1 n_2]ᵀ g_s
// (the test map is the trial map's transpose without geometry).
TEST(Elimination, TwoFrictionlessConstraintsOnOneSlave) {
  Constraint<3> a = stick(0, {1, 2, 3}, 0.2, 0.3), b = stick(0, {4, 5, 6}, 0.5, 0.1);
  a.kind = b.kind = Kind::frictionless;
  a.pair = 0;
  b.pair = 1;
  a.normal = Vec3(0.0, 0.0, 1.0);
  b.normal = Vec3(1.0, 0.0, 1.0).normalized();  // 45° apart
  std::vector<Constraint<3>> constraints{a, b};
  const Elimination<3> e(7, constraints);
  const Eigen::VectorXd q = random_vector(21, 7);
  Eigen::VectorXd du;
  e.expand(q, du);
  auto point = [&](const Constraint<3>& c) {
    const Vec3 N = facet_shape<3>(c.xi);
    Vec3 p = Vec3::Zero();
    for (int k = 0; k < 3; ++k) p += N(k) * du.segment<3>(3 * c.master[k]);
    return p;
  };
  EXPECT_LT(std::abs(a.normal.dot(du.segment<3>(0) - point(a))), 1e-15);
  EXPECT_LT(std::abs(b.normal.dot(du.segment<3>(0) - point(b))), 1e-15);
  Eigen::VectorXd q_slip = Eigen::VectorXd::Zero(21);
  q_slip[0] = 1.0;  // the slave's slot 0 alone: the slip along the edge
  e.expand(q_slip, du);
  EXPECT_LT((du.segment<3>(0).cwiseAbs() - Vec3(0.0, 1.0, 0.0)).norm(), 1e-15);
  // Residual: a force f_1 n_1 + f_2 n_2 on the slave goes to the masters.
  const Eigen::VectorXd g = [&] {
    Eigen::VectorXd v = Eigen::VectorXd::Zero(21);
    v.segment<3>(0) = 2.0 * a.normal + 3.0 * b.normal;
    return v;
  }();
  Eigen::VectorXd r;
  e.reduce_residual(g, r);
  EXPECT_LT(r.segment<3>(0).norm(), 1e-15);  // no slip force, dummies zero
  const Vec3 Na = facet_shape<3>(a.xi), Nb = facet_shape<3>(b.xi);
  for (int k = 0; k < 3; ++k) {
    EXPECT_LT((r.segment<3>(3 * a.master[k]) - 2.0 * Na(k) * a.normal).norm(), 1e-14);
    EXPECT_LT((r.segment<3>(3 * b.master[k]) - 3.0 * Nb(k) * b.normal).norm(), 1e-14);
  }
  // Three constraints, or two of one pair, are refused.
  Constraint<3> c = b;
  c.pair = 2;
  std::vector<Constraint<3>> three{a, b, c};
  EXPECT_THAT([&] { Elimination<3>(7, three); },
              ::testing::ThrowsMessage<SolverError>(::testing::HasSubstr("at most two")));
  Constraint<3> same = b;
  same.pair = 0;
  std::vector<Constraint<3>> one_pair{a, same};
  EXPECT_THROW(Elimination<3>(7, one_pair), SolverError);
}

// (41): slave rows vanish, master rows get Nᵀ g_s, the others are untouched.
TEST(Elimination, ReducedResidualIsPaperEquation41) {
  std::vector<Constraint<3>> constraints{stick(0, {1, 2, 3}, 0.2, 0.3)};
  const Elimination<3> e(5, constraints);
  const Eigen::VectorXd g = random_vector(15, 4);
  Eigen::VectorXd r;
  e.reduce_residual(g, r);
  EXPECT_EQ(r.segment<3>(0).norm(), 0.0);
  const double N[3] = {0.5, 0.2, 0.3};
  for (int a = 0; a < 3; ++a)
    EXPECT_LT((r.segment<3>(3 * (a + 1)) - g.segment<3>(3 * (a + 1)) - N[a] * g.segment<3>(0)).norm(), 1e-15);
  EXPECT_EQ((r.segment<3>(12) - g.segment<3>(12)).norm(), 0.0);
}

// (43)–(44): K_r = Tᵀ K T with β = tr(K_ss)/D on the slave's dummy diagonal.
TEST(Elimination, ReducedTangentHasBetaOnDummyRows) {
  std::vector<Constraint<3>> constraints{stick(0, {1, 2, 3}, 0.2, 0.3)};
  const Elimination<3> e(5, constraints);
  Eigen::MatrixXd Kd = Eigen::MatrixXd::Random(15, 15) + 10.0 * Eigen::MatrixXd::Identity(15, 15);
  const SparseMatrix K = Kd.sparseView();
  SparseMatrix Kr;
  e.reduce_tangent(K, Eigen::VectorXd::Zero(15), Kr);
  const Eigen::MatrixXd T(e.map());
  const Eigen::MatrixXd expected = T.transpose() * Kd * T;
  const double beta = (Kd(0, 0) + Kd(1, 1) + Kd(2, 2)) / 3.0;
  Eigen::MatrixXd Kr_d(Kr);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(Kr_d(i, i), beta, 1e-14);
  Kr_d.topLeftCorner<3, 3>().setZero();
  EXPECT_LT((Kr_d - expected).norm(), 1e-12);
  EXPECT_EQ(Kr.rows(), K.rows());  // the number of equations stays the same
}

// A slave of each kind, one of them chained (its master node is the other's
// slave), and free nodes: 3D slaves 0 (stick on 1, 2, 3), 1 (frictionless
// on 4, 5, 6) and 7 (frictionless on 8, 9, 4); 2D slaves 0 (stick on 1, 2),
// 1 (frictionless on 3, 4) and 5 (frictionless on 6, 7).
template <int D>
std::vector<Constraint<D>> chained_constraints() {
  std::vector<Constraint<D>> out(3);
  const std::vector<std::vector<int>> nodes =
      D == 3 ? std::vector<std::vector<int>>{{0, 1, 2, 3}, {1, 4, 5, 6}, {7, 8, 9, 4}}
             : std::vector<std::vector<int>>{{0, 1, 2}, {1, 3, 4}, {5, 6, 7}};
  for (int c = 0; c < 3; ++c) {
    Constraint<D>& k = out[c];
    k.kind = c == 0 ? Kind::stick : Kind::frictionless;
    k.slave = nodes[c][0];
    for (int a = 0; a < D; ++a) k.master[a] = nodes[c][a + 1];
    k.xi.setConstant(0.2 + 0.1 * c);
    k.tangents = random_vector(D * (D - 1), 10 + c).reshaped(D, D - 1);
  }
  return out;
}

/// A random K over `nodes` nodes: node blocks (as the assembler's pattern)
/// or scattered entries; always the diagonal.
template <int D>
SparseMatrix random_tangent(int nodes, bool node_blocks, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Eigen::Triplet<double>> t;
  const int n = nodes * D;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const bool couple = node_blocks ? (i / D + j / D) % 3 != 1 : u(rng) > 0.4;
      if (i == j || couple) t.emplace_back(i, j, u(rng) + (i == j ? 10.0 : 0.0));
    }
  SparseMatrix K(n, n);
  K.setFromTriplets(t.begin(), t.end());
  return K;
}

/// Wᵀ K T + β from the maps as dense matrices.
template <int D>
Eigen::MatrixXd product_formula(const Elimination<D>& e, const SparseMatrix& K) {
  const Eigen::MatrixXd T(e.map()), W(e.test_map()), Kd(K);
  Eigen::MatrixXd out = W.transpose() * Kd * T;
  for (const Constraint<D>& k : e.constraints()) {
    const double beta = Kd.diagonal().template segment<D>(k.slave * D).sum() / D;  // (44)
    for (int j = (k.kind == Kind::frictionless ? D - 1 : 0); j < D; ++j) out(k.slave * D + j, k.slave * D + j) += beta;
  }
  return out;
}

template <int D>
void check_reduced_tangent_against_products() {
  constexpr int kNodes = D == 3 ? 11 : 9;
  std::vector<Constraint<D>> constraints = chained_constraints<D>();
  const Elimination<D> e(kNodes, constraints);
  for (const bool node_blocks : {true, false}) {
    const SparseMatrix K = random_tangent<D>(kNodes, node_blocks, 5);
    SparseMatrix Kr;
    e.reduce_tangent(K, Eigen::VectorXd::Zero(kNodes * D), Kr);
    const Eigen::MatrixXd expected = product_formula(e, K);
    const double error = (Eigen::MatrixXd(Kr) - expected).norm() / expected.norm();
    std::printf("[ measured ] %dD, %s K: reduced tangent vs Wᵀ K T + β: %.1e relative\n", D,
                node_blocks ? "node-block" : "scattered", error);
    EXPECT_GT(expected.norm(), 1.0);  // non-zero guard
    EXPECT_LT(error, 1e-14);
    for (int j = 0; j < K.outerSize(); ++j)  // K's pattern is kept
      for (SparseMatrix::InnerIterator it(K, j); it; ++it) {
        const int* begin = Kr.innerIndexPtr() + Kr.outerIndexPtr()[j];
        const int* end = Kr.innerIndexPtr() + Kr.outerIndexPtr()[j + 1];
        EXPECT_TRUE(std::binary_search(begin, end, static_cast<int>(it.row())));
      }
  }
}

TEST(Elimination, ReducedTangentEqualsTheProducts3d) { check_reduced_tangent_against_products<3>(); }
TEST(Elimination, ReducedTangentEqualsTheProducts2d) { check_reduced_tangent_against_products<2>(); }

// New values in the same pattern: K_r keeps its storage and pattern (a
// solver's symbolic analysis stays valid); a new pattern of K is followed.
TEST(Elimination, ReducedTangentKeepsItsPattern) {
  std::vector<Constraint<3>> constraints = chained_constraints<3>();
  const Elimination<3> e(11, constraints);
  const Eigen::VectorXd g = Eigen::VectorXd::Zero(33);
  SparseMatrix K = random_tangent<3>(11, true, 6), Kr;
  EXPECT_TRUE(e.reduce_tangent(K, g, Kr));  // K_r given its pattern
  const int* storage = Kr.innerIndexPtr();
  const std::vector<int> inner(storage, storage + Kr.nonZeros());
  K.coeffs() = random_vector(static_cast<int>(K.nonZeros()), 7);
  K.coeffs()(0) = 0.0;
  EXPECT_FALSE(e.reduce_tangent(K, g, Kr));
  EXPECT_EQ(Kr.innerIndexPtr(), storage);
  EXPECT_TRUE(std::equal(inner.begin(), inner.end(), Kr.innerIndexPtr()));
  EXPECT_EQ(e.pattern_builds(), 1);
  EXPECT_LT((Eigen::MatrixXd(Kr) - product_formula(e, K)).norm(), 1e-13);
  const SparseMatrix scattered = random_tangent<3>(11, false, 8);
  EXPECT_TRUE(e.reduce_tangent(scattered, g, Kr));
  EXPECT_EQ(e.pattern_builds(), 2);
  EXPECT_LT((Eigen::MatrixXd(Kr) - product_formula(e, scattered)).norm(), 1e-13);
}

// The held gap gives way to the paper's rate condition (48) when its
// zero-work direction turns tangential (Elimination::enforce). A slave
// held at γ = 0 that starts 1 mm behind a facet which does not move asks
// for a push-out that is the constraint's only non-rigid motion: the
// zero-work direction on the slave is then exactly tangential (ā_s·n = 0),
// a force frictionless contact cannot balance. The slave is given (48)
// instead: it stays where its motion relative to the facet puts it (1 mm
// behind, as in the paper) and its force is the paper's, along n. With the
// facet stretched and the slave sliding, the same push-out is a small part
// of the motion: the gap is held (negative control).
struct PushOutCase {
  Positions<3> X = Positions<3>(3, 4);
  Eigen::VectorXd u_n = Eigen::VectorXd::Zero(12), u = Eigen::VectorXd::Zero(12);
  std::vector<ContactPair<3>> pairs{1};
  std::vector<Constraint<3>> constraints;
  explicit PushOutCase(double stretch) {
    X << 0.3, 0.0, 1.0, 0.0,  // node 0 the slave, 1–3 the facet in z = 0
        0.3, 0.0, 0.0, 1.0,   //
        -1e-3, 0.0, 0.0, 0.0;
    pairs[0].master.facets = Eigen::Matrix<int, 3, 1>(1, 2, 3);
    build_adjacency(pairs[0].master, 3);
    pairs[0].slave.nodes = {0};  // a lone slave node: no facets, no normal
    pairs[0].slave.node_facets = {{}};
    u = u_n;
    u(3 * 2) = stretch;    // node 2 moves along x: the facet stretches
    u(0) = 0.5 * stretch;  // and the slave slides
    Constraint<3> c;
    c.pair = 0;
    c.slave = 0;
    c.kind = Kind::frictionless;
    c.facet = 0;
    c.master = {1, 2, 3};
    c.gap = 0.0;  // pushed out to the facet
    constraints.push_back(c);
  }
  double end_gap() const { return X(2, 0) + u(2); }
};

TEST(Elimination, DegeneratePushOutHoldsThePaperRateCondition) {
  PushOutCase still(0.0);
  Elimination<3> e(still.X, still.u_n, still.u, still.constraints, still.pairs);
  e.enforce(still.u);
  const Constraint<3>& k = still.constraints[0];
  EXPECT_TRUE(k.rate);
  EXPECT_NEAR(still.end_gap(), -1e-3, 1e-15);  // (48): no relative normal motion
  // The force is the paper's: a residual f n on the slave goes to the
  // facet's nodes as N_b f n (56), with no slip force.
  Eigen::VectorXd g = Eigen::VectorXd::Zero(12), r;
  g(2) = 2.0;
  e.reduce_residual(g, r);
  EXPECT_LT(r.head<3>().norm(), 1e-15);
  const Vec3 N = facet_shape<3>(k.xi);
  for (int b = 0; b < 3; ++b) EXPECT_LT((r.segment<3>(3 * (b + 1)) - 2.0 * N(b) * Vec3::UnitZ()).norm(), 1e-14);

  PushOutCase stretched(0.1);  // 0.1 m of strain and slip against a 1 mm push-out
  Elimination<3> held(stretched.X, stretched.u_n, stretched.u, stretched.constraints, stretched.pairs);
  held.enforce(stretched.u);
  EXPECT_FALSE(stretched.constraints[0].rate);
  EXPECT_NEAR(stretched.end_gap(), 0.0, 1e-15);
}

// A slave found just behind a wall's face, low on it: it projects inside
// the face (its facet, A) and inside the wall's bottom (B, across the
// convex edge, 10 mm behind). Placing it keeps it on A, at its held gap;
// B is a neighbour to move to only at a concave edge (scripts/make_pour.py:
// a sphere's node was moved onto B and held 15 mm "behind" it, inside the
// wall).
TEST(Elimination, ASlaveBehindAFaceIsNotMovedRoundAConvexEdge) {
  Positions<3> X(3, 5);
  X << 1e-4, 0.0, 0.0, 0.0, 0.05,  // node 0 the slave; 1–2 the edge (along y); 3 up the face, 4 under the wall
      0.5, 0.0, 1.0, 0.5, 0.5,     //
      0.01, 0.0, 0.0, 0.05, 0.0;
  std::vector<ContactPair<3>> pairs(1);
  pairs[0].master.facets.resize(3, 2);
  pairs[0].master.facets << 1, 1, 3, 2, 2, 4;  // A = (1, 3, 2) in x = 0, normal −x; B = (1, 2, 4) in z = 0, normal −z
  build_adjacency(pairs[0].master, 3);
  ASSERT_EQ(pairs[0].master.facet_neighbours(1, 0), 1);  // across the edge 1–2
  pairs[0].slave.nodes = {0};
  pairs[0].slave.node_facets = {{}};
  Eigen::VectorXd u_n = Eigen::VectorXd::Zero(15), u = Eigen::VectorXd::Zero(15);
  u_n(0) = -1.1e-3;  // it came from 1 mm in front of A
  Constraint<3> c;
  c.pair = 0;
  c.slave = 0;
  c.kind = Kind::frictionless;
  c.facet = 0;
  c.master = {1, 3, 2};
  c.gap = 0.0;
  std::vector<Constraint<3>> constraints{c};
  Elimination<3> e(X, u_n, u, constraints, pairs);
  e.enforce(u);
  EXPECT_EQ(constraints[0].facet, 0);
  EXPECT_LT((constraints[0].normal - Vec3(-1, 0, 0)).norm(), 1e-12);
  EXPECT_LE(X(0, 0) + u(0), 1e-15);          // not behind A (placed by (48): back where it started)
  EXPECT_NEAR(X(2, 0) + u(2), 0.01, 1e-15);  // not pushed down onto B
}

}  // namespace
}  // namespace conserve::contact
