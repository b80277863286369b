// Bare surfaces: the orientation check, degenerate facets, flipping, and
// what `conserve check` states about the normals, on hand-made surfaces
// and on the generators' square and segment.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "mesh/generators.hpp"
#include "mesh/surface_mesh.hpp"
#include "mesh/topology.hpp"
#include "mesh_checks.hpp"

namespace conserve::mesh {
namespace {

using test::all_facets;

using ::testing::HasSubstr;

/// The unit square z = 0 as two triangles, counter-clockwise seen from +z.
Mesh unit_square() {
  Eigen::MatrixXd points(3, 4);
  points << 0, 1, 1, 0, 0, 0, 1, 1, 0, 0, 0, 0;
  Eigen::MatrixXi facets(3, 2);
  facets << 0, 0, 1, 2, 2, 3;
  return bare_surface(3, points, facets);
}

/// The surface of the tetrahedron (0, e_x, e_y, e_z), normals outward.
Mesh tetrahedron_surface() {
  Eigen::MatrixXd points(3, 4);
  points << 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1;
  Eigen::MatrixXi facets(3, 4);
  facets << 0, 0, 0, 1, 2, 1, 3, 2, 1, 3, 2, 3;
  return bare_surface(3, points, facets);
}

TEST(SurfaceMesh, BareSurfaceHasTheGeneratorsGroups) {
  const Mesh mesh = unit_square();
  EXPECT_EQ(mesh.num_cells(), 0);
  EXPECT_EQ(mesh.cells.rows(), 4);
  EXPECT_TRUE(mesh.cell_groups.at("body").empty());
  EXPECT_EQ(mesh.facet_groups.at("boundary").facets, all_facets(mesh));
}

TEST(SurfaceMesh, ConsistentSurfacesHaveNoClash) {
  EXPECT_FALSE(orientation_clash(all_facets(unit_square())).has_value());
  EXPECT_FALSE(orientation_clash(all_facets(tetrahedron_surface())).has_value());
  EXPECT_FALSE(orientation_clash(all_facets(generate_mesh("square", {{"lx", 2}, {"ly", 1}, {"size", 0.25}}))));
  EXPECT_FALSE(orientation_clash(all_facets(generate_mesh("segment", {{"lx", 2}, {"size", 0.25}}))));
}

TEST(SurfaceMesh, ClashNamesBothFacetsAndTheSharedSide) {
  Eigen::MatrixXi square = all_facets(unit_square());
  square.col(1) << 0, 3, 2;  // reversed: 0 → 2 as in facet 0
  const auto clash = orientation_clash(square);
  ASSERT_TRUE(clash.has_value());
  EXPECT_EQ(clash->first, 0);
  EXPECT_EQ(clash->second, 1);
  EXPECT_EQ(clash->from, 2);  // facet 1's sides: 0 → 3, 3 → 2, 2 → 0; facet 0 has 2 → 0
  EXPECT_EQ(clash->to, 0);
  Eigen::MatrixXi fan(3, 3);  // three triangles on the edge 0-1: never consistent
  fan << 0, 1, 0, 1, 0, 1, 2, 3, 4;
  const auto junction = orientation_clash(fan);
  ASSERT_TRUE(junction.has_value());
  EXPECT_EQ(junction->second, 2);
}

TEST(SurfaceMesh, ClashIn2DIsTwoStartsOrTwoEnds) {
  Eigen::MatrixXi chain(2, 3);
  chain << 0, 1, 2, 1, 2, 3;  // 0 → 1 → 2 → 3
  EXPECT_FALSE(orientation_clash(chain).has_value());
  chain.col(1) << 2, 1;  // 0 → 1 ← 2 → 3: both end at 1
  auto clash = orientation_clash(chain);
  ASSERT_TRUE(clash.has_value());
  EXPECT_EQ(clash->from, -1);
  EXPECT_EQ(clash->to, 1);
  EXPECT_EQ(clash->second, 1);
  chain.col(1) << 1, 2;
  chain.col(2) << 1, 3;  // a fork: both start at 1
  clash = orientation_clash(chain);
  ASSERT_TRUE(clash.has_value());
  EXPECT_EQ(clash->from, 1);
  EXPECT_EQ(clash->to, -1);
  EXPECT_EQ(clash->second, 2);
}

TEST(SurfaceMesh, DegenerateFacets) {
  Mesh mesh = unit_square();
  EXPECT_FALSE(degenerate_facet(mesh.points, all_facets(mesh)).has_value());
  Eigen::MatrixXi facets = all_facets(mesh);
  facets(2, 1) = 0;  // repeated node
  EXPECT_EQ(degenerate_facet(mesh.points, facets), 1);
  mesh.points.col(3) << 2, 2, 0;  // on the line through nodes 0 and 2
  EXPECT_EQ(degenerate_facet(mesh.points, all_facets(mesh)), 1);
  Eigen::MatrixXd line(2, 3);
  line << 0, 1, 1, 0, 0, 0;
  EXPECT_EQ(degenerate_facet(line, (Eigen::MatrixXi(2, 2) << 0, 1, 1, 2).finished()), 1);
}

TEST(SurfaceMesh, FlipReversesEveryGroup) {
  Mesh mesh = unit_square();
  mesh.facet_groups["half"].facets = all_facets(mesh).leftCols(1);
  flip_normals(mesh);
  EXPECT_EQ(all_facets(mesh), (Eigen::MatrixXi(3, 2) << 0, 0, 2, 3, 1, 2).finished());
  EXPECT_EQ(mesh.facet_groups.at("half").facets, all_facets(mesh).leftCols(1));
  EXPECT_LT(test::area_normal(mesh, all_facets(mesh), 0).z(), 0.0);
  Mesh segment = generate_mesh("segment", {{"lx", 1}, {"size", 0.5}});
  flip_normals(segment);
  EXPECT_LT(test::area_normal(segment, all_facets(segment), 0).y(), 0.0);
}

// Bare surfaces are linear, but flip_normals keeps a quadratic facet's
// midside nodes on their edges: a tri6 swaps vertices 1, 2 and midsides 3
// ((0,1) → (0,2)) and 5; a line3 swaps its ends, its middle stays.
TEST(SurfaceMesh, FlipTurnsQuadraticFacetsWhole) {
  Mesh tet = test::quadratic(generate_mesh("box", {{"lx", 1}, {"ly", 1}, {"lz", 1}, {"size", 2}}));
  tet.facet_groups["boundary"].facets = boundary_facets(tet);
  const Eigen::MatrixXi before = tet.facet_groups.at("boundary").facets;
  flip_normals(tet);
  const Eigen::MatrixXi& after = tet.facet_groups.at("boundary").facets;
  for (const auto [row, from] : {std::pair{0, 0}, {1, 2}, {2, 1}, {3, 5}, {4, 4}, {5, 3}})
    EXPECT_EQ(after.row(row), before.row(from)) << row;
  test::expect_straight_midsides(tet, after, 1e-12);
  EXPECT_NEAR(test::divergence_volume(tet, after), -1.0, 1e-12);
  Mesh plate = test::quadratic(generate_mesh("rectangle", {{"lx", 1}, {"ly", 1}, {"size", 2}}));
  plate.facet_groups["boundary"].facets = boundary_facets(plate);
  const Eigen::MatrixXi edges = plate.facet_groups.at("boundary").facets;
  flip_normals(plate);
  const Eigen::MatrixXi& flipped = plate.facet_groups.at("boundary").facets;
  EXPECT_EQ(flipped.row(0), edges.row(1));
  EXPECT_EQ(flipped.row(1), edges.row(0));
  EXPECT_EQ(flipped.row(2), edges.row(2));
  EXPECT_NEAR(test::divergence_volume(plate, flipped), -1.0, 1e-12);
}

TEST(SurfaceMesh, StatesTheGeneratorsNormals) {
  const Mesh square = generate_mesh("square", {{"lx", 2}, {"ly", 1}, {"size", 0.5}});
  EXPECT_EQ(describe_surface(summarize_surface(square.points, all_facets(square))),
            "surface of 16 triangles, normals point mostly +z (area-weighted mean normal (0.00, 0.00, 1.00)): the "
            "slaves belong on that side");
  const Mesh segment = generate_mesh("segment", {{"lx", 2}, {"size", 0.5}});
  EXPECT_EQ(describe_surface(summarize_surface(segment.points, all_facets(segment))),
            "line of 4 segments, normals point mostly +y (area-weighted mean normal (0.00, 1.00)): the slaves "
            "belong on that side");
}

TEST(SurfaceMesh, StatesClosedSurfacesAndPieces) {
  Mesh tet = tetrahedron_surface();
  SurfaceSummary s = summarize_surface(tet.points, all_facets(tet));
  EXPECT_TRUE(s.closed);
  EXPECT_EQ(s.pieces, 1);
  EXPECT_NEAR(s.enclosed, 1.0 / 6.0, 1e-15);
  EXPECT_EQ(describe_surface(s),
            "closed surface of 4 triangles, normals point outward (enclosing 0.167 m³): the slaves belong outside");
  flip_normals(tet);
  EXPECT_THAT(describe_surface(summarize_surface(tet.points, all_facets(tet))),
              HasSubstr("normals point inward (enclosing 0.167 m³): the slaves belong inside"));
  Eigen::MatrixXd points(3, 8);  // two unit squares side by side, 1 apart, the second facing -x
  points << 0, 1, 1, 0, 2, 2, 2, 2, 0, 0, 1, 1, 0, 1, 1, 0, 0, 0, 0, 0, 0, 0, 1, 1;
  Eigen::MatrixXi facets(3, 4);
  facets << 0, 0, 4, 4, 1, 2, 6, 7, 2, 3, 5, 6;
  s = summarize_surface(points, facets);
  EXPECT_EQ(s.pieces, 2);
  EXPECT_FALSE(s.closed);
  EXPECT_THAT(describe_surface(s), HasSubstr("surface of 4 triangles in 2 pieces"));
  EXPECT_NEAR(s.mean_normal.norm(), std::sqrt(2.0) / 2.0, 1e-15);
}

}  // namespace
}  // namespace conserve::mesh
