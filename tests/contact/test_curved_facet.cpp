// Quadratic master facets (contact/curved_facet.hpp): the closest-point
// projection by Newton against closed forms (a point placed at distance g
// along the normal of a curved facet projects back onto its foot with gap
// g), the linear facet's projection on a flat one, the Appendix 1
// derivative δξ̄ = H⁻¹[τᵀ(δx_s − Σ N_b δx_b) + (x_s − x̄)·Σ N_b,α δx_b]
// by the Taylor test (and without H's curvature term, a negative control
// that fails), and the Bézier box that holds the facet.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "contact/curved_facet.hpp"
#include "support/taylor.hpp"

namespace conserve::contact {
namespace {

/// A curved facet: the reference simplex's P2 nodes lifted into D
/// dimensions (3D: z = 0.3 x² − 0.2 y² + 0.1 xy, a saddle; 2D: y = 0.4 x²,
/// a parabola; with `cap`, −|ξ − ξ_c|², ξ_c = (1/3, 1/3): a top that is
/// above every node), then scaled by h and moved away from the origin.
template <int D>
typename CurvedFacet<D>::Nodes curved_nodes(double h = 0.5, double bend = 1.0, bool cap = false) {
  using F = CurvedFacet<D>;
  typename F::Nodes x;
  for (int a = 0; a < F::kNodes; ++a) {
    const auto xi = F::Shape::node(a);
    Vec<D> p = Vec<D>::Zero();
    p.template head<D - 1>() = xi;
    if (cap)
      p(D - 1) = -bend * (xi.array() - 1.0 / 3.0).square().sum();
    else if constexpr (D == 3)
      p(2) = bend * (0.3 * xi(0) * xi(0) - 0.2 * xi(1) * xi(1) + 0.1 * xi(0) * xi(1));
    else
      p(1) = bend * 0.4 * xi(0) * xi(0);
    x.col(a) = h * p + Vec<D>::Constant(3.0);
  }
  return x;
}

template <int D>
void check_normal_offsets() {
  using F = CurvedFacet<D>;
  const auto x = curved_nodes<D>();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.1, 0.7);
  double worst_xi = 0.0, worst_gap = 0.0;
  int most_iterations = 0;
  for (int trial = 0; trial < 50; ++trial) {
    Xi<D> xi0;
    for (int k = 0; k < D - 1; ++k) xi0(k) = u(rng);
    if (xi0.sum() > 1.1) xi0 *= 1.1 / xi0.sum();  // inside the facet or a little beyond its border
    const double g = 0.05 * (trial % 2 == 0 ? 1.0 : -1.0) * (1.0 + trial % 3);
    const Vec<D> x_s = F::point(x, xi0) + g * F::normal(x, xi0);
    const CurvedProjection<D> c = project_curved<D>(x_s, x);
    EXPECT_TRUE(c.converged) << trial;
    worst_xi = std::max(worst_xi, (c.projection.xi - xi0).norm());
    worst_gap = std::max(worst_gap, std::abs(c.projection.gap - g));
    most_iterations = std::max(most_iterations, c.iterations);
  }
  std::printf("[ measured ] %dD P2 facet, slaves placed along the normal: |xi - xi0| <= %.1e, |g - g0| <= %.1e m, "
              "<= %d Newton iterations\n",
              D, worst_xi, worst_gap, most_iterations);
  EXPECT_LT(worst_xi, 1e-12);
  EXPECT_LT(worst_gap, 1e-12);
  EXPECT_LE(most_iterations, 10);
}

TEST(CurvedFacet, SlavePlacedAlongTheNormalProjectsOntoItsFoot2d) { check_normal_offsets<2>(); }
TEST(CurvedFacet, SlavePlacedAlongTheNormalProjectsOntoItsFoot3d) { check_normal_offsets<3>(); }

// Slaves far beyond the focal distance (H not positive definite at the
// start) and far to the side: the guarded iteration still ends at a
// stationary point of the distance, r = τᵀ(x_s − x̄) = 0.
template <int D>
void check_far() {
  using F = CurvedFacet<D>;
  const auto x = curved_nodes<D>(0.5, 3.0);
  const Xi<D> centre = Xi<D>::Constant(1.0 / D);
  for (const double g : {-2.0, -8.0, 3.0}) {
    for (const double side : {0.0, 1.5}) {
      const Vec<D> x_s = F::point(x, centre) + g * F::normal(x, centre) + side * F::tangents(x, centre).col(0);
      const CurvedProjection<D> c = project_curved<D>(x_s, x);
      const Xi<D> r = c.projection.tangents.transpose() * (x_s - c.projection.point);
      EXPECT_TRUE(c.converged) << g << " " << side;
      EXPECT_LT(r.norm(), 1e-12 * x_s.norm()) << g << " " << side;
    }
  }
}

TEST(CurvedFacet, FarSlavesEndAtAStationaryPoint) { check_far<2>(), check_far<3>(); }

// Midside nodes at the middle of the edges: the linear facet's projection.
template <int D>
void check_flat() {
  const auto x = curved_nodes<D>(0.5, 0.0);
  const Vec<D> x_s = CurvedFacet<D>::chord(x) * Vec<D>::Constant(1.0 / D) + Vec<D>::Constant(0.1);
  const CurvedProjection<D> c = project_curved<D>(x_s, x);
  const Projection<D> p = project<D>(x_s, CurvedFacet<D>::chord(x));
  EXPECT_TRUE(c.converged);
  EXPECT_LE(c.iterations, 1);
  EXPECT_LT((c.projection.xi - p.xi).norm(), 1e-14);
  EXPECT_NEAR(c.projection.gap, p.gap, 1e-14);
  EXPECT_LT((c.projection.normal - p.normal).norm(), 1e-14);
}

TEST(CurvedFacet, FlatFacetProjectsAsTheLinearOne) { check_flat<2>(), check_flat<3>(); }

// ξ̄(y), y = (x_s, x_0 … x_{NF−1}), against H⁻¹ times the Appendix 1
// right-hand side; with H = τᵀτ (the curvature term dropped) the remainder
// is of order 1.
template <int D>
void check_xi_derivative() {
  using F = CurvedFacet<D>;
  constexpr int n = D * (F::kNodes + 1);
  const auto x = curved_nodes<D>();
  Xi<D> xi0 = Xi<D>::Constant(0.3);
  const Vec<D> x_s = F::point(x, xi0) + 0.2 * F::normal(x, xi0);
  const auto split = [&](const Eigen::VectorXd& y, Vec<D>& s, typename F::Nodes& m) {
    s = x_s + y.template head<D>();
    m = x + Eigen::Map<const typename F::Nodes>(y.data() + D);
  };
  const auto xi_of = [&](const Eigen::VectorXd& y) {
    Vec<D> s;
    typename F::Nodes m;
    split(y, s, m);
    return Eigen::VectorXd(project_curved<D>(s, m).projection.xi);
  };
  std::mt19937 rng(9);
  const Eigen::VectorXd dir = test::random_direction(rng, n);
  const CurvedProjection<D> c = project_curved<D>(x_s, x);
  const Xi<D>& xi = c.projection.xi;
  const auto N = F::Shape::shape(xi);
  const auto dN = F::Shape::dshape(xi);
  const Tangents<D> t = c.projection.tangents;
  const Vec<D> d = x_s - c.projection.point;
  Vec<D> dx_bar = Vec<D>::Zero();  // Σ N_b δx_b
  Tangents<D> dtau = Tangents<D>::Zero();  // Σ N_b,α δx_b
  for (int b = 0; b < F::kNodes; ++b) {
    dx_bar += N(b) * dir.template segment<D>(D * (b + 1));
    dtau += dir.template segment<D>(D * (b + 1)) * dN.col(b).transpose();
  }
  const Xi<D> rhs = t.transpose() * (dir.template head<D>() - dx_bar) + dtau.transpose() * d;
  const Eigen::VectorXd with_curvature = F::hessian(x_s, x, xi).inverse() * rhs;
  const Eigen::VectorXd without = (t.transpose() * t).inverse() * rhs;
  const test::TaylorOrder full = test::taylor_order(xi_of, Eigen::VectorXd::Zero(n), dir, with_curvature, 1e-2);
  const test::TaylorOrder flat = test::taylor_order(xi_of, Eigen::VectorXd::Zero(n), dir, without, 1e-2);
  std::printf("[ measured ] %dD dxi/dy with H's curvature term: %s; without: %s\n", D, test::describe(full).c_str(),
              test::describe(flat).c_str());
  test::expect_second_order(full, "dxi/dy");
  EXPECT_LT(flat.order, 1.2) << "the curvature term should matter: " << test::describe(flat);
}

TEST(CurvedFacet, XiDerivativeIsAppendixOnesWithTheCurvatureTerm) { check_xi_derivative<2>(), check_xi_derivative<3>(); }

// Every point of the facet lies in its Bézier box, which the nodes' own box
// does not hold (the cap's top is above every node).
template <int D>
void check_box() {
  using F = CurvedFacet<D>;
  const auto x = curved_nodes<D>(1.0, 2.0, true);
  const auto [lo, hi] = F::box(x);
  Vec<D> node_hi = x.rowwise().maxCoeff(), node_lo = x.rowwise().minCoeff();
  bool outside_node_box = false;
  for (int i = 0; i <= 20; ++i)
    for (int j = 0; j <= (D == 3 ? 20 - i : 0); ++j) {
      Xi<D> xi;
      xi(0) = i / 20.0;
      if constexpr (D == 3) xi(1) = j / 20.0;
      const Vec<D> p = F::point(x, xi);
      EXPECT_TRUE((p.array() >= lo.array() - 1e-14).all() && (p.array() <= hi.array() + 1e-14).all());
      outside_node_box |= (p.array() > node_hi.array() + 1e-6).any() || (p.array() < node_lo.array() - 1e-6).any();
    }
  EXPECT_TRUE(outside_node_box);  // the test can fail: the nodes' box would not do
}

TEST(CurvedFacet, BezierBoxHoldsTheFacet) { check_box<2>(), check_box<3>(); }

}  // namespace
}  // namespace conserve::contact
