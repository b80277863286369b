// Built-in generators: validation, volumes against the analytic ones,
// closed outward boundaries, and named facet groups on the right faces.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <functional>
#include <numbers>
#include <thread>

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

TEST(Generators, CatalogDescribesEveryGenerator) {
  const auto& catalog = generator_catalog();
  EXPECT_EQ(catalog.size(), cases().size());
  for (const Case& c : cases()) {
    ASSERT_TRUE(catalog.contains(c.kind)) << c.kind;
    const GeneratorInfo& info = catalog.at(c.kind);
    EXPECT_EQ(info.parameters.size(), c.params.size()) << c.kind;
    for (const GeneratorParameter& p : info.parameters) {
      EXPECT_TRUE(c.params.contains(p.name)) << c.kind << " " << p.name;
      EXPECT_EQ(p.unit, "m");
      EXPECT_FALSE(p.doc.empty());
    }
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
              AllOf(HasSubstr("unknown parameter 'width'"), HasSubstr("lx, ly, lz, size")));
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

}  // namespace
}  // namespace conserve::mesh
