// Broad phase: the bounding-volume tree returns exactly the brute-force
// oracle's facets, on random facet clouds and on the paper's meshes, after
// build, refit (nodes moved) and rebuild.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "contact/broad_phase.hpp"
#include "fem/lagrange.hpp"
#include "mesh/generators.hpp"
#include "mesh/topology.hpp"

namespace conserve::contact {
namespace {

constexpr double kRadii[] = {0.0, 1e-3, 0.02, 0.1};

template <int D>
Vec<D> random_point(std::mt19937& rng, double lo, double hi) {
  std::uniform_real_distribution<double> u(lo, hi);
  Vec<D> p;
  for (int i = 0; i < D; ++i) p(i) = u(rng);
  return p;
}

/// Counts the queries where tree and oracle disagree (reports the first).
template <int D>
int mismatches(const FacetTree<D>& tree, const Eigen::MatrixXi& facets, const Positions<D>& x,
               const std::vector<Vec<D>>& points, double radius) {
  std::vector<int> got, want;
  int bad = 0;
  for (const auto& p : points) {
    tree.query(p, radius, got);
    brute_force_query<D>(facets, x, p, radius, want);
    if (got != want && bad++ == 0)
      ADD_FAILURE() << "radius " << radius << " at " << p.transpose() << ": tree " << got.size() << " facets, oracle "
                    << want.size();
  }
  return bad;
}

/// `count` random query points around `x` plus every `stride`-th node
/// (exactly on box corners).
template <int D>
std::vector<Vec<D>> queries(std::mt19937& rng, const Positions<D>& x, int count, int stride = 1) {
  const Vec<D> lo = x.rowwise().minCoeff(), hi = x.rowwise().maxCoeff();
  const double pad = 0.1 * (hi - lo).maxCoeff();
  std::vector<Vec<D>> points;
  for (int q = 0; q < count; ++q) {
    const Vec<D> t = random_point<D>(rng, 0.0, 1.0);
    points.push_back((lo.array() - pad + t.array() * ((hi - lo).array() + 2 * pad)).matrix());
  }
  for (int n = 0; n < x.cols(); n += stride) points.push_back(x.col(n));
  return points;
}

/// Checks tree against oracle for every radius; the total of mismatches.
template <int D>
int check_all_radii(const FacetTree<D>& tree, const Eigen::MatrixXi& facets, const Positions<D>& x,
                    const std::vector<Vec<D>>& points, double scale) {
  int bad = 0;
  for (const double r : kRadii) bad += mismatches<D>(tree, facets, x, points, r * scale);
  return bad;
}

/// `n` random small facets (some degenerate, some sharing nodes) in [0,1]^D.
template <int D>
std::pair<Eigen::MatrixXi, Positions<D>> random_cloud(std::mt19937& rng, int n) {
  Positions<D> x(D, D * n);
  Eigen::MatrixXi facets(D, n);
  std::uniform_real_distribution<double> size(0.0, 0.05);
  for (int f = 0; f < n; ++f) {
    const Vec<D> centre = random_point<D>(rng, 0.0, 1.0);
    const double h = f % 17 == 0 ? 0.0 : size(rng);  // every 17th collapses to a point
    for (int i = 0; i < D; ++i) {
      x.col(D * f + i) = centre + h * random_point<D>(rng, -1.0, 1.0);
      facets(i, f) = D * f + i;
    }
    if (f % 5 == 0 && f > 0) facets(0, f) = facets(1, f - 1);  // shared nodes, far apart
  }
  return {facets, x};
}

template <int D>
void random_cloud_matches_oracle(unsigned seed) {
  std::mt19937 rng(seed);
  auto [facets, x] = random_cloud<D>(rng, 2000);
  FacetTree<D> tree;
  tree.build(facets, x);
  EXPECT_EQ(tree.num_facets(), 2000);
  const auto points = queries<D>(rng, x, 3000, 3);
  EXPECT_EQ(check_all_radii<D>(tree, facets, x, points, 1.0), 0);
  // move every node a lot compared with the facets' size, then refit
  for (int n = 0; n < x.cols(); ++n) x.col(n) += 0.2 * random_point<D>(rng, -1.0, 1.0);
  tree.refit(x);
  EXPECT_EQ(check_all_radii<D>(tree, facets, x, queries<D>(rng, x, 3000, 3), 1.0), 0);
  tree.build(facets, x);
  EXPECT_EQ(check_all_radii<D>(tree, facets, x, queries<D>(rng, x, 3000, 3), 1.0), 0);
}

TEST(BroadPhase, RandomCloud3dMatchesOracle) { random_cloud_matches_oracle<3>(11); }
TEST(BroadPhase, RandomCloud2dMatchesOracle) { random_cloud_matches_oracle<2>(12); }

TEST(BroadPhase, SmallAndEmptyTrees) {
  FacetTree<3> tree;
  std::vector<int> out{7};
  tree.query(Vec<3>::Zero(), 1.0, out);
  EXPECT_TRUE(out.empty());  // never built
  tree.build(Eigen::MatrixXi(3, 0), Positions<3>(3, 0));
  EXPECT_EQ(tree.num_facets(), 0);
  tree.query(Vec<3>::Zero(), 1.0, out);
  EXPECT_TRUE(out.empty());
  Positions<3> x(3, 3);
  x << 0, 1, 0, 0, 0, 1, 0, 0, 0;
  Eigen::MatrixXi one(3, 1);
  one << 0, 1, 2;
  tree.build(one, x);
  tree.query(Vec<3>(1.0, 1.0, 0.0), 0.0, out);  // a corner of the closed box
  EXPECT_EQ(out, std::vector<int>{0});
  tree.query(Vec<3>(1.0, 1.0, 0.5), 0.5, out);  // exactly on the enlarged box
  EXPECT_EQ(out, std::vector<int>{0});
  tree.query(Vec<3>(1.0, 1.0, 0.5000001), 0.5, out);
  EXPECT_TRUE(out.empty());
}

/// Rotates about the axis (1, 2, 3) (about z in 2D), translates and bends.
template <int D>
Positions<D> deformed(const Positions<D>& x) {
  Mat<D> R;
  if constexpr (D == 3) {
    R = Eigen::AngleAxisd(0.7, Vec<3>(1, 2, 3).normalized()).toRotationMatrix();
  } else {
    R = Eigen::Rotation2Dd(0.7).toRotationMatrix();
  }
  Positions<D> y = (R * x).colwise() + Vec<D>::Constant(0.3);
  for (int n = 0; n < y.cols(); ++n) y(0, n) += 0.05 * std::sin(7.0 * x(1, n));
  return y;
}

template <int D>
void mesh_surface_matches_oracle(const std::string& kind, const std::map<std::string, double>& params) {
  SCOPED_TRACE(kind);
  const mesh::Mesh mesh = mesh::generate_mesh(kind, params);
  const Eigen::MatrixXi facets = mesh::boundary_facets(mesh);
  Positions<D> x = mesh.points.topRows(D);
  const double scale = (x.rowwise().maxCoeff() - x.rowwise().minCoeff()).maxCoeff();
  std::mt19937 rng(5);
  FacetTree<D> tree;
  tree.build(facets, x);
  EXPECT_EQ(check_all_radii<D>(tree, facets, x, queries<D>(rng, x, 2000), scale), 0);
  x = deformed<D>(x);
  tree.refit(x);
  EXPECT_EQ(check_all_radii<D>(tree, facets, x, queries<D>(rng, x, 2000), scale), 0);
  tree.build(facets, x);
  EXPECT_EQ(check_all_radii<D>(tree, facets, x, queries<D>(rng, x, 2000), scale), 0);
}

TEST(BroadPhase, PaperMeshesMatchOracle) {
  mesh_surface_matches_oracle<3>("spherical_shell", {{"inner_radius", 0.2}, {"outer_radius", 0.4}, {"size", 0.1}});
  mesh_surface_matches_oracle<3>("hollow_cylinder",
                                 {{"inner_radius", 0.1}, {"outer_radius", 0.2}, {"length", 0.6}, {"size", 0.06}});
  mesh_surface_matches_oracle<3>("cylinder", {{"radius", 0.2}, {"length", 0.5}, {"size", 0.06}});
  mesh_surface_matches_oracle<2>("annulus", {{"inner_radius", 0.5}, {"outer_radius", 1.0}, {"size", 0.05}});
  mesh_surface_matches_oracle<2>("disc", {{"radius", 1.0}, {"size", 0.1}});
}

/// Quadratic facets leave their nodes' box (a 3-node line bulging through
/// its middle node, a 6-node triangle with raised middles): found where
/// the curve is, not where its nodes are.
TEST(BroadPhase, QuadraticFacetsAreFoundWhereTheyBulge) {
  Positions<2> x2(2, 3);
  x2 << 0.0, 1.0, 0.5, 0.0, 0.0, 0.3;  // apex at y = 0.3: the curve x(½) passes through node 2
  Eigen::MatrixXi line(3, 1);
  line << 0, 1, 2;
  FacetTree<2> tree2;
  tree2.build(line, x2);
  std::vector<int> out;
  tree2.query(Vec<2>(0.5, 0.35), 0.1, out);
  EXPECT_EQ(out, std::vector<int>{0});
  tree2.query(Vec<2>(0.5, -0.15), 0.1, out);  // below the chord, beyond the radius
  EXPECT_TRUE(out.empty());
  Positions<3> x3(3, 6);
  x3 << 0.0, 1.0, 0.0, 0.5, 0.5, 0.0,  //
      0.0, 0.0, 1.0, 0.0, 0.5, 0.5,    //
      0.0, 0.0, 0.0, 0.2, 0.2, 0.2;
  Eigen::MatrixXi tri(6, 1);
  tri << 0, 1, 2, 3, 4, 5;
  FacetTree<3> tree3;
  tree3.build(tri, x3);
  tree3.query(Vec<3>(0.3, 0.3, 0.3), 0.05, out);  // the patch rises to z = 0.2 (at ξ = η = 1/3: 0.178)
  EXPECT_EQ(out, std::vector<int>{0});
}

/// On a P2 sphere whose middle nodes are moved at random by up to 0.3 of
/// a facet, every facet with a point within the radius of a query (box
/// distance) is among the tree's answers, and the tree is the oracle.
TEST(BroadPhase, QuadraticSurfaceMatchesOracleAndHoldsItsCurves) {
  const mesh::Mesh mesh = mesh::generate_mesh(
      "spherical_shell", {{"inner_radius", 0.2}, {"outer_radius", 0.4}, {"size", 0.15}, {"order", 2}});
  const Eigen::MatrixXi facets = mesh::boundary_facets(mesh);
  ASSERT_EQ(facets.rows(), 6);
  Positions<3> x = mesh.points.topRows(3);
  std::mt19937 rng(17);
  for (int f = 0; f < facets.cols(); ++f)
    for (int m = 3; m < 6; ++m) x.col(facets(m, f)) += 0.3 * 0.15 * random_point<3>(rng, -1.0, 1.0);
  FacetTree<3> tree;
  tree.build(facets, x);
  const auto points = queries<3>(rng, x, 1000, 7);
  EXPECT_EQ(check_all_radii<3>(tree, facets, x, points, 1.0), 0);
  using Tri = fem::Lagrange<2, 2>;
  int missed = 0, near = 0;
  std::vector<int> out;
  for (const auto& p : points) {
    const double r = 0.02;
    tree.query(p, r, out);
    for (int f = 0; f < facets.cols(); ++f) {
      bool within = false;
      for (int i = 0; i <= 12 && !within; ++i)
        for (int j = 0; j <= 12 - i && !within; ++j) {
          Vec<3> y = Vec<3>::Zero();
          const auto N = Tri::shape(Vec<2>(i / 12.0, j / 12.0));
          for (int a = 0; a < 6; ++a) y += N(a) * x.col(facets(a, f));
          within = (y - p).lpNorm<Eigen::Infinity>() <= r;
        }
      if (!within) continue;
      ++near;
      if (!std::binary_search(out.begin(), out.end(), f)) ++missed;
    }
  }
  EXPECT_GT(near, 100);
  EXPECT_EQ(missed, 0);
}

}  // namespace
}  // namespace conserve::contact
