// Facet kernels: projection exactness, edge/vertex cases, penetration sign,
// and every derivative by the Taylor test (with non-zero guards).
#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <string>

#include "contact/facet.hpp"
#include "support/taylor.hpp"

namespace conserve::contact {
namespace {

template <int D>
FacetNodes<D> random_facet(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  FacetNodes<D> x = FacetNodes<D>::Zero();
  for (int k = 1; k < D; ++k) x(k - 1, k) = 1.0;  // a reference facet in the plane x_D = 0 …
  for (int k = 0; k < D; ++k)
    for (int i = 0; i < D; ++i) x(i, k) += 0.3 * u(rng);  // … distorted and tilted
  return x;
}

template <int D>
Vec<D> random_vec(std::mt19937& rng, double scale) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Vec<D> v;
  for (int i = 0; i < D; ++i) v(i) = scale * u(rng);
  return v;
}

template <int D>
void check_projects_back_exactly() {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double worst_xi = 0.0, worst_gap = 0.0;
  for (int trial = 0; trial < 1000; ++trial) {
    const FacetNodes<D> x = random_facet<D>(rng);
    Xi<D> xi;
    for (int k = 0; k < D - 1; ++k) xi(k) = 1.5 * u(rng) - 0.25;  // also outside the facet
    const double offset = 2.0 * u(rng) - 1.0;                      // both sides: penetration too
    const Vec<D> x_s = x * facet_shape<D>(xi) + offset * facet_normal<D>(x);
    const Projection<D> p = project<D>(x_s, x);
    worst_xi = std::max(worst_xi, (p.xi - xi).norm());
    worst_gap = std::max(worst_gap, std::abs(p.gap - offset));
    ASSERT_EQ(p.gap < 0.0, offset < 0.0);
    ASSERT_EQ(p.inside(), xi.minCoeff() >= 0.0 && xi.sum() <= 1.0);
  }
  std::printf("[ measured ] %dD projection of 1000 random points: |Δξ| ≤ %.1e, |Δg| ≤ %.1e\n", D, worst_xi, worst_gap);
  EXPECT_LT(worst_xi, 1e-12);
  EXPECT_LT(worst_gap, 1e-12);
}

TEST(Facet, ProjectsBackExactly2d) { check_projects_back_exactly<2>(); }
TEST(Facet, ProjectsBackExactly3d) { check_projects_back_exactly<3>(); }

TEST(Facet, NormalIsOutwardConvention) {
  FacetNodes<2> seg;
  seg << 1, 0, 0, 0;  // from (1,0) to (0,0): t = −x, n = (t_y, −t_x) = +y
  EXPECT_LT((facet_normal<2>(seg) - Vec<2>(0, 1)).norm(), 1e-15);
  FacetNodes<3> tri;
  tri << 0, 1, 0, 0, 0, 1, 0, 0, 0;  // counter-clockwise seen from +z
  EXPECT_LT((facet_normal<3>(tri) - Vec<3>(0, 0, 1)).norm(), 1e-15);
}

// The nearest point of the closed facet against dense sampling of it.
template <int D>
void check_closest_point_against_sampling() {
  std::mt19937 rng(9);
  for (int trial = 0; trial < 200; ++trial) {
    const FacetNodes<D> x = random_facet<D>(rng);
    const Vec<D> x_s = x.rowwise().mean() + random_vec<D>(rng, 2.0);
    const auto [xi, dist] = closest_point_on_facet<D>(x_s, x);
    EXPECT_GE(xi.minCoeff(), -1e-14);
    EXPECT_LE(xi.sum(), 1.0 + 1e-14);
    EXPECT_NEAR((x_s - x * facet_shape<D>(xi)).norm(), dist, 1e-12);
    double sampled = 1e300;
    const int n = D == 2 ? 2000 : 150;
    for (int i = 0; i <= n; ++i)
      for (int j = 0; j <= (D == 2 ? 0 : n - i); ++j) {
        Xi<D> s;
        s(0) = double(i) / n;
        if constexpr (D == 3) s(1) = double(j) / n;
        sampled = std::min(sampled, (x_s - x * facet_shape<D>(s)).norm());
      }
    EXPECT_LE(dist, sampled + 1e-12);
    EXPECT_GT(dist, sampled - 0.02);  // the sampling is within ~1/n of the truth
  }
}

TEST(Facet, ClosestPointOnEdgesAndVertices2d) { check_closest_point_against_sampling<2>(); }
TEST(Facet, ClosestPointOnEdgesAndVertices3d) { check_closest_point_against_sampling<3>(); }

TEST(Facet, ClosestPointAtVertexAndEdge) {
  FacetNodes<3> tri;
  tri << 0, 1, 0, 0, 0, 1, 0, 0, 0;
  auto [xi_v, d_v] = closest_point_on_facet<3>(Vec<3>(-1, -1, 0.5), tri);  // beyond vertex 0
  EXPECT_LT(xi_v.norm(), 1e-15);
  EXPECT_NEAR(d_v, std::sqrt(2.25), 1e-14);
  auto [xi_e, d_e] = closest_point_on_facet<3>(Vec<3>(1, 1, 0), tri);  // beyond the hypotenuse
  EXPECT_NEAR(xi_e(0), 0.5, 1e-14);
  EXPECT_NEAR(xi_e(1), 0.5, 1e-14);
  EXPECT_NEAR(d_e, std::sqrt(0.5), 1e-14);
}

/// The Taylor test of f(x_s, x) against its derivative J by y = (x_s, x_0,
/// …) along the direction d of y.
template <int D, int R, class F>
test::TaylorOrder taylor(const Eigen::Matrix<double, R, kPairDofs<D>>& J, const Vec<D>& x_s, const FacetNodes<D>& x,
                         const Eigen::VectorXd& d, double h0, F f) {
  auto at = [&](const Eigen::VectorXd& y) {
    return Eigen::VectorXd(f(Vec<D>(y.head<D>()), FacetNodes<D>(y.tail<D * D>().reshaped(D, D))));
  };
  Eigen::VectorXd y(kPairDofs<D>);
  y << x_s, x.reshaped();
  return test::taylor_order(at, y, d, J * d, h0);
}

// The gap's, ξ's and the normal's derivatives by the Taylor test (a
// remainder of order 2, support/taylor.hpp) along a random direction of
// the slave and facet nodes, for 50 random facets and slaves (the worst
// printed); the tangents, the facet's edge vectors, are linear in
// its nodes: their remainder has no order but is round-off at every step.
template <int D>
void check_derivatives() {
  std::mt19937 rng(13);
  const double h0 = 1e-3;
  test::TaylorOrder worst[4];
  const char* names[4] = {"gap", "projection ξ", "normal", "tangents"};
  for (int trial = 0; trial < 50; ++trial) {
    const FacetNodes<D> x = random_facet<D>(rng);
    const Vec<D> x_s = x.rowwise().mean() + random_vec<D>(rng, 0.7);
    using Row = Eigen::Matrix<double, 1, 1>;
    const auto g = gap_gradient<D>(x_s, x);
    const auto Jxi = xi_gradient<D>(x_s, x);
    const auto Jn = normal_gradient<D>(x);
    const auto Jt = tangents_gradient<D>();
    ASSERT_GT(g.norm(), 0.5);  // non-zero guards
    ASSERT_GT(Jxi.norm(), 0.5);
    ASSERT_GT(Jn.norm(), 0.1);
    ASSERT_GT(Jt.norm(), 0.5);
    const Eigen::VectorXd d = test::random_direction(rng, kPairDofs<D>);
    const test::TaylorOrder t[4] = {
        taylor<D, 1>(g, x_s, x, d, h0, [](const auto& s, const auto& m) { return Row(project<D>(s, m).gap); }),
        taylor<D, D - 1>(Jxi, x_s, x, d, h0, [](const auto& s, const auto& m) { return project<D>(s, m).xi; }),
        taylor<D, D>(Jn, x_s, x, d, h0, [](const auto&, const auto& m) { return facet_normal<D>(m); }),
        taylor<D, D*(D - 1)>(Jt, x_s, x, d, h0, [](const auto&, const auto& m) {
          return Eigen::Matrix<double, D*(D - 1), 1>(facet_tangents<D>(m).reshaped());
        })};
    for (int k = 0; k < 4; ++k) {
      const std::string what = std::string(names[k]) + ", trial " + std::to_string(trial);
      if (k < 3) {
        test::expect_second_order(t[k], what);
      } else {
        test::expect_exact(t[k], what);
      }
      worst[k] = trial == 0 ? t[k] : test::worse(t[k], worst[k]);
    }
  }
  for (int k = 0; k < 4; ++k)
    std::printf("[ measured ] %dD derivative of the %s, 50 random facets, the worst: %s\n", D, names[k],
                test::describe(worst[k]).c_str());
}

TEST(Facet, DerivativesMatchFiniteDifferences2d) { check_derivatives<2>(); }
TEST(Facet, DerivativesMatchFiniteDifferences3d) { check_derivatives<3>(); }

}  // namespace
}  // namespace conserve::contact
