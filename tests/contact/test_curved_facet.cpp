// Quadratic master facets (contact/curved_facet.hpp): the closest-point
// projection by Newton against closed forms (a point placed at distance g
// along the normal of a curved facet projects back onto its foot with gap
// g), the linear facet's projection on a flat one, the Appendix 1
// derivative δξ̄ = H⁻¹[τᵀ(δx_s − Σ N_b δx_b) + (x_s − x̄)·Σ N_b,α δx_b]
// by the Taylor test (and without H's curvature term, a negative control
// that fails), the Bézier box that holds the facet, and the zero-work
// kernels on curved masters: no work, resultant or moment, and their
// automatic derivatives through the one-step projection exact.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <type_traits>

#include "contact/curved_facet.hpp"
#include "contact/elimination/zero_work.hpp"
#include "support/taylor.hpp"

#include <unsupported/Eigen/AutoDiff>

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

template <int N>
using AD = Eigen::AutoDiffScalar<Eigen::Matrix<double, N, 1>>;

/// x as AD variables (entry k has derivative e_k), plus `shift`.
template <int N, int R, int C>
Eigen::Matrix<AD<N>, R, C> ad_variables(const Eigen::Matrix<double, R, C>& x) {
  Eigen::Matrix<AD<N>, R, C> y;
  for (int k = 0; k < R * C; ++k) y(k) = AD<N>(x(k), N, k);
  return y;
}

/// A slave 0.05 above a curved facet and a general step (every node moves,
/// not rigidly): (slave, facet nodes) at the step's start and its
/// displacements.
template <int D>
std::pair<zero_work::Nodes<D, double, CurvedFacet<D>::kNodes>, zero_work::Nodes<D, double, CurvedFacet<D>::kNodes>>
curved_step() {
  using F = CurvedFacet<D>;
  zero_work::Nodes<D, double, F::kNodes> x_n, dx;
  const auto m = curved_nodes<D>();
  const Xi<D> xi = Xi<D>::Constant(0.3);
  x_n.col(0) = F::point(m, xi) + 0.05 * F::normal(m, xi);
  x_n.template rightCols<F::kNodes>() = m;
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < dx.size(); ++k) dx(k) = 2e-3 * u(rng);
  return {x_n, dx};
}

/// ā on a curved master does no work over the step, has no resultant and
/// no moment about the mid-point configuration; the paper's a does work
/// (the control), and the mid-point projection is project_curved's.
template <int D>
void check_curved_zero_work() {
  constexpr int NF = CurvedFacet<D>::kNodes;
  const auto [x_n, dx] = curved_step<D>();
  const zero_work::Nodes<D, double, NF> x = x_n + dx, y = x - 0.5 * dx;
  zero_work::Plane<D, double, NF> mid;
  const auto abar = zero_work::frictionless_direction<D, double, NF>(x, dx, mid);
  const auto a = zero_work::frictionless_direction<D, double, NF>(x, dx, mid, false);
  const double scale = abar.norm() * dx.norm();
  const double work = abar.cwiseProduct(dx).sum();
  double moment = 0.0;
  if constexpr (D == 3) {
    Vec<3> j = Vec<3>::Zero();
    for (int b = 0; b <= NF; ++b) j += Vec<3>(y.col(b)).cross(Vec<3>(abar.col(b)));
    moment = j.norm();
  } else {
    for (int b = 0; b <= NF; ++b) moment += y(0, b) * abar(1, b) - y(1, b) * abar(0, b);
  }
  const CurvedProjection<D> c = project_curved<D>(y.col(0), y.template rightCols<NF>());
  std::printf("[ measured ] %dD curved master: |ā·Δx| %.1e (a·Δx %.1e), |Σā| %.1e, |Σ y×ā| %.1e\n", D,
              std::abs(work), std::abs(a.cwiseProduct(dx).sum()), abar.rowwise().sum().norm(), std::abs(moment));
  EXPECT_LT(std::abs(work), 1e-14 * scale);
  EXPECT_GT(std::abs(a.cwiseProduct(dx).sum()), 1e-3 * scale);
  EXPECT_LT(abar.rowwise().sum().norm(), 1e-14 * abar.norm());
  EXPECT_LT(std::abs(moment), 1e-14 * abar.norm() * y.norm());
  EXPECT_LT((mid.xi - c.projection.xi).norm(), 1e-14);
  EXPECT_NEAR(mid.gap, c.projection.gap, 1e-15);
  EXPECT_LT((mid.shape - CurvedFacet<D>::Shape::shape(c.projection.xi)).norm(), 1e-14);
}

TEST(CurvedFacet, ZeroWorkDirectionDoesNoWorkAndHasNoResultantOrMoment) {
  check_curved_zero_work<2>();
  check_curved_zero_work<3>();
}

/// Two constraints on one slave, on two curved facets (a notch): with the
/// nodes' residual g = f_1 ā_1 + f_2 ā_2 (each constraint's zero-work
/// direction) the pair's test columns and slip row leave nothing (Wᵀg = 0),
/// so the pair's forces do no work and have no resultant or moment.
template <int D>
void check_curved_pair() {
  constexpr int NF = CurvedFacet<D>::kNodes;
  const auto [x_n, dx1] = curved_step<D>();
  Mat<D> turn = Mat<D>::Identity();  // facet 2: facet 1 turned by 0.5 rad about the slave
  turn.template topLeftCorner<2, 2>() << std::cos(0.5), -std::sin(0.5), std::sin(0.5), std::cos(0.5);
  zero_work::PairNodes<D, double, NF> x, dx;
  x.col(0) = x_n.col(0) + dx1.col(0);
  dx.col(0) = dx1.col(0);
  for (int b = 0; b < NF; ++b) {
    x.col(1 + b) = x_n.col(1 + b) + dx1.col(1 + b);
    dx.col(1 + b) = dx1.col(1 + b);
    x.col(1 + NF + b) = x_n.col(0) + turn * (x_n.col(1 + b) - x_n.col(0)) + dx1.col(1 + b).reverse();
    dx.col(1 + NF + b) = dx1.col(1 + b).reverse();
  }
  const auto t = zero_work::pair_frictionless_test<D, double, NF>(x, dx);
  std::array<zero_work::Nodes<D, double, NF>, 2> abar;
  for (int k = 0; k < 2; ++k) {
    zero_work::Nodes<D, double, NF> xk, dxk;
    xk.col(0) = x.col(0);
    dxk.col(0) = dx.col(0);
    xk.template rightCols<NF>() = x.template middleCols<NF>(1 + k * NF);
    dxk.template rightCols<NF>() = dx.template middleCols<NF>(1 + k * NF);
    zero_work::Plane<D, double, NF> mid;
    abar[k] = zero_work::frictionless_direction<D, double, NF>(xk, dxk, mid);
    EXPECT_LT(std::abs(abar[k].cwiseProduct(dxk).sum()), 1e-14 * abar[k].norm() * dxk.norm());
  }
  const double f[2] = {1.3, -0.7};
  const Vec<D> g_s = f[0] * abar[0].col(0) + f[1] * abar[1].col(0);
  double left = std::abs(t.slip.dot(g_s));
  for (int k = 0; k < 2; ++k)
    for (int b = 0; b < NF; ++b)
      for (int i = 0; i < D; ++i)
        left = std::max(left, std::abs(f[k] * abar[k](i, b + 1) + t.master.col((k * NF + b) * D + i).dot(g_s)));
  const double scale = std::abs(f[0]) * abar[0].norm() + std::abs(f[1]) * abar[1].norm();
  std::printf("[ measured ] %dD pair on curved facets: |W^T g| %.1e of |g| %.1e\n", D, left, scale);
  EXPECT_LT(left, 1e-12 * scale);
  EXPECT_GT(t.master.norm(), 0.1);  // not a zero map
}

TEST(CurvedFacet, PairTestColumnsLeaveNothingOfTheTwoZeroWorkForces) {
  check_curved_pair<2>();
  check_curved_pair<3>();
}

/// The derivative of the one-step projection (project_on_curved: ξ, n, g,
/// N) by automatic differentiation is exact (Taylor order 2); without H's
/// curvature term it is not (order 1), and neither are then the test
/// columns of the frictionless kernel, whose own derivative (ā's turn,
/// the shape weights') is exact with it.
template <int D>
void check_curved_kernel_derivatives() {
  constexpr int NF = CurvedFacet<D>::kNodes;
  constexpr int N = D * (NF + 1);
  using Nodes = zero_work::Nodes<D, double, NF>;
  const auto [x_n, dx0] = curved_step<D>();
  const Nodes x0 = x_n + dx0;
  std::mt19937 rng(4);
  const Eigen::VectorXd dir = test::random_direction(rng, N);
  const auto projected = [&](const auto& p) {
    Eigen::VectorXd out(D - 1 + D + 1 + NF);
    out << p.xi, p.normal, p.gap, p.shape;
    return out;
  };
  const auto projection_of = [&](const Eigen::VectorXd& v) {
    const Nodes x = x0 + Eigen::Map<const Nodes>(v.data());
    return projected(zero_work::project_on_curved<D, double, NF>(x.col(0), x.template rightCols<NF>()));
  };
  const auto ad_slope = [&](bool curvature) {
    const Eigen::Matrix<AD<N>, D, NF + 1> X = ad_variables<N>(x0);
    const auto p = zero_work::project_on_curved<D, AD<N>, NF>(X.col(0), X.template rightCols<NF>(), curvature);
    Eigen::VectorXd Jd(D - 1 + D + 1 + NF);
    int k = 0;
    for (int i = 0; i < D - 1; ++i) Jd(k++) = p.xi(i).derivatives().dot(dir);
    for (int i = 0; i < D; ++i) Jd(k++) = p.normal(i).derivatives().dot(dir);
    Jd(k++) = p.gap.derivatives().dot(dir);
    for (int i = 0; i < NF; ++i) Jd(k++) = p.shape(i).derivatives().dot(dir);
    return Jd;
  };
  const test::TaylorOrder full = test::taylor_order(projection_of, Eigen::VectorXd::Zero(N), dir, ad_slope(true), 1e-2);
  const test::TaylorOrder flat = test::taylor_order(projection_of, Eigen::VectorXd::Zero(N), dir, ad_slope(false), 1e-2);
  // The kernel's test columns, with dx = x − x_n (x_n held).
  const auto columns_of = [&](const auto& t) {
    using S = typename std::decay_t<decltype(t.master)>::Scalar;
    Eigen::Matrix<S, Eigen::Dynamic, 1> out(t.master.size() + t.slip.size());
    out << t.master.reshaped(), t.slip.reshaped();
    return out;
  };
  const auto test_of = [&](const Eigen::VectorXd& v) {
    const Nodes x = x0 + Eigen::Map<const Nodes>(v.data());
    return Eigen::VectorXd(columns_of(zero_work::frictionless_test<D, double, NF>(x, x - x_n)));
  };
  const Eigen::Matrix<AD<N>, D, NF + 1> X = ad_variables<N>(x0);
  const auto t = columns_of(zero_work::frictionless_test<D, AD<N>, NF>(X, X - x_n.template cast<AD<N>>()));
  Eigen::VectorXd Jd(t.size());
  for (Eigen::Index k = 0; k < t.size(); ++k) Jd(k) = t(k).derivatives().dot(dir);
  const test::TaylorOrder kernel = test::taylor_order(test_of, Eigen::VectorXd::Zero(N), dir, Jd, 1e-3);
  std::printf("[ measured ] %dD one-step projection: %s; without the curvature term: %s\n", D,
              test::describe(full).c_str(), test::describe(flat).c_str());
  std::printf("[ measured ] %dD frictionless test columns on a curved master: %s\n", D, test::describe(kernel).c_str());
  test::expect_second_order(full, "projection");
  EXPECT_LT(flat.order, 1.2) << "the curvature term should matter: " << test::describe(flat);
  test::expect_second_order(kernel, "test columns");
}

TEST(CurvedFacet, KernelDerivativesThroughTheOneStepProjectionAreExact) {
  check_curved_kernel_derivatives<2>();
  check_curved_kernel_derivatives<3>();
}

}  // namespace
}  // namespace conserve::contact
