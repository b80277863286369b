// Quadratic simplices: the Lagrange basis, the quadrature rules, and the
// 6-node triangle / 10-node tetrahedron kernels of the conserving step.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <string>

#include "fem/element.hpp"
#include "fem/facet_integrals.hpp"
#include "fem/lagrange.hpp"
#include "fem/quadratic.hpp"
#include "fem/quadrature.hpp"
#include "material/law_cases.hpp"
#include "material/svk_law.hpp"
#include "support/random_cell.hpp"
#include "support/taylor.hpp"

namespace conserve::fem {
namespace {

template <int K, int P>
void check_basis() {
  using L = Lagrange<K, P>;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 0.4);
  for (int a = 0; a < L::kNodes; ++a) {  // Kronecker delta at the nodes
    const auto N = L::shape(L::node(a));
    for (int b = 0; b < L::kNodes; ++b) EXPECT_NEAR(N(b), a == b ? 1.0 : 0.0, 1e-15) << a << " " << b;
  }
  for (int trial = 0; trial < 10; ++trial) {
    Vec<K> xi;
    for (int i = 0; i < K; ++i) xi(i) = u(rng);
    EXPECT_NEAR(L::shape(xi).sum(), 1.0, 1e-15);
    EXPECT_LT(L::dshape(xi).rowwise().sum().norm(), 1e-14);
    // Derivatives against central differences (exact for quadratics up to round-off).
    const double h = 1e-4;
    const auto G = L::dshape(xi);
    const auto H = L::d2shape(xi);
    for (int i = 0; i < K; ++i) {
      const Vec<K> e = h * Vec<K>::Unit(i);
      const typename L::Values dN = (L::shape(xi + e) - L::shape(xi - e)) / (2 * h);
      EXPECT_LT((dN - G.row(i).transpose()).norm(), 1e-9);
      const typename L::Gradients dG = (L::dshape(xi + e) - L::dshape(xi - e)) / (2 * h);
      for (int a = 0; a < L::kNodes; ++a) EXPECT_LT((dG.col(a) - H[a].col(i)).norm(), 1e-8) << a;
    }
    // Quadratic fields are reproduced: x(ξ) = Σ N_a x(ξ_a) for x = ξ_0² + ξ_0 ξ_K.
    if constexpr (P == 2) {
      const auto field = [](const Vec<K>& p) { return p(0) * p(0) + p(0) * p(K - 1) - 0.5 * p(K - 1); };
      double interpolated = 0.0;
      for (int a = 0; a < L::kNodes; ++a) interpolated += L::shape(xi)(a) * field(L::node(a));
      EXPECT_NEAR(interpolated, field(xi), 1e-14);
    }
  }
}

TEST(Lagrange, BasisLine) { check_basis<1, 1>(), check_basis<1, 2>(); }
TEST(Lagrange, BasisTriangle) { check_basis<2, 1>(), check_basis<2, 2>(); }
TEST(Lagrange, BasisTetrahedron) { check_basis<3, 1>(), check_basis<3, 2>(); }

TEST(Lagrange, GmshEdgeOrder) {
  // tet10: 4=(0,1) 5=(1,2) 6=(2,0) 7=(3,0) 8=(3,2) 9=(3,1).
  using L = Lagrange<3, 2>;
  EXPECT_LT((L::node(8) - Vec3(0.0, 0.5, 0.5)).norm(), 1e-15);
  EXPECT_LT((L::node(9) - Vec3(0.5, 0.0, 0.5)).norm(), 1e-15);
  EXPECT_LT((L::node(7) - Vec3(0.0, 0.0, 0.5)).norm(), 1e-15);
  EXPECT_LT((Lagrange<2, 2>::node(4) - Vec<2>(0.5, 0.5)).norm(), 1e-15);
}

// ∫ ξ^a η^b ζ^c over the reference simplex = a! b! c! / (a + b + c + K)!.
double factorial(int n) { return n <= 1 ? 1.0 : n * factorial(n - 1); }

template <int K, int Degree>
void check_rule() {
  const auto q = quadrature<K, Degree>();
  int checked = 0;
  for (int a = 0; a <= Degree; ++a)
    for (int b = 0; b <= (K > 1 ? Degree - a : 0); ++b)
      for (int c = 0; c <= (K > 2 ? Degree - a - b : 0); ++c) {
        const int e[3] = {a, b, c};
        double sum = 0.0;
        for (int p = 0; p < q.kPoints; ++p) {
          double m = q.weights[p];
          for (int i = 0; i < K; ++i) m *= std::pow(q.points[p](i), e[i]);
          sum += m;
        }
        const double exact = factorial(a) * factorial(b) * factorial(c) / factorial(a + b + c + K);
        EXPECT_NEAR(sum, exact, 1e-16) << "K " << K << " degree " << Degree << " monomial " << a << b << c;
        ++checked;
        for (const double w : q.weights) EXPECT_GT(w, 0.0);
      }
  EXPECT_GT(checked, Degree);
}

TEST(Quadrature, ExactToItsDegree) {
  check_rule<1, 3>(), check_rule<1, 5>();
  check_rule<2, 1>(), check_rule<2, 2>(), check_rule<2, 4>();
  check_rule<3, 1>(), check_rule<3, 2>(), check_rule<3, 5>();
}

TEST(Quadrature, NotExactBeyondItsDegree) {  // the check above can fail
  const auto q = quadrature<3, 2>();
  double sum = 0.0;
  for (int p = 0; p < q.kPoints; ++p) sum += q.weights[p] * std::pow(q.points[p](0), 4);
  EXPECT_GT(std::abs(sum - factorial(4) / factorial(7)), 1e-6);
}

// A curved quadratic cell: a random linear simplex with its midside nodes
// moved off the edges' middles by `bulge` × size.
template <int D>
QuadraticNodes<D> random_quadratic_cell(std::mt19937& rng, double size, double bulge) {
  using L = Lagrange<D, 2>;
  const NodeMatrix<D> V = test::random_reference_cell<D>(rng, size);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  QuadraticNodes<D> X;
  X.template leftCols<D + 1>() = V;
  int e = D + 1;
  for (const auto& [a, b] : L::edges()) {
    X.col(e) = 0.5 * (V.col(a) + V.col(b));
    for (int i = 0; i < D; ++i) X(i, e) += bulge * size * u(rng);
    ++e;
  }
  return X;
}

template <int D>
QuadraticNodes<D> random_deformed(std::mt19937& rng, const QuadraticNodes<D>& X, double noise) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Mat<D> F = Mat<D>::Identity();
  for (int i = 0; i < D; ++i)
    for (int j = 0; j < D; ++j) F(i, j) += 0.3 * u(rng);
  QuadraticNodes<D> x = F * X;
  for (int a = 0; a < x.cols(); ++a)
    for (int i = 0; i < D; ++i) x(i, a) += noise * u(rng);
  return x;
}

template <int D>
struct Step {
  QuadraticGeometry<D> g;
  QuadraticNodes<D> x_n, x_np1;
  std::array<CellStart<D>, Quadratic<D>::kPoints> start;
};

template <int D>
Step<D> random_step(std::mt19937& rng, double size) {
  const QuadraticNodes<D> X = random_quadratic_cell<D>(rng, size, 0.05);
  Step<D> s{quadratic_geometry<D>(X, 1.0),
            random_deformed<D>(rng, X, 0.05 * size),
            random_deformed<D>(rng, X, 0.05 * size),
            {}};
  EXPECT_GT(min_jacobian<D>(X), 0.0);
  cell_start<D>(s.g, s.x_n, s.start.data());
  return s;
}

const material::Svk kSvk(material::Lame::from_young_poisson(1.0e4, 0.3));

/// The pointwise kernels, or the mean-dilatation ones (`mean`).
template <int D>
QuadraticNodes<D> force_of(bool mean, const Step<D>& s, const material::Law& law, const QuadraticNodes<D>& x,
                           StressScheme scheme) {
  return mean ? internal_force_mean_dilatation<D>(s.g, law, s.start.data(), x, scheme)
              : internal_force<D>(s.g, law, s.start.data(), x, scheme);
}
template <int D>
double energy_of(bool mean, const Step<D>& s, const material::Law& law, const QuadraticNodes<D>& x) {
  return mean ? strain_energy_mean_dilatation<D>(s.g, law, x) : strain_energy<D>(s.g, law, x);
}

template <int D>
void check_tangent(StressScheme scheme, const material::Law& law, const std::string& name, bool mean = false) {
  constexpr int N = D * Quadratic<D>::kNodes;
  std::mt19937 rng(11);
  test::TaylorOrder worst;
  for (int trial = 0; trial < 10; ++trial) {
    const Step<D> s = random_step<D>(rng, 0.1);
    QuadraticNodes<D> f;
    QuadraticMatrix<D> K;
    if (mean)
      internal_force_tangent_mean_dilatation<D>(s.g, law, s.start.data(), s.x_np1, scheme, f, K);
    else
      internal_force_tangent<D>(s.g, law, s.start.data(), s.x_np1, scheme, f, K);
    ASSERT_GT(K.norm(), 1.0);  // non-zero guard
    EXPECT_LT((f - force_of<D>(mean, s, law, s.x_np1, scheme)).norm(), 1e-12 * f.norm());
    auto force = [&](const Eigen::VectorXd& x) {
      return Eigen::VectorXd(force_of<D>(mean, s, law, QuadraticNodes<D>(x.reshaped(D, N / D)), scheme).reshaped());
    };
    const Eigen::VectorXd d = test::random_direction(rng, N);
    const test::TaylorOrder t = test::taylor_order(force, s.x_np1.reshaped(), d, K * d, 1e-3 * 0.1);
    test::expect_second_order(t, name + " trial " + std::to_string(trial));
    worst = trial == 0 ? t : test::worse(t, worst);
  }
  std::printf("[ measured ] quadratic element tangent (%s, %dD, %s%s), 10 curved cells: worst %s\n", name.c_str(), D,
              scheme == StressScheme::conserving ? "conserving" : "midpoint", mean ? ", mean dilatation" : "",
              test::describe(worst).c_str());
}

TEST(QuadraticElement, TangentEveryLaw) {
  for (StressScheme scheme : {StressScheme::conserving, StressScheme::midpoint}) {
    check_tangent<2>(scheme, kSvk, "svk");
    check_tangent<3>(scheme, kSvk, "svk");
    for (const auto& c : material::test::law_cases()) {
      const auto law = material::test::make(c);
      check_tangent<2>(scheme, *law, c.model);
      check_tangent<3>(scheme, *law, c.model);
    }
  }
}

// Paper (25)–(26) on curved quadratic cells: Σ f_A = 0, Σ x_{A,n+½} × f_A = 0
// and, conserving only, Σ f_A·Δx_A = W_{n+1} − W_n.
template <int D>
double energy_identity_error(StressScheme scheme, const material::Law& law, const std::string& name,
                             bool mean = false) {
  std::mt19937 rng(5);
  double worst = 0.0;
  for (int trial = 0; trial < 30; ++trial) {
    const Step<D> s = random_step<D>(rng, 1.0);
    const QuadraticNodes<D> f = force_of<D>(mean, s, law, s.x_np1, scheme);
    const double W1 = energy_of<D>(mean, s, law, s.x_np1), W0 = energy_of<D>(mean, s, law, s.x_n);
    const double work = (f.array() * (s.x_np1 - s.x_n).array()).sum();
    worst = std::max(worst, std::abs(work - (W1 - W0)) / (W1 + W0));
    EXPECT_LT(f.rowwise().sum().norm(), 1e-12 * f.norm());
    const QuadraticNodes<D> x_mid = 0.5 * (s.x_n + s.x_np1);
    double moment = 0.0;
    if constexpr (D == 2) {
      for (int a = 0; a < f.cols(); ++a) moment += x_mid(0, a) * f(1, a) - x_mid(1, a) * f(0, a);
    } else {
      Vec3 m = Vec3::Zero();
      for (int a = 0; a < f.cols(); ++a) m += Vec3(x_mid.col(a)).cross(Vec3(f.col(a)));
      moment = m.norm();
    }
    EXPECT_LT(std::abs(moment), 1e-12 * f.norm() * x_mid.norm());
  }
  std::printf("[ measured ] quadratic: max |Σf·Δx − ΔW| / W (%s, %dD, %s%s): %.3e\n", name.c_str(), D,
              scheme == StressScheme::conserving ? "conserving" : "midpoint", mean ? ", mean dilatation" : "", worst);
  return worst;
}

TEST(QuadraticElement, ConservingEnergyIsExactForEveryLaw) {
  EXPECT_LT(energy_identity_error<2>(StressScheme::conserving, kSvk, "svk"), 1e-12);
  EXPECT_LT(energy_identity_error<3>(StressScheme::conserving, kSvk, "svk"), 1e-12);
  EXPECT_GT(energy_identity_error<3>(StressScheme::midpoint, kSvk, "svk"), 1e-3);  // negative control
  for (const auto& c : material::test::law_cases()) {
    const auto law = material::test::make(c);
    EXPECT_LT(energy_identity_error<2>(StressScheme::conserving, *law, c.model), 1e-12) << c.model;
    EXPECT_LT(energy_identity_error<3>(StressScheme::conserving, *law, c.model), 1e-12) << c.model;
    EXPECT_GT(energy_identity_error<2>(StressScheme::midpoint, *law, c.model), 1e-3) << c.model;
  }
}

// The mean-dilatation kernels (fem/mean_dilatation.hpp): the tangent's
// remainder of order 2, the conserving work exact, the momenta kept, for
// every law including SVK (through its point law, not Simo–Tarnow).
TEST(QuadraticElement, MeanDilatationTangentEveryLaw) {
  for (StressScheme scheme : {StressScheme::conserving, StressScheme::midpoint}) {
    check_tangent<2>(scheme, kSvk, "svk", true);
    check_tangent<3>(scheme, kSvk, "svk", true);
    for (const double nu : {0.3, 0.4999})
      for (const auto& c : material::test::law_cases(1.0e6, nu)) {
        const auto law = material::test::make(c);
        check_tangent<2>(scheme, *law, c.model, true);
        check_tangent<3>(scheme, *law, c.model, true);
      }
  }
}

TEST(QuadraticElement, MeanDilatationEnergyIsExactForEveryLaw) {
  EXPECT_LT(energy_identity_error<2>(StressScheme::conserving, kSvk, "svk", true), 1e-12);
  EXPECT_LT(energy_identity_error<3>(StressScheme::conserving, kSvk, "svk", true), 1e-12);
  for (const double nu : {0.3, 0.4999})
    for (const auto& c : material::test::law_cases(1.0e6, nu)) {
      const auto law = material::test::make(c);
      EXPECT_LT(energy_identity_error<2>(StressScheme::conserving, *law, c.model, true), 1e-12) << c.model;
      EXPECT_LT(energy_identity_error<3>(StressScheme::conserving, *law, c.model, true), 1e-12) << c.model;
      EXPECT_GT(energy_identity_error<3>(StressScheme::midpoint, *law, c.model, true), 1e-3) << c.model;
    }
}

// A straight-sided quadratic cell (midside nodes at the middles) is the
// linear cell for affine motions: the same volume, F and energy.
template <int D>
void check_affine_patch() {
  std::mt19937 rng(3);
  const NodeMatrix<D> V = test::random_reference_cell<D>(rng, 2.0);
  QuadraticNodes<D> X;
  X.template leftCols<D + 1>() = V;
  int e = D + 1;
  for (const auto& [a, b] : Lagrange<D, 2>::edges()) X.col(e++) = 0.5 * (V.col(a) + V.col(b));
  const QuadraticGeometry<D> g = quadratic_geometry<D>(X, 1.0);
  const SimplexGeometry<D> g1 = simplex_geometry<D>(V, 1.0);
  EXPECT_NEAR(g.volume, g1.volume, 1e-14 * g1.volume);
  Mat<D> A = Mat<D>::Identity();
  A(0, D - 1) = 0.3, A(D - 1, 0) = -0.2, A(1, 1) = 1.1;
  std::array<CellStart<D>, Quadratic<D>::kPoints> start;
  cell_start<D>(g, QuadraticNodes<D>(A * X), start.data());
  for (const auto& s : start) EXPECT_LT((s.F - A).norm(), 1e-13);
  EXPECT_NEAR(strain_energy<D>(g, kSvk, A * X), strain_energy<D>(g1, kSvk, A * V),
              1e-12 * strain_energy<D>(g1, kSvk, A * V));
  // Σ f over the cell's nodes for a uniform stress: the P1 force on the
  // vertices, spread by the quadratic basis, sums to the same resultant
  // per direction and is zero in total.
  const QuadraticNodes<D> f = internal_force<D>(g, kSvk, start.data(), A * X, StressScheme::conserving);
  EXPECT_LT(f.rowwise().sum().norm(), 1e-12 * f.norm());
}

TEST(QuadraticElement, StraightCellUnderAffineMotionIsTheLinearCell) {
  check_affine_patch<2>();
  check_affine_patch<3>();
}

template <int D>
void check_mass() {
  std::mt19937 rng(9);
  const QuadraticNodes<D> X = random_quadratic_cell<D>(rng, 1.0, 0.0);
  const double V = quadratic_geometry<D>(X, 1.0).volume;
  const auto M = quadratic_mass<D>(X, 2.0, false);
  EXPECT_NEAR(M.sum(), 2.0 * V, 1e-13);
  EXPECT_LT((M - M.transpose()).norm(), 1e-15);
  EXPECT_GT(M.ldlt().vectorD().minCoeff(), 0.0);  // positive definite
  // First moment: Σ_AB M_AB X_B = ρ ∫ X dV = ρ V × the vertex centroid.
  const Vec<D> moment = X * M.rowwise().sum();
  EXPECT_LT((moment - 2.0 * V * X.template leftCols<D + 1>().rowwise().mean()).norm(), 1e-13);
  const auto rows = M.rowwise().sum();
  for (int a = 0; a <= D; ++a) EXPECT_LT(rows(a), 1e-12) << "row sum at a vertex";  // why row sums are not a lumping
  const auto L = quadratic_mass<D>(X, 2.0, true);
  EXPECT_NEAR(L.sum(), 2.0 * V, 1e-13);
  EXPECT_GT(L.diagonal().minCoeff(), 0.0);
  EXPECT_EQ((L - Eigen::Matrix<double, Quadratic<D>::kNodes, Quadratic<D>::kNodes>(L.diagonal().asDiagonal())).norm(),
            0.0);
}

TEST(QuadraticElement, ConsistentAndLumpedMass) {
  check_mass<2>();
  check_mass<3>();
}

TEST(QuadraticElement, FoldedMidsideNodeIsNotPositive) {
  std::mt19937 rng(2);
  QuadraticNodes<3> X = random_quadratic_cell<3>(rng, 1.0, 0.0);
  EXPECT_GT(min_jacobian<3>(X), 0.0);
  X.col(4) = X.col(0) + 0.1 * (X.col(1) - X.col(0));  // node 4 of edge (0, 1) pushed near vertex 0
  EXPECT_LT(min_jacobian<3>(X), 0.0);
}

// Surface-load shares on flat / straight quadratic facets in closed form
// (tri6: 0 at the vertices, A/3 at the midsides; line3: 1/6, 1/6, 2/3 of
// the length), the same area vector as the linear facet, and a P1 facet's
// equal shares A/D.
TEST(FacetIntegrals, SharesOfStraightFacetsInClosedForm) {
  Eigen::Matrix<double, 3, 6> tri;
  tri.leftCols<3>() << 0.0, 2.0, 0.5, 0.0, 0.0, 1.5, 0.3, 0.3, 0.3;
  for (int e = 0; e < 3; ++e) {
    const auto [a, b] = Lagrange<2, 2>::edges()[static_cast<std::size_t>(e)];
    tri.col(3 + e) = 0.5 * (tri.col(a) + tri.col(b));
  }
  const Vec3 area = 0.5 * Vec3(tri.col(1) - tri.col(0)).cross(Vec3(tri.col(2) - tri.col(0)));
  const auto s6 = FacetIntegrals<3, 2>::area_shares(tri, 1.0);
  const auto m6 = FacetIntegrals<3, 2>::measure_shares(tri, 1.0);
  const auto s3 = FacetIntegrals<3, 1>::area_shares(tri.leftCols<3>(), 1.0);
  for (int a = 0; a < 6; ++a) {
    const double expected = a < 3 ? 0.0 : 1.0 / 3.0;
    EXPECT_LT((s6.col(a) - expected * area).norm(), 1e-13 * area.norm()) << a;
    EXPECT_NEAR(m6(a), expected * area.norm(), 1e-13 * area.norm()) << a;
  }
  for (int a = 0; a < 3; ++a) EXPECT_LT((s3.col(a) - area / 3.0).norm(), 1e-13 * area.norm());
  Eigen::Matrix<double, 2, 3> line;
  line << 0.0, 3.0, 1.5, 0.0, 4.0, 2.0;  // length 5
  const double t = 0.2;
  const auto s = FacetIntegrals<2, 2>::area_shares(line, t);
  const auto m = FacetIntegrals<2, 2>::measure_shares(line, t);
  const Vec<2> outward = t * Vec<2>(4.0, -3.0);  // t (y_ξ, −x_ξ)
  const Vec3 fraction(1.0 / 6.0, 1.0 / 6.0, 2.0 / 3.0);
  for (int a = 0; a < 3; ++a) {
    EXPECT_LT((s.col(a) - fraction(a) * outward).norm(), 1e-13 * outward.norm()) << a;
    EXPECT_NEAR(m(a), fraction(a) * 5.0 * t, 1e-13) << a;
  }
}

// ∂s_a/∂x_b by the Taylor test on curved facets of either order and
// dimension (3D: the remainder of order 2; 2D: s is linear in x, the
// remainder round-off), with a guard that the derivative is not zero.
template <int D, int P>
void check_share_derivative() {
  using I = FacetIntegrals<D, P>;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-0.1, 0.1);
  typename I::Nodes x;
  for (int a = 0; a < I::kNodes; ++a) {
    const auto xi = I::Shape::node(a);
    x.col(a).setZero();
    x.col(a).template head<D - 1>() = xi;
    for (int i = 0; i < D; ++i) x(i, a) += u(rng);
  }
  const auto d = I::area_share_derivatives(x, 0.7);
  Eigen::Matrix<double, D * I::kNodes, 1> dir;
  for (int i = 0; i < dir.size(); ++i) dir(i) = u(rng);
  const auto value = [&](const Eigen::VectorXd& y) {
    const typename I::Nodes xn = x + Eigen::Map<const typename I::Nodes>(y.data());
    return Eigen::VectorXd(I::area_shares(xn, 0.7).reshaped());
  };
  Eigen::VectorXd slope = Eigen::VectorXd::Zero(D * I::kNodes);
  for (int a = 0; a < I::kNodes; ++a)
    for (int b = 0; b < I::kNodes; ++b)
      slope.segment<D>(D * a) += d[static_cast<std::size_t>(a * I::kNodes + b)] * dir.template segment<D>(D * b);
  EXPECT_GT(slope.norm(), 1e-3);
  const test::TaylorOrder t =
      test::taylor_order(value, Eigen::VectorXd::Zero(D * I::kNodes), Eigen::VectorXd(dir), slope, 1e-1);
  std::printf("[ measured ] facet area shares %dD P%d: %s\n", D, P, test::describe(t).c_str());
  if constexpr (D == 2)
    test::expect_exact(t, "area shares");  // linear in x: the remainder is round-off
  else
    test::expect_second_order(t, "area shares");
}

TEST(FacetIntegrals, AreaShareDerivativeMatchesDifferences) {
  check_share_derivative<2, 1>(), check_share_derivative<2, 2>();
  check_share_derivative<3, 1>(), check_share_derivative<3, 2>();
}

}  // namespace
}  // namespace conserve::fem
