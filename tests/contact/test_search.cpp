// Narrow phase: find_master on faces, edges, vertices and far sides, the
// slave-normal filter, follow() across facets and at borders,
// over_surface() at a border, node normals.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <random>

#include "contact/contact_support.hpp"
#include "contact/search.hpp"
#include "mesh/generators.hpp"
#include "support/grid_mesh.hpp"

namespace conserve::contact {
namespace {

/// A one-body model, one of its surfaces and a tree over it.
template <int D>
struct Scene {
  model::Model<D> model;
  ContactSurface surface;
  FacetTree<D> tree;

  Scene(const mesh::Mesh& mesh, const std::string& group, const std::function<bool(const Vec<D>&)>& keep = nullptr)
      : model(test::one_body_model<D>(mesh)) {
    if (keep) add_group(group, keep);
    surface = make_surface<D>(model, 0, group);
    tree.build(surface.facets, model.X);
  }
  /// Adds the group of the boundary facets whose centroid satisfies `keep`.
  void add_group(const std::string& name, const std::function<bool(const Vec<D>&)>& keep) {
    const ContactSurface all = make_surface<D>(model, 0, "boundary");
    std::vector<int> kept;
    for (int f = 0; f < all.num_facets(); ++f)
      if (keep(facet_nodes<D>(all, f, model.X).rowwise().mean())) kept.push_back(f);
    Eigen::MatrixXi group(D, static_cast<Eigen::Index>(kept.size()));
    for (std::size_t j = 0; j < kept.size(); ++j) group.col(static_cast<Eigen::Index>(j)) = all.facets.col(kept[j]);
    model.bodies[0].facet_groups[name] = group;
  }
  std::optional<Match<D>> find(const Vec<D>& x_s, const SearchSettings& settings,
                               const std::optional<Vec<D>>& slave_normal = std::nullopt) const {
    return find_master<D>(x_s, surface, tree, model.X, settings, slave_normal);
  }
  [[nodiscard]] Vec<D> normal(int f) const { return facet_normal<D>(facet_nodes<D>(surface, f, model.X)); }
  [[nodiscard]] double distance(const Vec<D>& x_s, int f) const {
    return closest_point_on_facet<D>(x_s, facet_nodes<D>(surface, f, model.X)).second;
  }
};

SearchSettings settings_with(double search_distance, double depth_factor = 0.5) {
  SearchSettings s;
  s.search_distance = search_distance;
  s.depth_factor = depth_factor;
  return s;
}

template <int D>
double longest_edge(const FacetNodes<D>& x) {
  double h = 0.0;
  for (int a = 0; a < D; ++a)
    for (int b = a + 1; b < D; ++b) h = std::max(h, (x.col(a) - x.col(b)).norm());
  return h;
}

/// Points at known barycentric coordinates (each ≥ 0.2) and normal offsets
/// (|g| ≤ 0.05 h, both signs) over random facets: matched to that facet, gap g.
template <int D>
void known_points_are_matched(const Scene<D>& scene, int trials) {
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> pick(0, scene.surface.num_facets() - 1);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int wrong = 0;
  for (int t = 0; t < trials; ++t) {
    const int f = pick(rng);
    const FacetNodes<D> x = facet_nodes<D>(scene.surface, f, scene.model.X);
    Vec<D> w;
    for (int i = 0; i < D; ++i) w(i) = -std::log(1.0 - u(rng));                 // uniform on the simplex …
    const Vec<D> bary = Vec<D>::Constant(0.2) + (1.0 - 0.2 * D) * w / w.sum();  // … kept 0.2 from its sides
    const double g = (2.0 * u(rng) - 1.0) * 0.05 * longest_edge<D>(x);
    const Vec<D> x_s = x * bary + g * facet_normal<D>(x);
    const auto m = scene.find(x_s, settings_with(0.05));
    if (!m || m->facet != f) {
      if (wrong++ == 0) ADD_FAILURE() << "facet " << f << " gap " << g << ": got " << (m ? m->facet : -1);
      continue;
    }
    EXPECT_NEAR(m->projection.gap, g, 1e-12);
    EXPECT_LT((m->projection.xi - bary.template tail<D - 1>()).norm(), 1e-10);
    EXPECT_TRUE(m->projection.inside());
  }
  EXPECT_EQ(wrong, 0);
}

TEST(Search, KnownPointsOnASphereShellsOuterSurface) {
  const Scene<3> scene(
      mesh::generate_mesh("spherical_shell", {{"inner_radius", 0.2}, {"outer_radius", 0.4}, {"size", 0.1}}), "outer");
  known_points_are_matched<3>(scene, 3000);
}

TEST(Search, KnownPointsOnAnAnnulusOuterCircle) {
  const Scene<2> scene(mesh::generate_mesh("annulus", {{"inner_radius", 0.5}, {"outer_radius", 1.0}, {"size", 0.1}}),
                       "outer");
  known_points_are_matched<2>(scene, 1000);
}

// A plate 1 × 1 × 0.05, 10 × 10 × 1 cubes: top facets have h = 0.1√2, so the
// default cut-off (0.5 h ≈ 0.0707) is deeper than the plate is thick.
mesh::Mesh plate() { return test::box_mesh(10, 10, 1, 1.0, 1.0, 0.05); }
bool on_top(const Vec<3>& c) { return c.z() > 0.05 - 1e-12; }

TEST(Search, BehindTheTopBeyondTheCutOffBelongsToTheOtherSide) {
  const Scene<3> scene(plate(), "boundary");
  // 0.08 below the top (beyond 0.0707), 0.03 below the bottom: the bottom, gap > 0
  auto m = scene.find(Vec<3>(0.53, 0.47, -0.03), settings_with(0.2));
  ASSERT_TRUE(m);
  EXPECT_NEAR(scene.normal(m->facet).z(), -1.0, 1e-14);
  EXPECT_NEAR(m->projection.gap, 0.03, 1e-14);
  // a shallower cut-off (0.2 h ≈ 0.028): 0.04 under the top, 0.01 into the bottom
  m = scene.find(Vec<3>(0.53, 0.47, 0.01), settings_with(0.2, 0.2));
  ASSERT_TRUE(m);
  EXPECT_NEAR(scene.normal(m->facet).z(), -1.0, 1e-14);
  EXPECT_NEAR(m->projection.gap, -0.01, 1e-14);
}

TEST(Search, BehindTheTopBeyondTheCutOffWithoutOtherSideIsNoMatch) {
  const Scene<3> scene(plate(), "top", on_top);
  EXPECT_FALSE(scene.find(Vec<3>(0.53, 0.47, 0.01), settings_with(0.2, 0.2)));  // 0.04 deep > 0.028
  EXPECT_FALSE(scene.find(Vec<3>(0.53, 0.47, -0.03), settings_with(0.2)));      // 0.08 deep > 0.0707
  const auto m = scene.find(Vec<3>(0.53, 0.47, 0.01), settings_with(0.2));      // 0.04 deep < 0.0707
  ASSERT_TRUE(m);
  EXPECT_NEAR(m->projection.gap, -0.04, 1e-14);
  EXPECT_TRUE(m->projection.inside());
}

TEST(Search, SlaveNormalFilterRejectsFacetsFacingTheSameWay) {
  const Scene<3> top(plate(), "top", on_top);
  const Vec<3> x_s(0.53, 0.47, 0.051);
  const auto settings = settings_with(0.1);
  EXPECT_TRUE(top.find(x_s, settings, Vec<3>(0, 0, -1)));
  EXPECT_TRUE(top.find(x_s, settings, Vec<3>(0.6, 0, -0.8)));
  EXPECT_TRUE(top.find(x_s, settings, Vec<3>(1, 0, 0)));  // perpendicular: kept (n · n_s = 0)
  EXPECT_FALSE(top.find(x_s, settings, Vec<3>(0, 0, 1)));
  EXPECT_FALSE(top.find(x_s, settings, Vec<3>(0.6, 0, 0.8)));
  const Scene<3> all(plate(), "boundary");
  const auto m = all.find(x_s, settings, Vec<3>(0, 0, 1));
  if (m) {
    EXPECT_LE(all.normal(m->facet).z(), 0.0);
  }
}

// A ball standing on a floor beside a wall (scripts/make_pour.py): its
// node level with the wall's bottom edge, in front of the wall's face,
// has a normal that leans a little towards the face's own. The face is
// still its facet, not the wall's bottom, behind whose plane the node is.
TEST(Search, AFacetSquareToTheSlaveNormalIsKept) {
  const Scene<3> wall(test::box_mesh(2, 2, 2, 1.0, 1.0, 1.0), "boundary");
  const Vec<3> x_s(1.15, 0.5, 0.11);
  const auto m = wall.find(x_s, settings_with(0.3), Vec<3>(0.05, 1.0, 0.0).normalized());
  ASSERT_TRUE(m);
  EXPECT_LT((wall.normal(m->facet) - Vec<3>(1, 0, 0)).norm(), 1e-14);
  EXPECT_NEAR(m->projection.gap, 0.15, 1e-14);
  EXPECT_TRUE(m->projection.inside());
}

// A point just behind the side of a thin slab, level with its bottom
// edge, with a rim node's normal (a cylinder's rim pressed into another
// cylinder's side): it projects just outside the side's facets and inside
// the top, a slab's thickness away; its facet is the side, the nearer.
TEST(Search, BehindTheSideOfAThinSlabAtItsEdgeIsOnTheSide) {
  const Scene<3> slab(test::box_mesh(2, 2, 1, 1.0, 1.0, 0.1), "boundary");
  const Vec<3> x_s(0.99, 0.5, -1e-6);
  const auto m = slab.find(x_s, settings_with(0.3), Vec<3>(-0.7, 0.0, -0.7).normalized());
  ASSERT_TRUE(m);
  EXPECT_LT((slab.normal(m->facet) - Vec<3>(1, 0, 0)).norm(), 1e-14);
  EXPECT_NEAR(m->projection.gap, -0.01, 1e-12);
  EXPECT_FALSE(m->projection.inside());
}

/// Point beyond a convex feature: matched to a facet touching it, at the
/// nearest distance, with the best aligned normal, projection outside.
void expect_corner(const Scene<3>& scene, const Vec<3>& x_s, double distance, const Vec<3>& normal, double gap) {
  const auto m = scene.find(x_s, settings_with(0.3));
  ASSERT_TRUE(m);
  EXPECT_FALSE(m->projection.inside());
  EXPECT_NEAR(scene.distance(x_s, m->facet), distance, 1e-14);
  EXPECT_LT((scene.normal(m->facet) - normal).norm(), 1e-14);
  EXPECT_NEAR(m->projection.gap, gap, 1e-14);
}

TEST(Search, ConvexEdgeAndVertexOfABox) {
  const Scene<3> box(test::box_mesh(2, 2, 2, 1.0, 1.0, 1.0), "boundary");
  const double a = 0.02, b = 0.05, c = 0.03;
  // beyond the edge x = 1, z = 1
  expect_corner(box, Vec<3>(1 + a, 0.3, 1 + b), std::hypot(a, b), Vec<3>(0, 0, 1), b);
  expect_corner(box, Vec<3>(1 + b, 0.3, 1 + a), std::hypot(a, b), Vec<3>(1, 0, 0), b);
  expect_corner(box, Vec<3>(1 + a, 0.5, 1 + b), std::hypot(a, b), Vec<3>(0, 0, 1), b);  // on a mesh vertex too
  // beyond the vertex (1, 1, 1): the face most aligned with x_s − vertex
  const double d = std::sqrt(a * a + b * b + c * c);
  expect_corner(box, Vec<3>(1 + a, 1 + c, 1 + b), d, Vec<3>(0, 0, 1), b);
  expect_corner(box, Vec<3>(1 + b, 1 + c, 1 + a), d, Vec<3>(1, 0, 0), b);
  expect_corner(box, Vec<3>(1 + a, 1 + b, 1 + c), d, Vec<3>(0, 1, 0), b);
  // beyond the vertex (0, 0, 0)
  expect_corner(box, Vec<3>(-a, -c, -b), d, Vec<3>(0, 0, -1), b);
}

TEST(Search, ConvexCornerOfARectangle) {
  const Scene<2> rect(test::rectangle_mesh(4, 4, 1.0, 1.0), "boundary");
  auto m = rect.find(Vec<2>(1.02, 1.05), settings_with(0.3));
  ASSERT_TRUE(m);
  EXPECT_LT((rect.normal(m->facet) - Vec<2>(0, 1)).norm(), 1e-14);
  EXPECT_NEAR(m->projection.gap, 0.05, 1e-14);
  EXPECT_FALSE(m->projection.inside());
  m = rect.find(Vec<2>(-0.05, -0.02), settings_with(0.3));
  ASSERT_TRUE(m);
  EXPECT_LT((rect.normal(m->facet) - Vec<2>(-1, 0)).norm(), 1e-14);
  EXPECT_FALSE(rect.find(Vec<2>(1.5, 1.5), settings_with(0.3)));  // nothing within the search distance
}

/// Slides a slave just inside a convex faceted surface along `path(t)`,
/// t ∈ [0, 1], in `steps` steps with follow(): the projection stays inside,
/// and each switch goes to a neighbour (or, walking, a facet further on).
template <int D>
int slide(const Scene<D>& scene, const std::function<Vec<D>(double)>& path, int steps) {
  auto m = scene.find(path(0.0), settings_with(0.1));
  EXPECT_TRUE(m);
  if (!m) return 0;
  int switches = 0, outside = 0;
  for (int s = 1; s <= steps; ++s) {
    const Vec<D> x_s = path(static_cast<double>(s) / steps);
    const Match<D> next = follow<D>(x_s, *m, scene.surface, scene.model.X);
    if (!next.projection.inside(1e-10)) ++outside;
    if (next.facet != m->facet) ++switches;
    m = next;
  }
  EXPECT_EQ(outside, 0);
  // at the end, follow agrees with a fresh search up to the overlap of facets
  const auto fresh = scene.find(path(1.0), settings_with(0.1));
  EXPECT_TRUE(fresh);
  if (fresh) {
    EXPECT_NEAR(std::abs(m->projection.gap), std::abs(fresh->projection.gap), 2e-3);
  }
  return switches;
}

/// Once round a disc of `order` just inside its circle: every facet once
/// (± the start facet, if the start lies where two overlap).
void slide_round_a_circle(int order) {
  const Scene<2> disc(
      mesh::generate_mesh("disc", {{"radius", 1.0}, {"size", 0.1}, {"order", static_cast<double>(order)}}), "circle");
  ASSERT_EQ(quadratic<2>(disc.surface), order == 2);
  const double pi = std::acos(-1.0);
  const auto path = [&](double t) {
    const double angle = 2 * pi * (t + 0.0123);
    return Vec<2>(0.995 * std::cos(angle), 0.995 * std::sin(angle));
  };
  const int switches = slide<2>(disc, path, 2000);
  EXPECT_NEAR(switches, disc.surface.num_facets(), 1);
}

TEST(Search, FollowSlidesAroundAFacetedCircle) { slide_round_a_circle(1); }

TEST(Search, FollowSlidesOverAFacetedSphere) {
  const Scene<3> shell(
      mesh::generate_mesh("spherical_shell", {{"inner_radius", 0.2}, {"outer_radius", 0.4}, {"size", 0.1}}), "outer");
  const double pi = std::acos(-1.0);
  const Vec<3> e1 = Vec<3>(1, 0.3, 0.2).normalized();
  const Vec<3> e2 = e1.cross(Vec<3>(0.1, 0.2, 1.0)).normalized();
  const auto path = [&](double t) -> Vec<3> { return 0.38 * (std::cos(pi * t) * e1 + std::sin(pi * t) * e2); };
  EXPECT_GT(slide<3>(shell, path, 3000), 10);  // half a great circle: many facets
}

TEST(Search, FollowWalksSeveralFacetsAndStopsAtTheBorder) {
  const Scene<3> top(plate(), "top", on_top);
  auto m = top.find(Vec<3>(0.13, 0.56, 0.06), settings_with(0.1));
  ASSERT_TRUE(m);
  // a jump of several facets: lands on the facet a fresh search finds
  auto moved = follow<3>(Vec<3>(0.73, 0.56, 0.06), *m, top.surface, top.model.X);
  const auto fresh = top.find(Vec<3>(0.73, 0.56, 0.06), settings_with(0.1));
  ASSERT_TRUE(fresh);
  EXPECT_EQ(moved.facet, fresh->facet);
  EXPECT_TRUE(moved.projection.inside());
  // past the border: keeps the border facet, extrapolated
  m = top.find(Vec<3>(0.97, 0.55, 0.06), settings_with(0.1));
  ASSERT_TRUE(m);
  moved = follow<3>(Vec<3>(1.2, 0.55, 0.06), *m, top.surface, top.model.X);
  EXPECT_EQ(moved.facet, m->facet);
  EXPECT_FALSE(moved.projection.inside());
  EXPECT_NEAR(moved.projection.gap, 0.01, 1e-14);
  EXPECT_NEAR(moved.projection.point.x(), 1.2, 1e-14);
}

TEST(Search, FollowStopsAtTheEndOfASegmentChain) {
  const Scene<2> top(test::rectangle_mesh(5, 2, 1.0, 0.5), "top", [](const Vec<2>& c) { return c.y() > 0.5 - 1e-12; });
  auto m = top.find(Vec<2>(0.5, 0.49), settings_with(0.1));
  ASSERT_TRUE(m);
  const auto moved = follow<2>(Vec<2>(0.71, 0.49), *m, top.surface, top.model.X);
  EXPECT_TRUE(moved.projection.inside());
  EXPECT_NEAR(moved.projection.point.x(), 0.71, 1e-14);
  // a jump past the end: no facet to land in, so the current one is kept
  auto end = follow<2>(Vec<2>(1.3, 0.49), moved, top.surface, top.model.X);
  EXPECT_EQ(end.facet, moved.facet);
  EXPECT_NEAR(end.projection.gap, -0.01, 1e-14);
  EXPECT_NEAR(end.projection.point.x(), 1.3, 1e-14);
  EXPECT_FALSE(end.projection.inside());
  // sliding there: the last segment, extrapolated
  end = moved;
  for (int s = 1; s <= 60; ++s) end = follow<2>(Vec<2>(0.71 + 0.01 * s, 0.49), end, top.surface, top.model.X);
  EXPECT_TRUE(top.surface.facet_neighbours(0, end.facet) < 0 || top.surface.facet_neighbours(1, end.facet) < 0);
  EXPECT_NEAR(end.projection.gap, -0.01, 1e-14);
  EXPECT_FALSE(end.projection.inside());
}

// A slave on the rim of one body, pressed against the side of another
// whose top is level with its own: round the other's convex corner lies
// its top face, which faces the way the slave's top does. Walking onto it
// would hold the slave against the top, across the motion that presses it
// (the whole-boundary rings of §6.2 did this in their first contact, and
// Newton failed from step 15 on: docs/notes/validation-history.md).
TEST(Search, FollowDoesNotWalkOntoAFacetThatFacesTheSlavesWay) {
  const Scene<2> box(test::rectangle_mesh(5, 2, 1.0, 0.5), "boundary");
  auto m = box.find(Vec<2>(0.99, 0.45), settings_with(0.1));
  ASSERT_TRUE(m);
  ASSERT_LT((box.normal(m->facet) - Vec<2>(1, 0)).norm(), 1e-14);  // the right side
  const Vec<2> above(0.995, 0.505), rim = Vec<2>(-1.0, 1.0).normalized();
  // Without the slave's normal the walk goes round the corner onto the top.
  const Match<2> walked = follow<2>(above, *m, box.surface, box.model.X);
  EXPECT_LT((box.normal(walked.facet) - Vec<2>(0, 1)).norm(), 1e-14);
  EXPECT_TRUE(walked.projection.inside());
  // With it the right side is kept, extrapolated past the corner.
  const Match<2> kept = follow<2>(above, *m, box.surface, box.model.X, 1e-10, &rim);
  EXPECT_EQ(kept.facet, m->facet);
  EXPECT_NEAR(kept.projection.gap, -0.005, 1e-14);
  EXPECT_FALSE(kept.projection.inside());
  // A slave whose normal opposes the top's (one coming down on it) walks there.
  const Vec<2> down(-0.6, -0.8);
  EXPECT_EQ(follow<2>(above, *m, box.surface, box.model.X, 1e-10, &down).facet, walked.facet);
}

/// The outer surface of a ring of the paper's §6.2 (one facet high, with
/// a row of nodes at mid-height).
Scene<3> ring() {
  return {mesh::generate_mesh("hollow_cylinder",
                              {{"inner_radius", 0.07}, {"outer_radius", 0.1}, {"length", 0.005}, {"size", 0.01}}),
          "outer"};
}

/// Of points round the ring at height z, `depth` inside the outer radius,
/// how many find_master matches and how many of those over_surface() keeps.
std::pair<int, int> matched_and_over(const Scene<3>& ring, double z, double depth) {
  const double pi = std::acos(-1.0);
  int matched = 0, over = 0;
  for (int i = 0; i < 200; ++i) {
    const double angle = 2 * pi * (i + 0.37) / 200;
    const Vec<3> x_s((0.1 - depth) * std::cos(angle), (0.1 - depth) * std::sin(angle), z);
    const auto m = ring.find(x_s, settings_with(0.05));
    if (!m) continue;
    ++matched;
    if (over_surface<3>(x_s, *m, ring.surface, ring.model.X, 1e-3)) ++over;
  }
  return {matched, over};
}

TEST(Search, OverTheSurfaceNotBeyondItsBorder) {
  const Scene<3> outer = ring();
  // A point 10 mm beyond a rim vertex along the axis, 2 mm inside the
  // outer radius, is beyond the surface's border, on every facet at that
  // vertex: seen accepted on a facet whose two edges at the vertex are
  // shared with other facets (§6.2: the rim slaves of the lifted ring,
  // matched 5.5 mm "behind" such a facet).
  int tried = 0, over = 0, interior = 0;
  for (int f = 0; f < outer.surface.num_facets(); ++f) {
    const FacetNodes<3> x = facet_nodes<3>(outer.surface, f, outer.model.X);
    for (int a = 0; a < 3; ++a) {
      const Vec<3> v = x.col(a);
      if (std::abs(std::abs(v.z()) - 0.0025) > 1e-12) continue;
      const Vec<3> radial(v.x(), v.y(), 0.0);
      const Vec<3> x_s = v + Vec<3>(0, 0, std::copysign(0.01, v.z())) - 0.02 * radial;
      ++tried;
      bool all_shared = true;
      for (int k = 0; k < 3; ++k)
        if (k != a && outer.surface.facet_neighbours(k, f) < 0) all_shared = false;
      interior += all_shared;
      if (over_surface<3>(x_s, Match<3>{f, project<3>(x_s, x)}, outer.surface, outer.model.X, 1e-3)) ++over;
    }
  }
  EXPECT_GT(interior, 10);
  EXPECT_GT(tried, 100);
  EXPECT_EQ(over, 0);
  // Found 10 mm above or below the rims: not over it either.
  EXPECT_EQ(matched_and_over(outer, 0.0125, 0.002), std::make_pair(200, 0));
  EXPECT_EQ(matched_and_over(outer, -0.0125, 0.002), std::make_pair(200, 0));
  // At mid-height, behind the surface (inside its facets) or in front of
  // its convex vertical edges, and level with a rim within the border
  // tolerance: over it.
  EXPECT_EQ(matched_and_over(outer, 0.0, 0.002), std::make_pair(200, 200));
  EXPECT_EQ(matched_and_over(outer, 0.0, -0.002), std::make_pair(200, 200));
  EXPECT_EQ(matched_and_over(outer, 0.0025 + 1e-6, 1e-5), std::make_pair(200, 200));
  EXPECT_EQ(matched_and_over(outer, -0.0025 - 1e-6, 1e-5), std::make_pair(200, 200));
}

// Quadratic facets (3-node lines, 6-node triangles): the projection is on
// the curved facet (project_curved), exits and walks use the vertices'
// barycentric coordinates, node normals are those of the curved facets.

/// Points at known ξ (each barycentric coordinate ≥ 0.2) and normal offsets
/// (|g| ≤ 0.05 h) off random curved facets: matched to that facet, gap g.
/// The chord's gap differs from g by the facet's sagitta (the control).
template <int D>
void known_points_on_curved_facets(const Scene<D>& scene, int trials) {
  ASSERT_TRUE(quadratic<D>(scene.surface));
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> pick(0, scene.surface.num_facets() - 1);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int wrong = 0;
  double chord_error = 0.0;
  for (int t = 0; t < trials; ++t) {
    const int f = pick(rng);
    const auto x = curved_nodes<D>(scene.surface, f, scene.model.X);
    Vec<D> w;
    for (int i = 0; i < D; ++i) w(i) = -std::log(1.0 - u(rng));
    const Vec<D> bary = Vec<D>::Constant(0.2) + (1.0 - 0.2 * D) * w / w.sum();
    const Xi<D> xi = bary.template tail<D - 1>();
    const double g = (2.0 * u(rng) - 1.0) * 0.05 * longest_edge<D>(facet_nodes<D>(scene.surface, f, scene.model.X));
    const Vec<D> x_s = CurvedFacet<D>::point(x, xi) + g * CurvedFacet<D>::normal(x, xi);
    const auto m = scene.find(x_s, settings_with(0.05));
    if (!m || m->facet != f) {
      if (wrong++ == 0) ADD_FAILURE() << "facet " << f << " gap " << g << ": got " << (m ? m->facet : -1);
      continue;
    }
    EXPECT_NEAR(m->projection.gap, g, 1e-12);
    EXPECT_LT((m->projection.xi - xi).norm(), 1e-10);
    EXPECT_TRUE(m->projection.inside());
    chord_error = std::max(chord_error, std::abs(project<D>(x_s, facet_nodes<D>(scene.surface, f, scene.model.X)).gap - g));
  }
  EXPECT_EQ(wrong, 0);
  std::printf("[ measured ] %dD: the chords' gaps are off by up to %.2e m\n", D, chord_error);
  EXPECT_GT(chord_error, 1e-4);
}

TEST(Search, KnownPointsOnQuadraticFacetsOfASphereShell) {
  const Scene<3> scene(mesh::generate_mesh("spherical_shell",
                                           {{"inner_radius", 0.2}, {"outer_radius", 0.4}, {"size", 0.1}, {"order", 2}}),
                       "outer");
  known_points_on_curved_facets<3>(scene, 2000);
}

TEST(Search, KnownPointsOnQuadraticFacetsOfAnAnnulus) {
  const Scene<2> scene(
      mesh::generate_mesh("annulus", {{"inner_radius", 0.5}, {"outer_radius", 1.0}, {"size", 0.1}, {"order", 2}}),
      "outer");
  known_points_on_curved_facets<2>(scene, 1000);
}

/// Beyond a curved facet's border, find_master's nearest point of the
/// closed facet is the nearest of a dense sampling of it, to the sampling's
/// resolution, and never farther than any sample.
template <int D>
void nearest_points_beyond_curved_borders(const Scene<D>& scene) {
  std::mt19937 rng(9);
  std::uniform_int_distribution<int> pick(0, scene.surface.num_facets() - 1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int n = D == 2 ? 400 : 60;  // samples per edge
  int tried = 0;
  for (int t = 0; t < 800; ++t) {
    const int f = pick(rng);
    const auto x = curved_nodes<D>(scene.surface, f, scene.model.X);
    const double h = longest_edge<D>(facet_nodes<D>(scene.surface, f, scene.model.X));
    Vec<D> offset;
    for (int i = 0; i < D; ++i) offset(i) = u(rng);
    const Vec<D> x_s = x.rowwise().mean() + 0.8 * h * offset;
    const Projection<D> p = project_curved<D>(x_s, x).projection;
    if (p.inside()) continue;
    ++tried;
    const auto [xi, dist, y] = closest_point_on_curved<D>(x_s, x, p);
    EXPECT_NEAR((x_s - y).norm(), dist, 1e-14);
    EXPECT_GE(xi.minCoeff(), -1e-15);
    EXPECT_LE(xi.sum(), 1.0 + 1e-15);
    double sampled = std::numeric_limits<double>::infinity();
    for (int i = 0; i <= n; ++i)
      for (int j = 0; j <= (D == 2 ? 0 : n - i); ++j) {
        Xi<D> z;
        z(0) = static_cast<double>(i) / n;
        if constexpr (D == 3) z(1) = static_cast<double>(j) / n;
        sampled = std::min(sampled, (x_s - CurvedFacet<D>::point(x, z)).norm());
      }
    EXPECT_LE(dist, sampled + 1e-14);
    EXPECT_GE(dist, sampled - 0.5 * h / n) << "a nearer point of the facet was missed";
  }
  EXPECT_GT(tried, 100);
}

TEST(Search, NearestPointsBeyondTheBorderOfQuadraticFacets) {
  nearest_points_beyond_curved_borders<2>(Scene<2>(
      mesh::generate_mesh("annulus", {{"inner_radius", 0.5}, {"outer_radius", 1.0}, {"size", 0.3}, {"order", 2}}),
      "outer"));
  nearest_points_beyond_curved_borders<3>(Scene<3>(
      mesh::generate_mesh("spherical_shell", {{"inner_radius", 0.2}, {"outer_radius", 0.4}, {"size", 0.2}, {"order", 2}}),
      "outer"));
}

TEST(Search, FollowSlidesAroundAQuadraticCircle) { slide_round_a_circle(2); }

TEST(Search, FollowSlidesOverAQuadraticSphere) {
  const Scene<3> shell(mesh::generate_mesh("spherical_shell",
                                           {{"inner_radius", 0.2}, {"outer_radius", 0.4}, {"size", 0.1}, {"order", 2}}),
                       "outer");
  const double pi = std::acos(-1.0);
  const auto path = [&](double t) {
    const double a = pi * (0.1 + 0.8 * t), b = 2.0 * pi * 0.7 * t;
    return Vec<3>(0.398 * std::sin(a) * std::cos(b), 0.398 * std::sin(a) * std::sin(b), 0.398 * std::cos(a));
  };
  EXPECT_GT(slide<3>(shell, path, 3000), 10);
}

/// On a P2 sphere the node normals, those of the curved facets at each
/// node, lie within 0.2° of the radius; on the P1 one within 11°.
TEST(Search, QuadraticNodeNormalsFollowTheCurvedSurface) {
  double worst[2] = {1.0, 1.0};
  for (const int order : {1, 2}) {
    const Scene<3> shell(mesh::generate_mesh("spherical_shell", {{"inner_radius", 0.2},
                                                                 {"outer_radius", 0.4},
                                                                 {"size", 0.1},
                                                                 {"order", static_cast<double>(order)}}),
                         "outer");
    const auto n = node_normals<3>(shell.surface, shell.model.X);
    for (std::size_t i = 0; i < n.size(); ++i) {
      EXPECT_NEAR(n[i].norm(), 1.0, 1e-14);
      worst[order - 1] = std::min(worst[order - 1], n[i].dot(shell.model.X.col(shell.surface.nodes[i]).normalized()));
    }
  }
  std::printf("[ measured ] node normals off the radius by up to %.2f° (P1), %.3f° (P2)\n",
              std::acos(worst[0]) * 180 / std::acos(-1.0), std::acos(worst[1]) * 180 / std::acos(-1.0));
  EXPECT_GT(worst[1], std::cos(0.2 * std::acos(-1.0) / 180));
  EXPECT_LT(worst[0], worst[1]);
}

TEST(Search, NodeNormalsAreUnitAndOutward) {
  const Scene<3> box(test::box_mesh(2, 2, 2, 1.0, 1.0, 1.0), "boundary");
  const auto n = node_normals<3>(box.surface, box.model.X);
  ASSERT_EQ(n.size(), box.surface.nodes.size());
  int top_centres = 0;
  for (std::size_t i = 0; i < n.size(); ++i) {
    EXPECT_NEAR(n[i].norm(), 1.0, 1e-14);
    const Vec<3> centre_to_node = box.model.X.col(box.surface.nodes[i]) - Vec<3>::Constant(0.5);
    EXPECT_GT(n[i].dot(centre_to_node), 0.0);
    if (std::abs(centre_to_node.z() - 0.5) < 1e-14 && centre_to_node.head<2>().norm() < 1e-14) {
      EXPECT_LT((n[i] - Vec<3>(0, 0, 1)).norm(), 1e-14);  // the centre of the top face
      ++top_centres;
    }
  }
  EXPECT_EQ(top_centres, 1);
  const Scene<3> shell(
      mesh::generate_mesh("spherical_shell", {{"inner_radius", 0.2}, {"outer_radius", 0.4}, {"size", 0.1}}), "outer");
  const auto m = node_normals<3>(shell.surface, shell.model.X);
  for (std::size_t i = 0; i < m.size(); ++i)
    EXPECT_GT(m[i].dot(shell.model.X.col(shell.surface.nodes[i]).normalized()), 0.98);
  const Scene<2> rect(test::rectangle_mesh(2, 2, 1.0, 1.0), "boundary");
  for (const auto& v : node_normals<2>(rect.surface, rect.model.X)) EXPECT_NEAR(v.norm(), 1.0, 1e-14);
}

}  // namespace
}  // namespace conserve::contact

namespace conserve::contact {
namespace {

/// Random points around a surface, both sides and beyond its facets' sides,
/// within the search distance of many facets.
template <int D>
std::vector<Vec<D>> points_around(const Scene<D>& scene, int count, double spread) {
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> pick(0, scene.surface.num_facets() - 1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Vec<D>> points;
  for (int k = 0; k < count; ++k) {
    const Vec<D> c = facet_nodes<D>(scene.surface, pick(rng), scene.model.X).rowwise().mean();
    Vec<D> offset;
    for (int i = 0; i < D; ++i) offset(i) = spread * u(rng);
    points.push_back(c + offset);
  }
  return points;
}

/// find_master with the facets' frames kept across a search (made once per
/// facet) gives the matches of the projection from the nodes, bit for bit;
/// frames left from other positions (the control) do not.
template <int D>
void frames_give_the_same_matches(const Scene<D>& scene) {
  const SearchSettings settings = settings_with(0.15);
  const std::vector<Vec<D>> points = points_around<D>(scene, 2000, 0.1);
  FacetFrames<D> frames;
  frames.reset(scene.surface.num_facets());
  int matched = 0, outside = 0;
  for (const Vec<D>& x_s : points) {
    const auto plain = find_master<D>(x_s, scene.surface, scene.tree, scene.model.X, settings);
    const auto framed = find_master<D>(x_s, scene.surface, scene.tree, scene.model.X, settings, std::nullopt, &frames);
    ASSERT_EQ(plain.has_value(), framed.has_value());
    if (!plain) continue;
    ++matched;
    if (!plain->projection.inside()) ++outside;
    EXPECT_EQ(plain->facet, framed->facet);
    EXPECT_EQ(plain->projection.gap, framed->projection.gap);  // exactly
    EXPECT_EQ(plain->projection.xi, framed->projection.xi);
    EXPECT_EQ(plain->projection.normal, framed->projection.normal);
  }
  std::printf("[ measured ] %dD: %d of %zu points matched (%d outside their facet), the same bit for bit\n", D, matched,
              points.size(), outside);
  ASSERT_GT(matched, 1000);
  ASSERT_GT(outside, 10);
  // The control: frames of the surface moved by 1 % of its size, not reset.
  const Positions<D> moved = 1.01 * scene.model.X;
  FacetFrames<D> stale;
  stale.reset(scene.surface.num_facets());
  for (const Vec<D>& x_s : points)
    (void)find_master<D>(x_s, scene.surface, scene.tree, moved, settings, std::nullopt, &stale);
  int differ = 0;
  for (const Vec<D>& x_s : points) {
    const auto plain = find_master<D>(x_s, scene.surface, scene.tree, scene.model.X, settings);
    const auto framed = find_master<D>(x_s, scene.surface, scene.tree, scene.model.X, settings, std::nullopt, &stale);
    if (plain && framed && plain->projection.gap != framed->projection.gap) ++differ;
  }
  EXPECT_GT(differ, 100);
}

TEST(Search, FramesKeptAcrossASearchGiveTheSameMatchesBitForBit3d) {
  const Scene<3> scene(
      mesh::generate_mesh("spherical_shell", {{"inner_radius", 0.2}, {"outer_radius", 0.4}, {"size", 0.1}}), "outer");
  frames_give_the_same_matches<3>(scene);
}

TEST(Search, FramesKeptAcrossASearchGiveTheSameMatchesBitForBit2d) {
  const Scene<2> scene(mesh::generate_mesh("annulus", {{"inner_radius", 0.5}, {"outer_radius", 1.0}, {"size", 0.1}}),
                       "outer");
  frames_give_the_same_matches<2>(scene);
}

}  // namespace
}  // namespace conserve::contact
