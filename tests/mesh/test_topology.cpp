// Boundary facets, sub-meshes and orientation checks on small hand-made
// meshes, linear and quadratic (midside nodes in Gmsh's order, mesh.hpp).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>

#include "core/error.hpp"
#include "mesh/topology.hpp"
#include "mesh_checks.hpp"

namespace conserve::mesh {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

/// The unit cube split into the 6 positive tets around the diagonal 0-6
/// (Kuhn triangulation); nodes are the corners, bit k of the index = axis k.
Mesh kuhn_cube() {
  Mesh mesh;
  mesh.dim = 3;
  mesh.points.resize(3, 8);
  for (int n = 0; n < 8; ++n) mesh.points.col(n) = Eigen::Vector3d(n & 1, (n >> 1) & 1, (n >> 2) & 1);
  const int paths[6][2] = {{1, 3}, {1, 5}, {2, 3}, {2, 6}, {4, 5}, {4, 6}};  // 0 → a → b → 7
  mesh.cells.resize(4, 6);
  for (int c = 0; c < 6; ++c) {
    mesh.cells.col(c) = Eigen::Vector4i(0, paths[c][0], paths[c][1], 7);
    if (signed_volume(mesh, c) < 0) std::swap(mesh.cells(1, c), mesh.cells(2, c));
  }
  mesh.cell_groups["low"] = {0, 1, 2};
  mesh.cell_groups["high"] = {3, 4, 5};
  return mesh;
}

/// Two counter-clockwise triangles making the unit square.
Mesh square() {
  Mesh mesh;
  mesh.dim = 2;
  mesh.points.resize(2, 4);
  mesh.points << 0, 1, 1, 0, 0, 0, 1, 1;
  mesh.cells.resize(3, 2);
  mesh.cells << 0, 0, 1, 2, 2, 3;
  return mesh;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError";
  return "";
}

TEST(Topology, SingleTetFacetsPointOutward) {
  Mesh mesh;
  mesh.points = Eigen::Matrix<double, 3, 4>{{0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};
  mesh.cells = Eigen::Vector4i(0, 1, 2, 3);
  const Eigen::MatrixXi facets = boundary_facets(mesh);
  ASSERT_EQ(facets.cols(), 4);
  const Eigen::Vector3d centre = mesh.points.rowwise().mean();
  for (int f = 0; f < 4; ++f) {
    const Eigen::Vector3d mid =
        (mesh.points.col(facets(0, f)) + mesh.points.col(facets(1, f)) + mesh.points.col(facets(2, f))) / 3;
    EXPECT_GT(test::area_normal(mesh, facets, f).dot(mid - centre), 0.0) << f;
  }
  EXPECT_NEAR(test::divergence_volume(mesh, facets), 1.0 / 6.0, 1e-15);
}

TEST(Topology, CubeBoundaryIsClosedAndOutward) {
  const Mesh mesh = kuhn_cube();
  EXPECT_NEAR(total_volume(mesh), 1.0, 1e-15);
  const Eigen::MatrixXi facets = boundary_facets(mesh);
  EXPECT_EQ(facets.cols(), 12);  // two triangles per cube face; interior faces are shared
  EXPECT_NEAR(test::check_mesh_consistency(mesh), 1.0, 1e-15);
}

TEST(Topology, SquareBoundaryIn2D) {
  const Mesh mesh = square();
  const Eigen::MatrixXi edges = boundary_facets(mesh);
  ASSERT_EQ(edges.rows(), 2);
  ASSERT_EQ(edges.cols(), 4);  // the diagonal 0-2 is shared
  EXPECT_NEAR(test::divergence_volume(mesh, edges), 1.0, 1e-15);
  for (int e = 0; e < 4; ++e) {  // normal (t_y, -t_x) points away from the centre
    const Eigen::Vector2d mid = (mesh.points.col(edges(0, e)) + mesh.points.col(edges(1, e))) / 2;
    EXPECT_GT(test::area_normal(mesh, edges, e).head<2>().dot(mid - Eigen::Vector2d(0.5, 0.5)), 0.0);
  }
}

TEST(Topology, OrientOutwardFollowsTheBoundary) {
  const Mesh mesh = kuhn_cube();
  const Eigen::MatrixXi boundary = boundary_facets(mesh);
  Eigen::MatrixXi facets(3, 3);
  facets.col(0) = boundary.col(5).reverse();  // a boundary facet, inward
  facets.col(1) = boundary.col(7);            // one already outward
  facets.col(2) = Eigen::Vector3i(0, 7, 1);   // inside the cube (tets 0 and 1 share it)
  EXPECT_EQ(orient_outward(facets, boundary), 1);
  EXPECT_EQ(facets.col(0), boundary.col(5));
  EXPECT_EQ(facets.col(1), boundary.col(7));
  EXPECT_EQ(facets.col(2), Eigen::Vector3i(0, 7, 1));
}

TEST(Topology, ExtractRenumbersAndRestrictsGroups) {
  Mesh mesh = kuhn_cube();
  mesh.facet_groups["bottom"].facets = Eigen::Matrix<int, 3, 2>{{0, 0}, {2, 3}, {3, 1}};  // z = 0
  mesh.facet_groups["top"].facets = Eigen::Matrix<int, 3, 2>{{4, 5}, {5, 7}, {7, 6}};     // z = 1
  const Mesh low = extract(mesh, "low");  // tets 0-1-3-7, 0-1-5-7, 0-2-3-7: nodes 0 1 2 3 5 7
  EXPECT_EQ(low.num_cells(), 3);
  ASSERT_EQ(low.num_nodes(), 6);
  EXPECT_EQ(low.points.col(4), Eigen::Vector3d(1, 0, 1));  // old node 5, in increasing old order
  EXPECT_EQ(low.points.col(5), Eigen::Vector3d(1, 1, 1));
  EXPECT_EQ(low.cell_groups.at("low"), (std::vector<int>{0, 1, 2}));
  EXPECT_FALSE(low.cell_groups.contains("high"));
  EXPECT_EQ(low.facet_groups.at("bottom").facets.cols(), 2);
  EXPECT_FALSE(low.facet_groups.contains("top"));  // needs nodes 4 and 6
  EXPECT_NO_THROW(check_orientation(low, "low"));
  mesh.cell_groups["none"] = {};
  const Mesh none = extract(mesh, "none");
  EXPECT_EQ(none.num_cells(), 0);
  EXPECT_EQ(none.num_nodes(), 0);
  EXPECT_TRUE(none.facet_groups.empty());
  const Mesh all = extract(mesh, "");
  EXPECT_EQ(all.num_cells(), 6);
  EXPECT_EQ(all.points, mesh.points);
  EXPECT_EQ(all.facet_groups.size(), 2u);
}

TEST(Topology, NodeGraphListsEachNeighbourOnce) {
  std::vector<int> offsets, neighbours;
  node_graph(kuhn_cube(), offsets, neighbours);
  ASSERT_EQ(offsets.size(), 9u);
  // Nodes 0 and 7 are on every tet: neighbours of all others, once each.
  EXPECT_EQ(std::vector<int>(neighbours.begin() + offsets[0], neighbours.begin() + offsets[1]),
            (std::vector<int>{1, 2, 3, 4, 5, 6, 7}));
  EXPECT_EQ(std::vector<int>(neighbours.begin() + offsets[1], neighbours.begin() + offsets[2]),
            (std::vector<int>{0, 3, 5, 7}));
}

TEST(Topology, RenumberedKeepsTheMeshAndSortsCellsByTheirLowestNode) {
  Mesh mesh = kuhn_cube();
  mesh.facet_groups["bottom"].facets = Eigen::Matrix<int, 3, 2>{{0, 0}, {2, 3}, {3, 1}};
  const std::vector<int> order = {7, 6, 5, 4, 3, 2, 1, 0};  // node 7 first
  const Mesh r = renumbered(mesh, order);
  ASSERT_EQ(r.num_nodes(), 8);
  ASSERT_EQ(r.num_cells(), 6);
  for (int k = 0; k < 8; ++k) EXPECT_EQ(r.points.col(k), mesh.points.col(order[k]));
  // The same cells, as sets of points, each still positively oriented, in
  // increasing lowest new node.
  int previous_lowest = -1;
  for (int c = 0; c < r.num_cells(); ++c) {
    EXPECT_EQ(cell_orientation(r, c), CellOrientation::positive);
    const int lowest = r.cells.col(c).minCoeff();
    EXPECT_LE(previous_lowest, lowest);
    previous_lowest = lowest;
  }
  EXPECT_DOUBLE_EQ(total_volume(r), total_volume(mesh));
  // Every cell keeps its group: cell j of the new mesh is some old cell whose
  // node set maps onto it.
  const auto old_cell_of = [&](int j) {
    for (int c = 0; c < mesh.num_cells(); ++c) {
      bool same = true;
      for (int a = 0; a < 4; ++a) same = same && r.cells(a, j) == 7 - mesh.cells(a, c);
      if (same) return c;
    }
    return -1;
  };
  for (const char* name : {"low", "high"})
    for (const int j : r.cell_groups.at(name)) {
      const auto& old = mesh.cell_groups.at(name);
      EXPECT_NE(std::find(old.begin(), old.end(), old_cell_of(j)), old.end()) << name << " cell " << j;
    }
  EXPECT_EQ(r.facet_groups.at("bottom").facets, (Eigen::Matrix<int, 3, 2>{{7, 7}, {5, 4}, {4, 6}}));
  EXPECT_THROW(renumbered(mesh, {0, 1, 2, 3, 4, 5, 6, 6}), std::invalid_argument);
  EXPECT_THROW(renumbered(mesh, {0, 1, 2}), std::invalid_argument);
}

TEST(Topology, ExtractUnknownGroupListsAvailable) {
  EXPECT_THAT(error_of([] { extract(kuhn_cube(), "middle"); }),
              AllOf(HasSubstr("unknown cell group 'middle'"), HasSubstr("high, low")));
}

TEST(Topology, CheckOrientationNamesTheFirstBadCell) {
  Mesh mesh = kuhn_cube();
  std::swap(mesh.cells(0, 4), mesh.cells(1, 4));
  EXPECT_EQ(cell_orientation(mesh, 4), CellOrientation::inverted);
  EXPECT_THAT(error_of([&] { check_orientation(mesh, "cube.msh"); }),
              AllOf(HasSubstr("cube.msh: cell 4 is inverted"), HasSubstr("-0.166667")));
  Mesh flat = square();
  flat.points.col(2) = Eigen::Vector2d(2, 0);  // node 2 on the line of nodes 0 and 1
  EXPECT_EQ(cell_orientation(flat, 0), CellOrientation::degenerate);
  EXPECT_THAT(error_of([&] { check_orientation(flat, "sq"); }), HasSubstr("sq: cell 0 is degenerate"));
}

TEST(Topology, SignedVolumes) {
  const Mesh mesh = square();
  EXPECT_DOUBLE_EQ(signed_volume(mesh, 0), 0.5);
  EXPECT_DOUBLE_EQ(total_volume(mesh), 1.0);
  EXPECT_EQ(cell_orientation(mesh, 1), CellOrientation::positive);
}

// ---- quadratic cells (tet10, tri6; Gmsh's node order, mesh.hpp) ----

Mesh unit_tet() {
  Mesh mesh;
  mesh.points = Eigen::Matrix<double, 3, 4>{{0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};
  mesh.cells = Eigen::Vector4i(0, 1, 2, 3);
  return mesh;
}

Mesh unit_triangle() {
  Mesh mesh;
  mesh.dim = 2;
  mesh.points = Eigen::Matrix<double, 2, 3>{{0, 1, 0}, {0, 0, 1}};
  mesh.cells = Eigen::Vector3i(0, 1, 2);
  return mesh;
}

TEST(MeshOrder, NodeCountsAndTheDerivedOrder) {
  static_assert(cell_nodes(2, 1) == 3 && cell_nodes(3, 1) == 4 && cell_nodes(2, 2) == 6 && cell_nodes(3, 2) == 10);
  static_assert(facet_nodes(2, 1) == 2 && facet_nodes(3, 1) == 3 && facet_nodes(2, 2) == 3 && facet_nodes(3, 2) == 6);
  EXPECT_EQ(kuhn_cube().order(), 1);
  EXPECT_EQ(square().order(), 1);
  EXPECT_EQ(test::quadratic(kuhn_cube()).order(), 2);
  EXPECT_EQ(test::quadratic(square()).order(), 2);
  EXPECT_EQ(Mesh{}.order(), 1);
  Mesh none = test::quadratic(kuhn_cube());
  none.cell_groups["none"] = {};
  EXPECT_EQ(extract(none, "none").order(), 2);  // no cells, but 10 rows
  Mesh surface;                                 // no cells at all: the facets say
  surface.dim = 3;
  surface.cells.resize(4, 0);
  surface.facet_groups["s"].facets = Eigen::MatrixXi::Zero(6, 1);
  EXPECT_EQ(surface.order(), 2);
  surface.facet_groups["s"].facets = Eigen::MatrixXi::Zero(3, 1);
  EXPECT_EQ(surface.order(), 1);
}

TEST(Topology, SingleTet10FacetsAreOutwardTri6WithTheirMidsides) {
  const Mesh mesh = test::quadratic(unit_tet());  // midside nodes 4…9 are the local ones
  ASSERT_EQ(mesh.cells.col(0), (Eigen::Matrix<int, 10, 1>() << 0, 1, 2, 3, 4, 5, 6, 7, 8, 9).finished());
  const Eigen::MatrixXi facets = boundary_facets(mesh);
  ASSERT_EQ(facets.rows(), 6);
  ASSERT_EQ(facets.cols(), 4);
  // facet k opposite vertex k, each edge's midside node in the facet's vertex order
  const Eigen::Matrix<int, 6, 4> expected{{1, 0, 0, 0}, {2, 3, 1, 2}, {3, 2, 3, 1},
                                          {5, 7, 4, 6}, {8, 8, 9, 5}, {9, 6, 7, 4}};
  EXPECT_EQ(facets, expected);
  test::expect_straight_midsides(mesh, facets, 1e-15);
  const Eigen::Vector3d centre = mesh.points.leftCols(4).rowwise().mean();
  for (int f = 0; f < 4; ++f) {
    const Eigen::Vector3d mid =
        (mesh.points.col(facets(0, f)) + mesh.points.col(facets(1, f)) + mesh.points.col(facets(2, f))) / 3;
    EXPECT_GT(test::area_normal(mesh, facets, f).dot(mid - centre), 0.0) << f;
  }
  EXPECT_NEAR(test::divergence_volume(mesh, facets), 1.0 / 6.0, 1e-15);
  EXPECT_NEAR(signed_volume(mesh, 0), 1.0 / 6.0, 1e-15);
  EXPECT_DOUBLE_EQ(min_jacobian_determinant(mesh, 0), 1.0);
  EXPECT_FALSE(is_folded(mesh, 0));
}

TEST(Topology, SingleTri6EdgesAreOutwardLine3) {
  const Mesh mesh = test::quadratic(unit_triangle());
  const Eigen::MatrixXi edges = boundary_facets(mesh);
  ASSERT_EQ(edges.rows(), 3);
  ASSERT_EQ(edges.cols(), 3);
  EXPECT_EQ(edges, (Eigen::Matrix3i{{1, 2, 0}, {2, 0, 1}, {4, 5, 3}}));  // columns {1,2,4}, {2,0,5}, {0,1,3}
  test::expect_straight_midsides(mesh, edges, 1e-15);
  for (int e = 0; e < 3; ++e) {
    const Eigen::Vector2d mid = mesh.points.col(edges(2, e));
    EXPECT_GT(test::area_normal(mesh, edges, e).head<2>().dot(mid - Eigen::Vector2d(1.0 / 3, 1.0 / 3)), 0.0) << e;
  }
  EXPECT_NEAR(test::divergence_volume(mesh, edges), 0.5, 1e-15);
}

TEST(Topology, FlipCellTurnsMidsideNodesWithTheVertices) {
  for (Mesh mesh : {kuhn_cube(), square(), test::quadratic(kuhn_cube()), test::quadratic(square())}) {
    SCOPED_TRACE(mesh.cells.rows());
    const Mesh before = mesh;
    flip_cell(mesh, 1);
    EXPECT_EQ(cell_orientation(mesh, 1), CellOrientation::inverted);
    EXPECT_NEAR(signed_volume(mesh, 1), -signed_volume(before, 1), 1e-15);
    EXPECT_EQ(mesh.cells.col(0), before.cells.col(0));
    if (mesh.order() == 2) test::expect_straight_midsides(mesh, mesh.cells, 1e-15);  // each still on its edge
    flip_cell(mesh, 1);
    EXPECT_EQ(mesh.cells, before.cells);
  }
}

TEST(Topology, CurvedTri6AreaIsExact) {
  Mesh mesh = test::quadratic(unit_triangle());
  const double bulge = 0.1;  // node 3, the middle of edge (0,1), pushed out of the triangle
  mesh.points.col(3) = Eigen::Vector2d(0.5, -bulge);
  const double exact = 0.5 + 2.0 / 3.0 * bulge;  // plus a parabolic segment of chord 1
  EXPECT_NEAR(signed_volume(mesh, 0), exact, 1e-15);
  EXPECT_NEAR(total_volume(mesh), exact, 1e-15);
  EXPECT_NEAR(test::divergence_volume(mesh, boundary_facets(mesh)), exact, 1e-15);
  EXPECT_EQ(vertex_volume(mesh, 0), 0.5);
  EXPECT_EQ(cell_orientation(mesh, 0), CellOrientation::positive);
  EXPECT_FALSE(is_folded(mesh, 0));
  EXPECT_NO_THROW(check_orientation(mesh, "tri6"));
  // node 3 at a tenth of its edge: det J = 4·0.1 − 1 < 0 at vertex 0
  mesh.points.col(3) = Eigen::Vector2d(0.1, 0.0);
  EXPECT_EQ(cell_orientation(mesh, 0), CellOrientation::positive);  // the vertex triangle is fine
  EXPECT_TRUE(is_folded(mesh, 0));
  EXPECT_NEAR(min_jacobian_determinant(mesh, 0), -0.6, 1e-15);
  EXPECT_THAT(error_of([&] { check_orientation(mesh, "tri6"); }),
              AllOf(HasSubstr("tri6: cell 0 is folded"), HasSubstr("-0.6")));
}

TEST(Topology, CurvedTet10VolumeMatchesItsCurvedSurface) {
  Mesh mesh = test::quadratic(kuhn_cube());
  // bend two midside nodes: of an interior edge (the body diagonal) and,
  // outward, of a boundary one
  const Eigen::MatrixXi straight = boundary_facets(mesh);
  const int diagonal = mesh.cells(7, 0);  // edge (3, 0) of tet 0 = (0, a, b, 7)
  ASSERT_EQ(mesh.points.col(diagonal), Eigen::Vector3d(0.5, 0.5, 0.5));
  mesh.points.col(diagonal) += Eigen::Vector3d(0.05, -0.02, 0.04);
  const Eigen::Vector3d n = test::area_normal(mesh, straight, 0).normalized();
  mesh.points.col(straight(3, 0)) += 0.05 * n;
  const double volume = total_volume(mesh);
  EXPECT_GT(std::abs(volume - 1.0), 1e-3);  // the curved surface encloses another volume
  EXPECT_NEAR(test::divergence_volume(mesh, boundary_facets(mesh)), volume, 1e-14);
  double vertices = 0.0;
  for (int c = 0; c < mesh.num_cells(); ++c) vertices += vertex_volume(mesh, c);
  EXPECT_NEAR(vertices, 1.0, 1e-15);
  EXPECT_NO_THROW(check_orientation(mesh, "cube"));
}

TEST(Topology, Tet10CubeBoundaryIsClosedAndOutward) {
  const Mesh mesh = test::quadratic(kuhn_cube());
  EXPECT_EQ(mesh.num_nodes(), 8 + 19);  // 12 cube edges, 6 face diagonals, the body diagonal
  const Eigen::MatrixXi facets = boundary_facets(mesh);
  ASSERT_EQ(facets.rows(), 6);
  EXPECT_EQ(facets.cols(), 12);
  test::expect_straight_midsides(mesh, facets, 1e-15);
  EXPECT_EQ(facets.topRows(3), boundary_facets(kuhn_cube()));  // the same vertices, in the same order
  EXPECT_NEAR(test::check_mesh_consistency(mesh), 1.0, 1e-15);
}

TEST(Topology, OrientOutwardTurnsQuadraticFacetsWhole) {
  const Mesh mesh = test::quadratic(kuhn_cube());
  const Eigen::MatrixXi boundary = boundary_facets(mesh);
  Eigen::MatrixXi facets(6, 2);
  const Eigen::VectorXi out = boundary.col(5);
  facets.col(0) << out(0), out(2), out(1), out(5), out(4), out(3);                       // the same facet, inward
  facets.col(1) << mesh.cells(0, 0), mesh.cells(3, 0), mesh.cells(1, 0), 100, 101, 102;  // inside (tets 0, 1)
  const Eigen::VectorXi inside = facets.col(1);
  EXPECT_EQ(orient_outward(facets, boundary), 1);
  EXPECT_EQ(facets.col(0), out);
  EXPECT_EQ(facets.col(1), inside);
  Eigen::MatrixXi linear = boundary.topRows(3);
  EXPECT_THROW(orient_outward(linear, boundary), std::invalid_argument);
  // 2D: line3 facets (3 rows, as a tri3)
  const Mesh plate = test::quadratic(square());
  const Eigen::MatrixXi edges = boundary_facets(plate);
  Eigen::MatrixXi reversed = edges;
  reversed.row(0).swap(reversed.row(1));
  EXPECT_EQ(orient_outward(reversed, edges), 0);
  EXPECT_EQ(reversed, edges);
}

TEST(Topology, ExtractAndRenumberedKeepMidsideNodes) {
  Mesh mesh = test::quadratic(kuhn_cube());
  const Eigen::MatrixXi boundary = boundary_facets(mesh);
  std::vector<int> bottom;
  for (int f = 0; f < boundary.cols(); ++f)
    if (mesh.points(2, boundary(0, f)) + mesh.points(2, boundary(1, f)) + mesh.points(2, boundary(2, f)) == 0.0)
      bottom.push_back(f);
  ASSERT_EQ(bottom.size(), 2u);
  mesh.facet_groups["bottom"].facets = boundary(Eigen::all, bottom);
  const Mesh low = extract(mesh, "low");  // tets 0-1-3-7, 0-1-5-7, 0-2-3-7
  EXPECT_EQ(low.num_cells(), 3);
  ASSERT_EQ(low.cells.rows(), 10);
  EXPECT_EQ(low.num_nodes(), 6 + 12);  // their vertices and edges
  test::expect_straight_midsides(low, low.cells, 1e-15);
  EXPECT_NEAR(total_volume(low), 0.5, 1e-15);
  ASSERT_EQ(low.facet_groups.at("bottom").facets.rows(), 6);
  EXPECT_EQ(low.facet_groups.at("bottom").facets.cols(), 2);
  test::expect_straight_midsides(low, low.facet_groups.at("bottom").facets, 1e-15);
  test::expect_oriented_subset(low.facet_groups.at("bottom").facets, boundary_facets(low));

  std::vector<int> order(static_cast<std::size_t>(mesh.num_nodes()));
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = mesh.num_nodes() - 1 - static_cast<int>(k);
  const Mesh r = renumbered(mesh, order);
  ASSERT_EQ(r.cells.rows(), 10);
  test::expect_straight_midsides(r, r.cells, 1e-15);
  EXPECT_DOUBLE_EQ(total_volume(r), total_volume(mesh));
  for (int c = 0; c < r.num_cells(); ++c) EXPECT_EQ(cell_orientation(r, c), CellOrientation::positive);
  test::expect_straight_midsides(r, r.facet_groups.at("bottom").facets, 1e-15);
  test::expect_oriented_subset(r.facet_groups.at("bottom").facets, boundary_facets(r));
}

TEST(Topology, NodeGraphOfQuadraticCellsLinksMidsideNodes) {
  const Mesh mesh = test::quadratic(kuhn_cube());
  std::vector<int> offsets, neighbours;
  node_graph(mesh, offsets, neighbours);
  ASSERT_EQ(offsets.size(), 28u);
  EXPECT_EQ(offsets[1] - offsets[0], 26);  // node 0 is on every tet: every other node
  const int mid = mesh.cells(4, 0);        // the middle of edge (0, 1) of tet 0: the nodes of its tets
  std::vector<int> expected;
  for (int c = 0; c < mesh.num_cells(); ++c)
    if ((mesh.cells.col(c).array() == mid).any())
      for (int a = 0; a < 10; ++a)
        if (mesh.cells(a, c) != mid) expected.push_back(mesh.cells(a, c));
  std::sort(expected.begin(), expected.end());
  expected.erase(std::unique(expected.begin(), expected.end()), expected.end());
  EXPECT_EQ(std::vector<int>(neighbours.begin() + offsets[mid], neighbours.begin() + offsets[mid + 1]), expected);
}

}  // namespace
}  // namespace conserve::mesh
