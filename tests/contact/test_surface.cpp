// Contact surfaces: closed boundaries, outward orientation, adjacency,
// surface-only bodies and the input errors.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <set>

#include "material/svk_law.hpp"
#include "contact/contact_support.hpp"
#include "core/error.hpp"
#include "mesh/generators.hpp"
#include "mesh/topology.hpp"
#include "support/grid_mesh.hpp"

namespace conserve::contact {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

/// The nodes of facet f's side (edge in 3D, vertex in 2D) opposite local node k, sorted.
std::vector<int> side(const ContactSurface& s, int f, int k) {
  std::vector<int> nodes;
  for (int i = 0; i < s.facets.rows(); ++i)
    if (i != k) nodes.push_back(s.facets(i, f));
  std::sort(nodes.begin(), nodes.end());
  return nodes;
}

/// Every neighbour link is mutual and the two facets share the side.
void expect_consistent_neighbours(const ContactSurface& s) {
  const int dim = static_cast<int>(s.facets.rows());
  ASSERT_EQ(s.facet_neighbours.rows(), dim);
  ASSERT_EQ(s.facet_neighbours.cols(), s.num_facets());
  for (int f = 0; f < s.num_facets(); ++f)
    for (int k = 0; k < dim; ++k) {
      const int g = s.facet_neighbours(k, f);
      if (g < 0) continue;
      bool back = false;
      for (int l = 0; l < dim; ++l)
        if (s.facet_neighbours(l, g) == f && side(s, g, l) == side(s, f, k)) back = true;
      EXPECT_TRUE(back) << "facet " << f << " side " << k << " → " << g;
    }
}

/// nodes sorted unique; node_facets[i] lists exactly the facets holding nodes[i].
void expect_consistent_node_facets(const ContactSurface& s) {
  EXPECT_TRUE(std::is_sorted(s.nodes.begin(), s.nodes.end()));
  EXPECT_EQ(std::adjacent_find(s.nodes.begin(), s.nodes.end()), s.nodes.end());
  ASSERT_EQ(s.node_facets.size(), s.nodes.size());
  std::size_t total = 0;
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    EXPECT_EQ(s.local_node(s.nodes[i]), static_cast<int>(i));
    for (const int f : s.node_facets[i]) {
      const auto col = s.facets.col(f);
      EXPECT_TRUE(std::find(col.begin(), col.end(), s.nodes[i]) != col.end());
    }
    total += s.node_facets[i].size();
  }
  EXPECT_EQ(total, static_cast<std::size_t>(s.facets.size()));
}

bool all_neighbours(const ContactSurface& s) { return (s.facet_neighbours.array() >= 0).all(); }

TEST(Surface, BoxBoundaryIsClosedOutwardAndConsistent) {
  const auto model = test::one_body_model<3>(test::box_mesh(3, 2, 2, 1.0, 0.8, 0.6), "box");
  const auto s = make_surface<3>(model, 0, "boundary");
  EXPECT_EQ(s.name, "box:boundary");
  EXPECT_EQ(s.body, 0);
  EXPECT_FALSE(s.rigid);
  EXPECT_EQ(s.num_facets(), 2 * 2 * (3 * 2 + 3 * 2 + 2 * 2));
  EXPECT_EQ(s.nodes.size(), 4u * 3u * 3u - 2u * 1u * 1u);  // all but the interior nodes
  EXPECT_TRUE(all_neighbours(s));
  EXPECT_NEAR(test::enclosed_measure<3>(s, model.X), 1.0 * 0.8 * 0.6, 1e-13);
  expect_consistent_neighbours(s);
  expect_consistent_node_facets(s);
  EXPECT_EQ(s.local_node(-5), -1);
}

/// A P2 body's surface: 6-node (3-node) facets, neighbours over the
/// vertices' sides that share the side's middle node too, and every node
/// of the facets a surface node (closed sphere: V + E = 2F + 2).
TEST(Surface, QuadraticBoundaryIsClosedAndItsSidesShareTheirMiddles) {
  {
    const auto model = test::one_body_model<3>(mesh::generate_mesh(
        "spherical_shell", {{"inner_radius", 0.2}, {"outer_radius", 0.4}, {"size", 0.15}, {"order", 2}}));
    const ContactSurface s = make_surface<3>(model, 0, "outer");
    ASSERT_EQ(s.facets.rows(), 6);
    ASSERT_EQ(s.facet_neighbours.rows(), 3);
    EXPECT_TRUE(all_neighbours(s));
    EXPECT_EQ(s.nodes.size(), static_cast<std::size_t>(2 * s.num_facets() + 2));
    for (int f = 0; f < s.num_facets(); ++f)
      for (int k = 0; k < 3; ++k) {
        const int g = s.facet_neighbours(k, f);
        const int mid = s.facets(3 + (k + 1) % 3, f);  // tri6: the side opposite vertex k is edge (k+1, k+2)
        int shared = 0;
        for (int l = 0; l < 3; ++l)
          if (s.facet_neighbours(l, g) == f) shared += s.facets(3 + (l + 1) % 3, g) == mid;
        EXPECT_EQ(shared, 1) << "facet " << f << " side " << k;
      }
    std::size_t total = 0;
    for (std::size_t i = 0; i < s.nodes.size(); ++i) total += s.node_facets[i].size();
    EXPECT_EQ(total, static_cast<std::size_t>(s.facets.size()));
  }
  const auto model = test::one_body_model<2>(
      mesh::generate_mesh("annulus", {{"inner_radius", 0.5}, {"outer_radius", 1.0}, {"size", 0.2}, {"order", 2}}));
  const ContactSurface s = make_surface<2>(model, 0, "outer");
  ASSERT_EQ(s.facets.rows(), 3);
  ASSERT_EQ(s.facet_neighbours.rows(), 2);
  EXPECT_TRUE(all_neighbours(s));
  EXPECT_EQ(s.nodes.size(), static_cast<std::size_t>(2 * s.num_facets()));  // a closed loop
}

TEST(Surface, RectangleBoundaryIsClosedOutwardAndConsistent) {
  const auto model = test::one_body_model<2>(test::rectangle_mesh(4, 3, 2.0, 1.5));
  const auto s = make_surface<2>(model, 0, "boundary");
  EXPECT_EQ(s.num_facets(), 2 * (4 + 3));
  EXPECT_TRUE(all_neighbours(s));
  EXPECT_NEAR(test::enclosed_measure<2>(s, model.X), 3.0, 1e-13);
  expect_consistent_neighbours(s);
  expect_consistent_node_facets(s);
}

/// The unit normal of facet f (right-hand rule; (t_y, −t_x) in 2D).
template <int D>
Vec<D> normal_of(const ContactSurface& s, int f, const Eigen::Matrix<double, D, Eigen::Dynamic>& x) {
  const Vec<D> t = x.col(s.facets(1, f)) - x.col(s.facets(0, f));
  if constexpr (D == 3) {
    return t.cross(Vec<3>(x.col(s.facets(2, f)) - x.col(s.facets(0, f)))).normalized();
  } else {
    return Vec<2>(t.y(), -t.x()).normalized();
  }
}

TEST(Surface, GroupsAreOrientedOutwardWhateverTheirInputOrder) {
  auto model = test::one_body_model<3>(test::box_mesh(2, 2, 2, 1.0, 1.0, 1.0));
  auto& xmin = model.bodies[0].facet_groups["xmin"];
  xmin.row(1).swap(xmin.row(2));  // inward as given
  const auto s = make_surface<3>(model, 0, "xmin");
  EXPECT_EQ(s.num_facets(), 8);
  for (int f = 0; f < s.num_facets(); ++f) EXPECT_NEAR(normal_of<3>(s, f, model.X).x(), -1.0, 1e-14);
  EXPECT_FALSE(all_neighbours(s));  // an open patch has a border
  expect_consistent_neighbours(s);

  auto model2 = test::one_body_model<2>(test::rectangle_mesh(3, 3, 1.0, 1.0));
  auto& xmin2 = model2.bodies[0].facet_groups["xmin"];
  xmin2.row(0).swap(xmin2.row(1));
  const auto s2 = make_surface<2>(model2, 0, "xmin");
  for (int f = 0; f < s2.num_facets(); ++f) EXPECT_NEAR(normal_of<2>(s2, f, model2.X).x(), -1.0, 1e-14);
  EXPECT_EQ((s2.facet_neighbours.array() < 0).count(), 2);  // the two ends
}

TEST(Surface, GeneratorBoundaryGroupAndCurvedFaces) {
  const auto mesh =
      mesh::generate_mesh("spherical_shell", {{"inner_radius", 0.2}, {"outer_radius", 0.4}, {"size", 0.1}});
  const auto model = test::one_body_model<3>(mesh, "ball");
  const auto all = make_surface<3>(model, 0, "boundary");
  EXPECT_EQ(all.num_facets(), mesh::boundary_facets(mesh).cols());
  EXPECT_NEAR(test::enclosed_measure<3>(all, model.X), mesh::total_volume(mesh), 1e-12);
  EXPECT_TRUE(all_neighbours(all));
  const auto outer = make_surface<3>(model, 0, "outer");
  const auto inner = make_surface<3>(model, 0, "inner");
  EXPECT_EQ(outer.num_facets() + inner.num_facets(), all.num_facets());
  EXPECT_TRUE(all_neighbours(outer));
  EXPECT_TRUE(all_neighbours(inner));
  expect_consistent_neighbours(outer);
  // outer encloses the faceted ball; the cavity's facets face into the cavity (negative volume)
  const double outer_volume = test::enclosed_measure<3>(outer, model.X);
  const double inner_volume = test::enclosed_measure<3>(inner, model.X);
  const double pi = std::acos(-1.0);
  EXPECT_NEAR(outer_volume, 4.0 / 3.0 * pi * std::pow(0.4, 3), 0.05 * 4.0 / 3.0 * pi * std::pow(0.4, 3));
  EXPECT_NEAR(inner_volume, -4.0 / 3.0 * pi * std::pow(0.2, 3), 0.15 * 4.0 / 3.0 * pi * std::pow(0.2, 3));
  EXPECT_NEAR(outer_volume + inner_volume, mesh::total_volume(mesh), 1e-12);
}

TEST(Surface, AnnulusFacesAreClosedLoops) {
  const auto mesh = mesh::generate_mesh("annulus", {{"inner_radius", 0.5}, {"outer_radius", 1.0}, {"size", 0.1}});
  const auto model = test::one_body_model<2>(mesh, "ring");
  const auto outer = make_surface<2>(model, 0, "outer");
  EXPECT_TRUE(all_neighbours(outer));
  expect_consistent_neighbours(outer);
  EXPECT_NEAR(test::enclosed_measure<2>(outer, model.X), std::acos(-1.0), 0.02);
}

TEST(Surface, UnknownGroupNamesBodyGroupAndTheGroupsThereAre) {
  const auto model = test::one_body_model<3>(test::box_mesh(1, 1, 1, 1.0, 1.0, 1.0), "crate");
  try {
    make_surface<3>(model, 0, "lid");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), AllOf(HasSubstr("'crate'"), HasSubstr("'lid'"), HasSubstr("xmin"), HasSubstr("boundary")));
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
  }
  EXPECT_THROW(make_surface<3>(model, 3, "boundary"), InputError);
}

TEST(Surface, EmptyGroupIsAnError) {
  auto model = test::one_body_model<3>(test::box_mesh(1, 1, 1, 1.0, 1.0, 1.0), "crate");
  model.bodies[0].facet_groups["hole"] = Eigen::MatrixXi(3, 0);
  try {
    make_surface<3>(model, 0, "hole");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), AllOf(HasSubstr("'crate'"), HasSubstr("'hole'"), HasSubstr("no facets")));
  }
}

TEST(Surface, InteriorFacetIsAnError) {
  const auto mesh = test::box_mesh(2, 2, 2, 1.0, 1.0, 1.0);
  auto model = test::one_body_model<3>(mesh, "crate");
  // a face of some cell that is not on the boundary
  std::set<std::array<int, 3>> boundary;
  const Eigen::MatrixXi b = mesh::boundary_facets(mesh);
  for (int f = 0; f < b.cols(); ++f) {
    std::array<int, 3> key{b(0, f), b(1, f), b(2, f)};
    std::sort(key.begin(), key.end());
    boundary.insert(key);
  }
  Eigen::MatrixXi group(3, 1);
  bool found = false;
  for (int c = 0; c < mesh.num_cells() && !found; ++c)
    for (int k = 0; k < 4 && !found; ++k) {
      std::array<int, 3> key{};
      for (int i = 0, j = 0; i < 4; ++i)
        if (i != k) key[static_cast<std::size_t>(j++)] = mesh.cells(i, c);
      std::sort(key.begin(), key.end());
      if (!boundary.count(key)) {
        group << key[0], key[1], key[2];
        found = true;
      }
    }
  ASSERT_TRUE(found);
  Eigen::MatrixXi mixed(3, 3);
  mixed << model.bodies[0].facet_groups["xmin"].leftCols(2), group;
  model.bodies[0].facet_groups["cut"] = mixed;
  try {
    make_surface<3>(model, 0, "cut");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), AllOf(HasSubstr("'crate'"), HasSubstr("'cut'"), HasSubstr("1 of its 3 facets"),
                                HasSubstr("not on the body's boundary")));
  }
}

TEST(Surface, RigidWhenEveryDofOfEverySurfaceNodeIsPrescribed) {
  auto model = test::one_body_model<3>(test::box_mesh(2, 2, 2, 1.0, 1.0, 1.0));
  auto s = make_surface<3>(model, 0, "boundary");
  EXPECT_FALSE(s.rigid);
  for (const int node : s.nodes)
    for (int i = 0; i < 3; ++i) model.prescribed.dofs.push_back(model::dof<3>(node, i));
  model.prescribed.value.assign(model.prescribed.dofs.size(), 0.0);
  model.prescribed.rate.assign(model.prescribed.dofs.size(), 0.0);
  EXPECT_TRUE(make_surface<3>(model, 0, "boundary").rigid);  // interior node free: still rigid surface
  model.prescribed.dofs.erase(model.prescribed.dofs.begin() + 4);
  EXPECT_FALSE(make_surface<3>(model, 0, "boundary").rigid);
}

/// A box body, then a surface-only body: the unit square z = 0 as two triangles.
model::Model<3> box_and_square() {
  auto model = test::one_body_model<3>(test::box_mesh(1, 1, 1, 1.0, 1.0, 1.0), "box");
  mesh::Mesh square;
  square.dim = 3;
  square.points.resize(3, 4);
  square.points << 0, 1, 1, 0, 0, 0, 1, 1, -1, -1, -1, -1;
  square.cells.resize(4, 0);
  Eigen::MatrixXi tris(3, 2);
  tris << 0, 0, 1, 2, 2, 3;
  square.facet_groups["floor"].facets = tris;
  Eigen::MatrixXi again = tris;
  again.row(1).swap(again.row(2));  // the same triangles, the other way round
  square.facet_groups["under"].facets = again;
  model::add_body<3>(model, square, "floor", std::make_shared<const material::Svk>(material::Lame{1.0, 1.0}), 1.0, 1.0);
  return model;
}

TEST(Surface, SurfaceOnlyBodyUsesItsGroups) {
  auto model = box_and_square();
  const int first = model.bodies[1].first_node;
  const auto floor = make_surface<3>(model, 1, "floor");
  EXPECT_EQ(floor.num_facets(), 2);
  EXPECT_EQ(floor.nodes, (std::vector<int>{first, first + 1, first + 2, first + 3}));
  EXPECT_NEAR(normal_of<3>(floor, 0, model.X).z(), 1.0, 1e-15);  // kept as given
  EXPECT_EQ(floor.facet_neighbours(1, 0), 1);                    // the diagonal (0, 2)
  EXPECT_EQ(floor.facet_neighbours(2, 1), 0);
  EXPECT_EQ((floor.facet_neighbours.array() < 0).count(), 4);
  // "boundary" is the union of the groups, each facet once
  const auto all = make_surface<3>(model, 1, "boundary");
  EXPECT_EQ(all.num_facets(), 2);
  EXPECT_FALSE(all.rigid);
  for (const int node : all.nodes)
    for (int i = 0; i < 3; ++i) model.prescribed.dofs.push_back(model::dof<3>(node, i));
  EXPECT_TRUE(make_surface<3>(model, 1, "boundary").rigid);
  EXPECT_FALSE(make_surface<3>(model, 0, "boundary").rigid);
  // a group named "boundary" takes precedence
  model.bodies[1].facet_groups["boundary"] = model.bodies[1].facet_groups["floor"].leftCols(1);
  EXPECT_EQ(make_surface<3>(model, 1, "boundary").num_facets(), 1);
  // no groups at all: nothing to contact
  model.bodies[1].facet_groups.clear();
  EXPECT_THAT([&] { make_surface<3>(model, 1, "boundary"); },
              ::testing::ThrowsMessage<InputError>(AllOf(HasSubstr("'floor'"), HasSubstr("no facets"))));
}

TEST(Surface, NonManifoldEdgeHasNoNeighbourAndDoesNotCrash) {
  ContactSurface s;
  s.facets.resize(3, 4);
  // three triangles on the edge (0, 1), a fourth on the edge (1, 2) of the first
  s.facets << 0, 1, 0, 2, 1, 0, 1, 1, 2, 3, 4, 5;
  build_adjacency(s, 3);
  EXPECT_EQ(s.nodes, (std::vector<int>{0, 1, 2, 3, 4, 5}));
  for (int f = 0; f < 3; ++f) EXPECT_EQ(s.facet_neighbours(2, f), -1) << f;  // opposite node 2: the edge (0, 1)
  EXPECT_EQ(s.facet_neighbours(0, 0), 3);                                    // edge (1, 2)
  expect_consistent_neighbours(s);
  expect_consistent_node_facets(s);
}

}  // namespace
}  // namespace conserve::contact
