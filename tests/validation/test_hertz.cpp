// Quasi-static plane-strain Hertz contact: a disc of radius R pressed onto a
// rigid plane. Reference (cylinder on a rigid half-space, load P per unit
// thickness, E* = E/(1−ν²)): half-width a = √(4PR/(πE*)), peak pressure
// p0 = 2P/(πa).
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "bar_impact.hpp"  // long_tests()
#include "support/contact_run.hpp"
#include "validation_scenarios.hpp"

namespace conserve::test {
namespace {

/// One slave node of the disc near the rigid plane.
struct Node {
  double x = 0.0, force = 0.0;
  bool active = false;
  int node = -1;
};

/// The disc's boundary nodes in the lower quarter, sorted by x, with the
/// normal forces of the constraints against the ground (pair 0).
std::vector<Node> bottom_nodes(const ContactRun<2>& run, double radius) {
  const contact::Positions<2> x = run.positions();
  std::vector<Node> nodes;
  std::vector<int> index(run.problem.model.num_nodes(), -1);
  for (int s : run.contacts->pairs()[0].slave.nodes)
    if (x(1, s) < -0.7 * radius) {
      index[s] = static_cast<int>(nodes.size());
      nodes.push_back({x(0, s), 0.0, false, s});
    }
  const auto& cs = run.contacts->constraints();
  for (std::size_t i = 0; i < cs.size(); ++i)
    if (cs[i].pair == 0 && index[cs[i].slave] >= 0) {
      nodes[index[cs[i].slave]].force = run.contacts->normal_forces()[i];
      nodes[index[cs[i].slave]].active = true;
    }
  std::sort(nodes.begin(), nodes.end(), [](const Node& a, const Node& b) { return a.x < b.x; });
  return nodes;
}

/// The pressure whose consistent nodal forces are the constraints' forces:
/// M p = f with M = ∫ N_a N_b dx over the disc's boundary facets along the
/// plane (2-node or 3-node lines, 3-point Gauss: exact for both); its
/// largest value. (Forces over tributary lengths alternate on 3-node lines,
/// whose consistent forces of a uniform pressure are 1/6, 2/3, 1/6 of it.)
double recovered_peak(const ContactRun<2>& run, const std::vector<Node>& nodes) {
  const contact::Positions<2> x = run.positions();
  const auto& facets = run.contacts->pairs()[0].slave.facets;
  std::vector<int> index(run.problem.model.num_nodes(), -1);
  for (std::size_t i = 0; i < nodes.size(); ++i) index[nodes[i].node] = static_cast<int>(i);
  const int n = static_cast<int>(nodes.size());
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(n, n);
  Eigen::VectorXd f(n);
  for (int i = 0; i < n; ++i) f(i) = nodes[i].force;
  const double g = std::sqrt(0.6), gauss[3][2] = {{-g, 5.0 / 9.0}, {0.0, 8.0 / 9.0}, {g, 5.0 / 9.0}};
  for (Eigen::Index e = 0; e < facets.cols(); ++e) {
    const int k = static_cast<int>(facets.rows());
    bool in = true;
    for (int a = 0; a < k; ++a) in = in && index[facets(a, e)] >= 0;
    if (!in) continue;
    for (const auto& [t, w] : gauss) {  // t ∈ [−1, 1]; Gmsh order: ends 0, 1, middle 2
      Eigen::Vector3d N, dN;
      if (k == 2) {
        N << 0.5 * (1 - t), 0.5 * (1 + t), 0.0;
        dN << -0.5, 0.5, 0.0;
      } else {
        N << 0.5 * t * (t - 1), 0.5 * t * (t + 1), 1 - t * t;
        dN << t - 0.5, t + 0.5, -2 * t;
      }
      Eigen::Vector2d tangent = Eigen::Vector2d::Zero();
      for (int a = 0; a < k; ++a) tangent += dN(a) * x.col(facets(a, e));
      const double ds = w * tangent.norm();
      for (int a = 0; a < k; ++a)
        for (int b = 0; b < k; ++b) M(index[facets(a, e)], index[facets(b, e)]) += N(a) * N(b) * ds;
    }
  }
  for (int i = 0; i < n; ++i)
    if (M(i, i) == 0.0) M(i, i) = 1.0;  // a node on no facet of the set (the set's ends): p = f = 0
  const Eigen::VectorXd p = M.ldlt().solve(f);
  return p.maxCoeff();
}

struct Measured {
  double load = 0.0;           ///< P: Σ f_N on the ground [N/m]
  double load_top = 0.0;       ///< Σ f_N on the block [N/m]
  double a_edge = 0.0;         ///< half-width: mid-way between the last active and the first free node [m]
  double a_moment = 0.0;       ///< half-width from the second moment of the forces, 2√(Σf(x−x̄)²/Σf) [m]
  double p0 = 0.0;             ///< largest nodal force / tributary length [Pa]
  double p0_recovered = 0.0;   ///< largest pressure whose consistent forces are the nodal forces [Pa]
  double kinetic_ratio = 0.0;  ///< K / W
  int active = 0;
};

Measured measure(const ContactRun<2>& run, double radius) {
  const std::vector<Node> nodes = bottom_nodes(run, radius);
  Measured m;
  double fx = 0.0;
  std::size_t lo = nodes.size(), hi = 0;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    m.load += nodes[i].force;
    fx += nodes[i].force * nodes[i].x;
    if (nodes[i].active) lo = std::min(lo, i), hi = std::max(hi, i), ++m.active;
  }
  for (std::size_t i = 0; i < run.contacts->constraints().size(); ++i)
    if (run.contacts->constraints()[i].pair == 1) m.load_top += run.contacts->normal_forces()[i];
  if (m.active == 0 || lo == 0 || hi + 1 >= nodes.size()) return m;
  const double centre = fx / m.load;
  double second = 0.0;
  for (const Node& n : nodes) second += n.force * (n.x - centre) * (n.x - centre);
  m.a_moment = 2.0 * std::sqrt(second / m.load);
  m.a_edge = 0.25 * ((nodes[hi].x + nodes[hi + 1].x) - (nodes[lo].x + nodes[lo - 1].x));
  for (std::size_t i = lo; i <= hi; ++i)
    m.p0 = std::max(m.p0, nodes[i].force / (0.5 * (nodes[i + 1].x - nodes[i - 1].x)));
  m.p0_recovered = recovered_peak(run, nodes);
  const time::Diagnostics d = run.diagnostics();
  m.kinetic_ratio = d.kinetic / d.strain;
  return m;
}

struct HertzErrors {
  double a_edge = 0.0, a_moment = 0.0, p0 = 0.0, p0_recovered = 0.0;  ///< relative
  int unknowns = 0;
  double a_edge_in_elements = 0.0;                ///< (a_edge − a_H) / h
};

HertzErrors check_hertz(const Hertz& hz) {
  ContactRun<2> run(hertz_scenario(hz));
  const int steps = static_cast<int>(std::lround(hz.end / hz.step));
  int activations = 0, releases = 0;
  for (int n = 0; n < steps; ++n) {
    run.step();
    activations += run.integrator->contact_stats().activations;
    releases += run.integrator->contact_stats().releases;
  }
  const Measured m = measure(run, hz.radius);
  const double e_star = hz.plane_strain_modulus();
  const double a_ref = std::sqrt(4.0 * m.load * hz.radius / (std::numbers::pi * e_star));
  const double p0_ref = 2.0 * m.load / (std::numbers::pi * a_ref);
  HertzErrors e{(m.a_edge - a_ref) / a_ref, (m.a_moment - a_ref) / a_ref, (m.p0 - p0_ref) / p0_ref,
                (m.p0_recovered - p0_ref) / p0_ref, static_cast<int>(run.state.u.size()), 0.0};
  e.a_edge_in_elements = (m.a_edge - a_ref) / hz.size;
  std::printf(
      "[ measured ] Hertz P%d h = %g m (a/h = %.1f, %d unknowns): P %.4e N/m (top %.4e), K/W %.1e, %d active; "
      "a_H %.4e m: a_edge %.4e (%+.1f %%, %+.2f h), a_moment %.4e (%+.1f %%); p0_H %.4e Pa: p0 %.4e (%+.1f %%), "
      "recovered %.4e (%+.1f %%); %d activations, %d releases\n",
      hz.order, hz.size, a_ref / hz.size, e.unknowns, m.load, m.load_top, m.kinetic_ratio, m.active, a_ref, m.a_edge,
      100 * e.a_edge, e.a_edge_in_elements, m.a_moment, 100 * e.a_moment, p0_ref, m.p0, 100 * e.p0, m.p0_recovered,
      100 * e.p0_recovered, activations, releases);
  // Quasi-static: the disc's rigid bounce between block and plane is not
  // damped; on P2 it keeps K/W at 1.2e-2 on the coarse mesh, where the two
  // contacts' loads still agree within 0.5 % (checked next).
  EXPECT_LT(m.kinetic_ratio, hz.order == 1 ? 1e-2 : 2e-2);
  EXPECT_NEAR(m.load_top / m.load, 1.0, 0.05);     // equilibrium, but for the disc's rigid bouncing
  EXPECT_LT(std::abs(e.a_edge_in_elements), 1.0);  // a within one element
  return e;
}

TEST(Hertz, DiscOnRigidPlaneCoarse) {
  Hertz hz;
  const HertzErrors e = check_hertz(hz);
  EXPECT_LT(std::abs(e.a_moment), 0.15);
  EXPECT_LT(std::abs(e.p0), 0.25);
}

/// The same disc and block with quadratic cells at twice the size (about
/// the same unknowns) under the default active set (persistent contact),
/// beside the linear ones: the curved P2 boundary against the plane.
TEST(Hertz, LinearAndQuadraticDiscOnRigidPlaneCoarse) {
  for (int order = 1; order <= 2; ++order) {
    Hertz hz;
    hz.order = order;
    hz.size = 0.08 * order;
    hz.scheme = "persistent";
    const HertzErrors e = check_hertz(hz);
    EXPECT_LT(std::abs(e.a_moment), 0.15);
    EXPECT_LT(std::abs(e.p0_recovered), 0.25);
  }
}

/// P1 and P2 side by side under refinement (CONSERVE_LONG_TESTS=1): P2 at
/// twice P1's element size (the same node spacing and about the same
/// unknowns), the observed order of each error between successive sizes.
TEST(Hertz, LinearAndQuadraticRefinementLong) {
  if (!long_tests()) GTEST_SKIP() << "set CONSERVE_LONG_TESTS=1";
  const double sizes[] = {0.08, 0.04, 0.02};
  HertzErrors e[2][3];
  for (int order = 1; order <= 2; ++order)
    for (int i = 0; i < 3; ++i) {
      Hertz hz;
      hz.order = order;
      hz.size = sizes[i] * order;
      hz.scheme = "persistent";
      e[order - 1][i] = check_hertz(hz);
    }
  auto rate = [](double coarse, double fine) { return std::log(std::abs(coarse) / std::abs(fine)) / std::log(2.0); };
  for (int o = 0; o < 2; ++o)
    for (int i = 0; i < 3; ++i)
      std::printf("[ measured ] Hertz P%d h = %.2f (%d unknowns): a_edge %+.2f %%, a_moment %+.2f %%, p0 recovered "
                  "%+.2f %%, p0 tributary %+.2f %%%s\n",
                  o + 1, sizes[i] * (o + 1), e[o][i].unknowns, 100 * e[o][i].a_edge, 100 * e[o][i].a_moment,
                  100 * e[o][i].p0_recovered, 100 * e[o][i].p0,
                  i == 0 ? ""
                         : fmt::format("; orders from the size before: a_moment {:.2f}, p0 recovered {:.2f}",
                                       rate(e[o][i - 1].a_moment, e[o][i].a_moment),
                                       rate(e[o][i - 1].p0_recovered, e[o][i].p0_recovered))
                               .c_str());
  for (int i = 0; i < 3; ++i) {
    EXPECT_LT(std::abs(e[1][i].a_moment), 0.06);
    EXPECT_LT(std::abs(e[1][i].p0_recovered), 0.10);
  }
}

/// Mesh refinement study (CONSERVE_LONG_TESTS=1). The errors do not fall
/// monotonically (the contact edge jumps from node to node as the load
/// grows), so each size is held to what its mesh allows.
TEST(Hertz, RefinementStudyLong) {
  if (!long_tests()) GTEST_SKIP() << "set CONSERVE_LONG_TESTS=1";
  for (double size : {0.08, 0.04, 0.02}) {
    Hertz hz;
    hz.size = size;
    const HertzErrors e = check_hertz(hz);
    EXPECT_LT(std::abs(e.a_edge_in_elements), 0.5);
    EXPECT_LT(std::abs(e.a_moment), 0.06);
    EXPECT_LT(std::abs(e.p0), 0.05);
  }
}

/// Half the indentation time on the finest mesh (a/R ≈ 0.1 instead of
/// 0.14): separates the finite-strain / finite-a/R part of the error.
TEST(Hertz, LowerLoadLong) {
  if (!long_tests()) GTEST_SKIP() << "set CONSERVE_LONG_TESTS=1";
  Hertz hz;
  hz.size = 0.02;
  hz.end = 3.0;
  const HertzErrors e = check_hertz(hz);
  EXPECT_LT(std::abs(e.a_moment), 0.06);
  EXPECT_LT(std::abs(e.p0), 0.05);
}

}  // namespace
}  // namespace conserve::test
