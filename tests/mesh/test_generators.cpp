// Built-in generators: validation, volumes against the analytic ones,
// closed outward boundaries, and named facet groups on the right faces;
// with order = 2, every midside node of a group on its (curved) face.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <numbers>
#include <thread>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "core/error.hpp"
#include "mesh/generators.hpp"
#include "mesh/topology.hpp"
#include "mesh_checks.hpp"

namespace conserve::mesh {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using Params = std::map<std::string, double>;
/// True if a point lies on the face/edge a group names.
using OnGroup = std::function<bool(const Eigen::Vector3d&)>;

constexpr double kPi = std::numbers::pi;

bool near(double a, double b) { return std::abs(a - b) < 1e-9; }
double radius_xy(const Eigen::Vector3d& x) { return std::hypot(x.x(), x.y()); }

struct Case {
  std::string kind;
  Params params;
  double volume;     ///< analytic volume / area
  double tolerance;  ///< relative, for the faceted mesh
  std::map<std::string, OnGroup> groups;
  bool groups_cover_boundary = true;
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.kind; }

std::vector<Case> cases() {
  const double ri = 0.5, ro = 1.0, l = 2.0;
  const auto on_radius = [](double r) {
    return [r](const Eigen::Vector3d& x) { return std::abs(radius_xy(x) - r) < 1e-6; };
  };
  const auto on_sphere = [](double r) {
    return [r](const Eigen::Vector3d& x) { return std::abs(x.norm() - r) < 1e-6; };
  };
  const auto on_plane = [](int axis, double v) {
    return [axis, v](const Eigen::Vector3d& x) { return near(x[axis], v); };
  };
  return {
      {"box",
       {{"lx", 1}, {"ly", 2}, {"lz", 3}, {"size", 0.5}},
       6.0,
       1e-12,
       {{"xmin", on_plane(0, -0.5)},
        {"xmax", on_plane(0, 0.5)},
        {"ymin", on_plane(1, -1)},
        {"ymax", on_plane(1, 1)},
        {"zmin", on_plane(2, -1.5)},
        {"zmax", on_plane(2, 1.5)}}},
      {"cylinder",
       {{"radius", ro}, {"length", l}, {"size", 0.3}},
       kPi * l,
       0.03,
       {{"side", on_radius(ro)}, {"zmin", on_plane(2, -1)}, {"zmax", on_plane(2, 1)}}},
      {"hollow_cylinder",
       {{"inner_radius", ri}, {"outer_radius", ro}, {"length", l}, {"size", 0.3}},
       kPi * (ro * ro - ri * ri) * l,
       0.03,
       {{"inner", on_radius(ri)}, {"outer", on_radius(ro)}, {"zmin", on_plane(2, -1)}, {"zmax", on_plane(2, 1)}}},
      {"sphere", {{"radius", ro}, {"size", 0.3}}, 4.0 / 3.0 * kPi, 0.05, {{"surface", on_sphere(ro)}}},
      {"spherical_shell",
       {{"inner_radius", ri}, {"outer_radius", ro}, {"size", 0.3}},
       4.0 / 3.0 * kPi * (ro * ro * ro - ri * ri * ri),
       0.05,
       {{"inner", on_sphere(ri)}, {"outer", on_sphere(ro)}}},
      {"plate",
       {{"lx", 2}, {"ly", 1}, {"thickness", 0.1}, {"size", 0.3}},
       0.2,
       1e-12,
       {{"top", on_plane(2, 0.0)}, {"bottom", on_plane(2, -0.1)}},
       false},
      {"rectangle",
       {{"lx", 2}, {"ly", 1}, {"size", 0.2}},
       2.0,
       1e-12,
       {{"xmin", on_plane(0, -1)}, {"xmax", on_plane(0, 1)}, {"ymin", on_plane(1, -0.5)}, {"ymax", on_plane(1, 0.5)}}},
      {"disc", {{"radius", ro}, {"size", 0.2}}, kPi, 0.02, {{"circle", on_radius(ro)}}},
      {"annulus",
       {{"inner_radius", ri}, {"outer_radius", ro}, {"size", 0.2}},
       kPi * (ro * ro - ri * ri),
       0.02,
       {{"inner", on_radius(ri)}, {"outer", on_radius(ro)}}},
  };
}

std::string error_of(const std::string& kind, const Params& params) {
  try {
    generate_mesh(kind, params);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError";
  return "";
}

Eigen::Vector3d point3(const Mesh& mesh, int node) {
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  x.head(mesh.dim) = mesh.points.col(node);
  return x;
}

class GeneratorTest : public ::testing::TestWithParam<Case> {};

TEST_P(GeneratorTest, VolumeBoundaryAndGroups) {
  const Case& c = GetParam();
  const Mesh mesh = generate_mesh(c.kind, c.params);
  EXPECT_EQ(mesh.dim, generator_catalog().at(c.kind).dim);
  EXPECT_EQ(mesh.points.rows(), mesh.dim);
  EXPECT_NEAR(test::check_mesh_consistency(mesh), c.volume, c.tolerance * c.volume);
  ASSERT_EQ(mesh.cell_groups.size(), 1u);
  EXPECT_EQ(mesh.cell_groups.at("body").size(), static_cast<std::size_t>(mesh.num_cells()));
  const Eigen::MatrixXi boundary = boundary_facets(mesh);
  EXPECT_EQ(mesh.facet_groups.at("boundary").facets, boundary);
  ASSERT_EQ(mesh.facet_groups.size(), c.groups.size() + 1);
  Eigen::Index in_groups = 0;
  for (const auto& [name, on_group] : c.groups) {
    SCOPED_TRACE(name);
    EXPECT_THAT(generator_catalog().at(c.kind).doc, HasSubstr(name));
    const Eigen::MatrixXi& facets = mesh.facet_groups.at(name).facets;
    ASSERT_GT(facets.cols(), 0);
    test::expect_oriented_subset(facets, boundary);
    for (int f = 0; f < facets.cols(); ++f)
      for (int i = 0; i < mesh.dim; ++i)
        ASSERT_TRUE(on_group(point3(mesh, facets(i, f)))) << point3(mesh, facets(i, f));
    in_groups += facets.cols();
  }
  if (c.groups_cover_boundary) {
    EXPECT_EQ(in_groups, boundary.cols());
  }
}

INSTANTIATE_TEST_SUITE_P(AllShapes, GeneratorTest, ::testing::ValuesIn(cases()),
                         [](const auto& info) { return info.param.kind; });

/// The bare-surface generators (no cells), tested separately below.
std::vector<Case> surface_cases() {
  return {{"square", {{"lx", 2}, {"ly", 1}, {"size", 0.3}}, 2.0, 1e-12, {}},
          {"segment", {{"lx", 2}, {"size", 0.3}}, 2.0, 1e-12, {}}};
}

// Gmsh sets OpenMP's thread count to its own General.NumThreads (1) when it
// starts: every later parallel loop of the process then ran on one thread.
TEST(Generators, GmshLeavesTheProcessThreadsAsTheyWere) {
#ifdef _OPENMP
  const int before = omp_get_max_threads();
  omp_set_num_threads(3);
  const Mesh m = generate_mesh("spherical_shell", {{"inner_radius", 0.5}, {"outer_radius", 1.0}, {"size", 0.5}});
  EXPECT_GT(m.num_cells(), 0);
  EXPECT_EQ(omp_get_max_threads(), 3);
  omp_set_num_threads(before);
#else
  GTEST_SKIP() << "built without OpenMP";
#endif
}

TEST(Generators, CatalogDescribesEveryGenerator) {
  const auto& catalog = generator_catalog();
  auto all = cases();
  for (const Case& c : surface_cases()) all.push_back(c);
  EXPECT_EQ(catalog.size(), all.size());
  for (const Case& c : all) {
    ASSERT_TRUE(catalog.contains(c.kind)) << c.kind;
    const GeneratorInfo& info = catalog.at(c.kind);
    ASSERT_EQ(info.parameters.size(), c.params.size() + 1) << c.kind;
    for (const GeneratorParameter& p : info.parameters) {
      EXPECT_FALSE(p.doc.empty());
      if (p.name == "order") continue;
      EXPECT_TRUE(c.params.contains(p.name)) << c.kind << " " << p.name;
      EXPECT_EQ(p.unit, "m");
    }
    // and last, the order every generator takes
    const GeneratorParameter& order = info.parameters.back();
    EXPECT_EQ(order.name, "order") << c.kind;
    EXPECT_FALSE(order.required);
    EXPECT_EQ(order.default_value, 1.0);
    EXPECT_EQ(order.unit, "");
  }
}

TEST(Generators, FlatGroupsPointOutward) {
  const Mesh plate = generate_mesh("plate", {{"lx", 2}, {"ly", 1}, {"thickness", 0.1}, {"size", 0.3}});
  EXPECT_TRUE(test::total_area_normal(plate, plate.facet_groups.at("top").facets).isApprox(Eigen::Vector3d(0, 0, 2)));
  EXPECT_TRUE(
      test::total_area_normal(plate, plate.facet_groups.at("bottom").facets).isApprox(Eigen::Vector3d(0, 0, -2)));
  const Mesh rect = generate_mesh("rectangle", {{"lx", 2}, {"ly", 1}, {"size", 0.3}});
  EXPECT_TRUE(test::total_area_normal(rect, rect.facet_groups.at("xmin").facets).isApprox(Eigen::Vector3d(-1, 0, 0)));
  EXPECT_TRUE(test::total_area_normal(rect, rect.facet_groups.at("ymax").facets).isApprox(Eigen::Vector3d(0, 2, 0)));
}

/// Every node of `mesh` is used by a facet of `facets`.
void expect_every_node_on_a_facet(const Mesh& mesh, const Eigen::MatrixXi& facets) {
  std::vector<int> uses(static_cast<std::size_t>(mesh.num_nodes()), 0);
  for (int f = 0; f < facets.cols(); ++f)
    for (int i = 0; i < facets.rows(); ++i) {
      ASSERT_GE(facets(i, f), 0);
      ASSERT_LT(facets(i, f), mesh.num_nodes());
      ++uses[static_cast<std::size_t>(facets(i, f))];
    }
  EXPECT_EQ(std::count(uses.begin(), uses.end(), 0), 0);
}

/// Common checks of a bare surface mesh: no cells, groups, every node used.
void expect_bare_surface(const Mesh& mesh, int dim) {
  EXPECT_EQ(mesh.dim, dim);
  EXPECT_EQ(mesh.points.rows(), dim);
  EXPECT_EQ(mesh.cells.rows(), dim + 1);
  EXPECT_EQ(mesh.cells.cols(), 0);
  EXPECT_EQ(mesh.num_cells(), 0);
  EXPECT_TRUE(mesh.cell_groups.at("body").empty());
  ASSERT_EQ(mesh.facet_groups.size(), 2u);
  const Eigen::MatrixXi& surface = mesh.facet_groups.at("surface").facets;
  EXPECT_EQ(surface.rows(), dim);
  EXPECT_EQ(mesh.facet_groups.at("boundary").facets, surface);
  expect_every_node_on_a_facet(mesh, surface);
}

TEST(Generators, SquareIsABareSurfaceFacingUp) {
  const Mesh mesh = generate_mesh("square", {{"lx", 2}, {"ly", 1}, {"size", 0.3}});
  expect_bare_surface(mesh, 3);
  const Eigen::MatrixXi& facets = mesh.facet_groups.at("surface").facets;
  EXPECT_EQ(facets.cols(), 2 * 7 * 4);  // ceil(2/0.3) × ceil(1/0.3) squares
  EXPECT_EQ(mesh.num_nodes(), 8 * 5);
  for (int f = 0; f < facets.cols(); ++f) {
    const Eigen::Vector3d n = test::area_normal(mesh, facets, f);
    EXPECT_GT(n.z(), 0.0) << "facet " << f;
    EXPECT_NEAR(n.head<2>().norm(), 0.0, 1e-15);
  }
  EXPECT_NEAR(test::total_area_normal(mesh, facets).z(), 2.0, 1e-12);  // area lx·ly
  EXPECT_NEAR(mesh.points.row(2).cwiseAbs().maxCoeff(), 0.0, 0.0);
  EXPECT_NEAR(mesh.points.row(0).minCoeff(), -1.0, 1e-15);
  EXPECT_NEAR(mesh.points.row(0).maxCoeff(), 1.0, 1e-15);
  EXPECT_NEAR(mesh.points.row(1).minCoeff(), -0.5, 1e-15);
  EXPECT_NEAR(mesh.points.row(1).maxCoeff(), 0.5, 1e-15);
}

TEST(Generators, SquareWithSizeAboveItsSidesIsTwoTriangles) {
  const Mesh big = generate_mesh("square", {{"lx", 6}, {"ly", 6}, {"size", 3}});
  EXPECT_EQ(big.facet_groups.at("surface").facets.cols(), 8);  // 2 × 2 squares: an exact division stays exact
  const Mesh one = generate_mesh("square", {{"lx", 6}, {"ly", 6}, {"size", 10}});
  expect_bare_surface(one, 3);
  EXPECT_EQ(one.facet_groups.at("surface").facets.cols(), 2);
  EXPECT_EQ(one.num_nodes(), 4);
}

TEST(Generators, SegmentIsABareLineFacingUp) {
  const Mesh mesh = generate_mesh("segment", {{"lx", 2}, {"size", 0.3}});
  expect_bare_surface(mesh, 2);
  const Eigen::MatrixXi& facets = mesh.facet_groups.at("surface").facets;
  ASSERT_EQ(facets.cols(), 7);  // ceil(2/0.3)
  EXPECT_EQ(mesh.num_nodes(), 8);
  for (int f = 0; f < facets.cols(); ++f) {
    const Eigen::Vector3d n = test::area_normal(mesh, facets, f);  // (t_y, −t_x)
    EXPECT_NEAR(n.y(), 2.0 / 7.0, 1e-14) << "facet " << f;
    EXPECT_EQ(n.x(), 0.0);
    EXPECT_GT(mesh.points(0, facets(0, f)), mesh.points(0, facets(1, f)));  // from larger to smaller x
  }
  EXPECT_EQ(mesh.points.row(1).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_NEAR(mesh.points.row(0).minCoeff(), -1.0, 1e-15);
  EXPECT_NEAR(mesh.points.row(0).maxCoeff(), 1.0, 1e-15);
}

TEST(Generators, SurfaceDocsNameTheGroupAndTheNormal) {
  EXPECT_EQ(generator_catalog().at("square").dim, 3);
  EXPECT_EQ(generator_catalog().at("segment").dim, 2);
  EXPECT_THAT(generator_catalog().at("square").doc, AllOf(HasSubstr("surface"), HasSubstr("+z")));
  EXPECT_THAT(generator_catalog().at("segment").doc, AllOf(HasSubstr("surface"), HasSubstr("+y")));
}

TEST(GeneratorErrors, SurfaceParameters) {
  EXPECT_THAT(error_of("square", {{"lx", 1}, {"size", 0.1}}), HasSubstr("missing parameter 'ly'"));
  EXPECT_THAT(error_of("segment", {{"lx", 1}, {"size", 0}}), HasSubstr("'size' = 0"));
  EXPECT_THAT(error_of("segment", {{"lx", -1}, {"size", 0.1}}), HasSubstr("'lx' = -1"));
  EXPECT_THAT(error_of("square", {{"lx", 1}, {"ly", 1}, {"size", 1e-4}}), HasSubstr("would make about"));
}

TEST(Generators, CurvedVolumesConvergeWhenRefined) {
  const double exact = 4.0 / 3.0 * kPi;
  const double coarse = total_volume(generate_mesh("sphere", {{"radius", 1}, {"size", 0.4}}));
  const double fine = total_volume(generate_mesh("sphere", {{"radius", 1}, {"size", 0.12}}));
  EXPECT_LT(std::abs(fine - exact), 0.5 * std::abs(coarse - exact));
  EXPECT_NEAR(fine, exact, 0.01 * exact);
  const double disc = total_volume(generate_mesh("disc", {{"radius", 1}, {"size", 0.05}}));
  EXPECT_NEAR(disc, kPi, 0.002 * kPi);
}

TEST(Generators, WorksAtAnyLengthScale) {
  const Mesh small = generate_mesh("box", {{"lx", 1e-3}, {"ly", 2e-3}, {"lz", 1e-3}, {"size", 5e-4}});
  EXPECT_NEAR(test::check_mesh_consistency(small), 2e-9, 1e-21);
  EXPECT_EQ(small.facet_groups.size(), 7u);
  const Mesh shell = generate_mesh("spherical_shell", {{"inner_radius", 5e-5}, {"outer_radius", 1e-4}, {"size", 3e-5}});
  EXPECT_NEAR(test::check_mesh_consistency(shell), 4.0 / 3.0 * kPi * (1e-12 - 1.25e-13), 0.05 * 3.7e-12);
  EXPECT_GT(shell.facet_groups.at("inner").facets.cols(), 0);
}

TEST(Generators, ConcurrentCallsAreSerialised) {
  Mesh a, b;
  std::thread t1([&] { a = generate_mesh("box", {{"lx", 1}, {"ly", 1}, {"lz", 1}, {"size", 0.25}}); });
  std::thread t2([&] { b = generate_mesh("disc", {{"radius", 1}, {"size", 0.2}}); });
  t1.join();
  t2.join();
  EXPECT_NEAR(total_volume(a), 1.0, 1e-12);
  EXPECT_NEAR(total_volume(b), kPi, 0.02 * kPi);
}

TEST(GeneratorErrors, GmshFailureIsAnInputErrorAndGmshRecovers) {
  // a shell much thinner than the elements: Gmsh's 3D mesher gives up
  EXPECT_THAT(error_of("spherical_shell", {{"inner_radius", 0.95}, {"outer_radius", 1}, {"size", 0.5}}),
              AllOf(HasSubstr("generator 'spherical_shell': Gmsh failed"), HasSubstr("mesh size")));
  EXPECT_NEAR(total_volume(generate_mesh("box", {{"lx", 1}, {"ly", 1}, {"lz", 1}, {"size", 0.5}})), 1.0, 1e-12);
}

TEST(GeneratorErrors, UnknownGeneratorListsKnownOnes) {
  EXPECT_THAT(error_of("cube", {}), AllOf(HasSubstr("unknown mesh generator 'cube'"), HasSubstr("box"),
                                          HasSubstr("spherical_shell"), HasSubstr("annulus")));
}

TEST(GeneratorErrors, UnknownParameterListsAllowedOnes) {
  EXPECT_THAT(error_of("box", {{"lx", 1}, {"ly", 1}, {"lz", 1}, {"size", 1}, {"width", 2}}),
              AllOf(HasSubstr("unknown parameter 'width'"), HasSubstr("lx, ly, lz, order, size")));
}

TEST(GeneratorErrors, MissingOrBadParameters) {
  EXPECT_THAT(error_of("sphere", {{"radius", 1}}), HasSubstr("missing parameter 'size'"));
  EXPECT_THAT(error_of("sphere", {{"radius", -1}, {"size", 0.1}}),
              HasSubstr("'radius' = -1 (expected a positive length"));
  EXPECT_THAT(error_of("disc", {{"radius", 1}, {"size", 0}}), HasSubstr("'size' = 0"));
  EXPECT_THAT(error_of("disc", {{"radius", std::nan("")}, {"size", 1}}), HasSubstr("'radius'"));
  EXPECT_THAT(error_of("annulus", {{"inner_radius", 1}, {"outer_radius", 1}, {"size", 0.1}}),
              HasSubstr("inner_radius = 1 must be smaller than outer_radius = 1"));
  EXPECT_THAT(error_of("hollow_cylinder", {{"inner_radius", 2}, {"outer_radius", 1}, {"length", 1}, {"size", 0.1}}),
              HasSubstr("must be smaller"));
  EXPECT_THAT(error_of("box", {{"lx", 1}, {"ly", 1}, {"lz", 1}, {"size", 1e-4}}), HasSubstr("would make about"));
}

// ---- order = 2: 10-node tetrahedra, 6-node triangles ----

/// The case with order = 2.
Case quadratic(Case c) {
  c.params["order"] = 2;
  return c;
}

/// Straight shapes, whose quadratic cells Gmsh leaves straight.
bool straight(const std::string& kind) { return kind == "box" || kind == "plate" || kind == "rectangle"; }

class QuadraticGeneratorTest : public ::testing::TestWithParam<Case> {};

TEST_P(QuadraticGeneratorTest, EveryNodeOfTheGroupsOnItsFaceAndAnExactVolume) {
  const Case& c = GetParam();
  const Mesh mesh = generate_mesh(c.kind, quadratic(c).params);
  ASSERT_EQ(mesh.order(), 2);
  ASSERT_EQ(mesh.cells.rows(), cell_nodes(mesh.dim, 2));
  const Mesh linear = generate_mesh(c.kind, c.params);
  EXPECT_EQ(mesh.num_cells(), linear.num_cells());  // the same cells, with midside nodes
  EXPECT_GT(mesh.num_nodes(), 2 * linear.num_nodes());
  // check_orientation (in check_mesh_consistency) also refuses folded cells
  const double volume = test::check_mesh_consistency(mesh);
  // curved boundaries: within 2e-4 of the analytic volume (the linear
  // meshes' faceting is off by up to 3e-2); straight ones: exact
  EXPECT_NEAR(volume, c.volume, (straight(c.kind) ? 1e-12 : 2e-4) * c.volume);
  EXPECT_LT(std::abs(volume - c.volume), std::max(0.5 * std::abs(total_volume(linear) - c.volume), 1e-12 * c.volume));
  if (straight(c.kind)) test::expect_straight_midsides(mesh, mesh.cells, 1e-9);  // Gmsh's node order is ours
  const Eigen::MatrixXi boundary = boundary_facets(mesh);
  ASSERT_EQ(boundary.rows(), facet_nodes(mesh.dim, 2));
  EXPECT_EQ(mesh.facet_groups.at("boundary").facets, boundary);
  Eigen::Index in_groups = 0;
  for (const auto& [name, on_group] : c.groups) {
    SCOPED_TRACE(name);
    const Eigen::MatrixXi& facets = mesh.facet_groups.at(name).facets;
    ASSERT_EQ(facets.rows(), facet_nodes(mesh.dim, 2));
    test::expect_oriented_subset(facets, boundary);
    for (int f = 0; f < facets.cols(); ++f)  // midside nodes on the true surface, not on the chord
      for (int i = 0; i < facets.rows(); ++i)
        ASSERT_TRUE(on_group(point3(mesh, facets(i, f)))) << point3(mesh, facets(i, f));
    in_groups += facets.cols();
  }
  if (c.groups_cover_boundary) {
    EXPECT_EQ(in_groups, boundary.cols());
  }
}

INSTANTIATE_TEST_SUITE_P(AllShapes, QuadraticGeneratorTest, ::testing::ValuesIn(cases()),
                         [](const auto& info) { return info.param.kind; });

/// The largest |r − R| / R over the nodes of `facets` (r = |x| in 3D, the
/// distance from the z axis when `axis`).
double off_radius(const Mesh& mesh, const Eigen::MatrixXi& facets, double radius, bool axis) {
  double worst = 0.0;
  for (int f = 0; f < facets.cols(); ++f)
    for (int i = 0; i < facets.rows(); ++i) {
      const Eigen::Vector3d x = point3(mesh, facets(i, f));
      worst = std::max(worst, std::abs((axis ? radius_xy(x) : x.norm()) - radius) / radius);
    }
  return worst;
}

TEST(Generators, QuadraticSphereAndDiscHaveTheirMidsidesOnTheCurve) {
  const double r = 0.7;
  const Mesh ball = generate_mesh("sphere", {{"radius", r}, {"size", 0.25}, {"order", 2}});
  EXPECT_EQ(ball.cells.rows(), 10);
  EXPECT_LT(off_radius(ball, ball.facet_groups.at("boundary").facets, r, false), 1e-9);
  const double exact = 4.0 / 3.0 * kPi * r * r * r;
  const double linear = total_volume(generate_mesh("sphere", {{"radius", r}, {"size", 0.25}}));
  const double curved = total_volume(ball);
  EXPECT_LT(std::abs(curved - exact), 0.02 * std::abs(linear - exact)) << curved - exact << " " << linear - exact;
  EXPECT_NEAR(test::divergence_volume(ball, ball.facet_groups.at("surface").facets), curved, 1e-12 * exact);
  const Mesh disc = generate_mesh("disc", {{"radius", r}, {"size", 0.1}, {"order", 2}});
  EXPECT_EQ(disc.cells.rows(), 6);
  EXPECT_LT(off_radius(disc, disc.facet_groups.at("circle").facets, r, true), 1e-9);
  EXPECT_NEAR(total_volume(disc), kPi * r * r, 1e-5 * kPi * r * r);
  EXPECT_NEAR(test::divergence_volume(disc, disc.facet_groups.at("boundary").facets), total_volume(disc), 1e-13);
}

TEST(Generators, OrderOneIsTheDefault) {
  const Params p = {{"radius", 1}, {"size", 0.3}};
  Params one = p;
  one["order"] = 1;
  const Mesh a = generate_mesh("disc", p), b = generate_mesh("disc", one);
  EXPECT_EQ(a.order(), 1);
  EXPECT_EQ(a.cells, b.cells);
  EXPECT_EQ(a.points, b.points);
  EXPECT_EQ(a.facet_groups.at("circle").facets, b.facet_groups.at("circle").facets);
  EXPECT_EQ(generate_mesh("segment", {{"lx", 1}, {"size", 0.5}, {"order", 1}}).num_nodes(), 3);
}

TEST(GeneratorErrors, OrderIsOneOrTwoAndOneForBareSurfaces) {
  EXPECT_THAT(error_of("box", {{"lx", 1}, {"ly", 1}, {"lz", 1}, {"size", 1}, {"order", 3}}),
              HasSubstr("generator 'box': parameter 'order' = 3 (expected 1 or 2)"));
  EXPECT_THAT(error_of("disc", {{"radius", 1}, {"size", 1}, {"order", 1.5}}),
              HasSubstr("parameter 'order' = 1.5 (expected 1 or 2)"));
  EXPECT_THAT(error_of("disc", {{"radius", 1}, {"size", 1}, {"order", std::nan("")}}),
              HasSubstr("parameter 'order' = nan (expected a finite number)"));
  EXPECT_THAT(error_of("square", {{"lx", 1}, {"ly", 1}, {"size", 0.5}, {"order", 2}}),
              HasSubstr("generator 'square': order = 2, but it makes a bare surface of straight facets without cells "
                        "(expected order = 1)"));
  EXPECT_THAT(error_of("segment", {{"lx", 1}, {"size", 0.5}, {"order", 2}}), HasSubstr("bare surface"));
}

}  // namespace
}  // namespace conserve::mesh
