#pragma once
// Helpers shared by the mesh tests: file access and geometric checks.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "mesh/mesh.hpp"
#include "mesh/topology.hpp"

namespace conserve::mesh::test {

inline std::filesystem::path data_dir() { return std::filesystem::path(CONSERVE_SOURCE_DIR) / "tests/data/msh"; }

inline std::string file_bytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

/// The facets of a bare surface's (or an STL's) "surface" group.
inline const Eigen::MatrixXi& all_facets(const Mesh& mesh) { return mesh.facet_groups.at("surface").facets; }

/// Outward normal of facet `f` scaled by its area (3D) / length (2D).
inline Eigen::Vector3d area_normal(const Mesh& mesh, const Eigen::MatrixXi& facets, int f) {
  Eigen::Vector3d a = Eigen::Vector3d::Zero(), b = Eigen::Vector3d::Zero(), c = Eigen::Vector3d::Zero();
  a.head(mesh.dim) = mesh.points.col(facets(0, f));
  b.head(mesh.dim) = mesh.points.col(facets(1, f));
  if (mesh.dim == 2) return Eigen::Vector3d(b.y() - a.y(), -(b.x() - a.x()), 0.0);
  c.head(mesh.dim) = mesh.points.col(facets(2, f));
  return 0.5 * (b - a).cross(c - a);
}

/// x · n dA/dξ of a quadratic facet (line3 / tri6, Gmsh order) of `mesh`
/// at reference point ξ (ξ_2 unused in 2D), in the facet's own frame of
/// shape functions.
inline double quadratic_flux(const Mesh& mesh, const Eigen::MatrixXi& facets, int f, double s, double t) {
  const auto x = [&](int i) {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    p.head(mesh.dim) = mesh.points.col(facets(i, f));
    return p;
  };
  if (mesh.dim == 2) {  // N = (1−s)(1−2s), s(2s−1), 4s(1−s)
    const Eigen::Vector3d at = (1 - s) * (1 - 2 * s) * x(0) + s * (2 * s - 1) * x(1) + 4 * s * (1 - s) * x(2);
    const Eigen::Vector3d tangent = (4 * s - 3) * x(0) + (4 * s - 1) * x(1) + (4 - 8 * s) * x(2);
    return at.x() * tangent.y() - at.y() * tangent.x();  // x · (t_y, −t_x)
  }
  const double l[3] = {1 - s - t, s, t};
  const int edges[3][3] = {{3, 0, 1}, {4, 1, 2}, {5, 2, 0}};
  Eigen::Vector3d at = Eigen::Vector3d::Zero(), dl[3] = {at, at, at};  // dl[a] = ∂x/∂λ_a
  for (int a = 0; a < 3; ++a) {
    at += l[a] * (2 * l[a] - 1) * x(a);
    dl[a] += (4 * l[a] - 1) * x(a);
  }
  for (const auto& e : edges) {
    at += 4 * l[e[1]] * l[e[2]] * x(e[0]);
    dl[e[1]] += 4 * l[e[2]] * x(e[0]);
    dl[e[2]] += 4 * l[e[1]] * x(e[0]);
  }
  return at.dot((dl[1] - dl[0]).cross(dl[2] - dl[0]));
}

/// Σ (1/dim) x·n dA over the facets: the enclosed volume (area in 2D) when
/// they form a closed, outward oriented surface. Quadratic facets are
/// integrated exactly: x·n dA/dξ is of degree 3 on a line3 (2-point Gauss)
/// and 4 on a tri6 (Dunavant's 6-point rule of degree 4).
inline double divergence_volume(const Mesh& mesh, const Eigen::MatrixXi& facets) {
  double sum = 0.0;
  if (facets.rows() == facet_nodes(mesh.dim, 2) && mesh.dim == 2) {
    const double g = 0.5 / std::sqrt(3.0);
    for (int f = 0; f < facets.cols(); ++f)
      sum += 0.5 * (quadratic_flux(mesh, facets, f, 0.5 - g, 0) + quadratic_flux(mesh, facets, f, 0.5 + g, 0)) / 2;
    return sum;
  }
  if (facets.rows() == facet_nodes(mesh.dim, 2)) {
    const double a[2] = {0.445948490915965, 0.091576213509771}, w[2] = {0.223381589678011, 0.109951743655322};
    for (int f = 0; f < facets.cols(); ++f)
      for (int k = 0; k < 2; ++k) {
        const double b = 1 - 2 * a[k];
        sum += w[k] * 0.5 / 3 *
               (quadratic_flux(mesh, facets, f, a[k], a[k]) + quadratic_flux(mesh, facets, f, a[k], b) +
                quadratic_flux(mesh, facets, f, b, a[k]));
      }
    return sum;
  }
  for (int f = 0; f < facets.cols(); ++f) {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int i = 0; i < mesh.dim; ++i) centroid.head(mesh.dim) += mesh.points.col(facets(i, f)) / mesh.dim;
    sum += centroid.dot(area_normal(mesh, facets, f)) / mesh.dim;
  }
  return sum;
}

/// Every midside node of `nodes`, quadratic cells or facets of `mesh`
/// (tet10, tri6, or in 2D line3), is at the middle of its edge (to
/// `tolerance` × the edge's length): a straight-sided quadratic mesh.
/// Checks Gmsh's node order (mesh.hpp) as much as the geometry.
inline void expect_straight_midsides(const Mesh& mesh, const Eigen::MatrixXi& nodes, double tolerance) {
  static const int tri6[3][3] = {{3, 0, 1}, {4, 1, 2}, {5, 2, 0}};
  static const int tet10[6][3] = {{4, 0, 1}, {5, 1, 2}, {6, 2, 0}, {7, 3, 0}, {8, 3, 2}, {9, 3, 1}};
  static const int line3[1][3] = {{2, 0, 1}};
  const auto check = [&](const auto& edges) {
    for (int c = 0; c < nodes.cols(); ++c)
      for (const auto& e : edges) {
        const Eigen::VectorXd a = mesh.points.col(nodes(e[1], c)), b = mesh.points.col(nodes(e[2], c));
        ASSERT_LE((mesh.points.col(nodes(e[0], c)) - (a + b) / 2).norm(), tolerance * (a - b).norm())
            << "column " << c << " node " << e[0];
      }
  };
  if (nodes.rows() == 10) check(tet10);
  if (nodes.rows() == 6) check(tri6);
  if (nodes.rows() == 3 && mesh.dim == 2) check(line3);
}

/// Σ n dA over the facets (zero for a closed surface).
inline Eigen::Vector3d total_area_normal(const Mesh& mesh, const Eigen::MatrixXi& facets) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int f = 0; f < facets.cols(); ++f) sum += area_normal(mesh, facets, f);
  return sum;
}

/// Each facet of `group` is a column of `boundary` with the same node order
/// up to a cyclic rotation (so the same orientation); a tri6's midside
/// nodes turn with its vertices.
inline void expect_oriented_subset(const Eigen::MatrixXi& group, const Eigen::MatrixXi& boundary) {
  const auto canonical = [](const Eigen::VectorXi& f) {  // triangles: rotate the smallest vertex first
    Eigen::Index first = 0;
    if (f.size() == 3 || f.size() == 6) f.head(3).minCoeff(&first);
    std::vector<int> out(static_cast<std::size_t>(f.size()));
    for (Eigen::Index i = 0; i < std::min<Eigen::Index>(f.size(), 3); ++i)
      out[static_cast<std::size_t>(i)] = f((first + i) % 3);
    for (Eigen::Index i = 3; i < f.size(); ++i) out[static_cast<std::size_t>(i)] = f(3 + (first + i - 3) % 3);
    if (f.size() == 2) out = {f(0), f(1)};
    return out;
  };
  std::map<std::vector<int>, int> present;
  for (int f = 0; f < boundary.cols(); ++f) ++present[canonical(boundary.col(f))];
  for (int f = 0; f < group.cols(); ++f) EXPECT_TRUE(present.contains(canonical(group.col(f)))) << "facet " << f;
}

/// `mesh` (linear) made quadratic and straight-sided: a node at the middle
/// of every edge, shared by the cells around it and numbered after the
/// vertices in the order the cells first meet the edges; cells in Gmsh's
/// order (mesh.hpp). Facet groups are dropped.
inline Mesh quadratic(const Mesh& mesh) {
  static const int tri[3][2] = {{0, 1}, {1, 2}, {2, 0}};
  static const int tet[6][2] = {{0, 1}, {1, 2}, {2, 0}, {3, 0}, {3, 2}, {3, 1}};
  Mesh out = mesh;
  out.facet_groups.clear();
  out.cells.resize(cell_nodes(mesh.dim, 2), mesh.num_cells());
  std::map<std::pair<int, int>, int> middle;
  std::vector<Eigen::VectorXd> added;
  for (int c = 0; c < mesh.num_cells(); ++c) {
    out.cells.col(c).head(mesh.dim + 1) = mesh.cells.col(c);
    for (int e = 0; e < (mesh.dim == 3 ? 6 : 3); ++e) {
      const int a = mesh.cells(mesh.dim == 3 ? tet[e][0] : tri[e][0], c);
      const int b = mesh.cells(mesh.dim == 3 ? tet[e][1] : tri[e][1], c);
      const auto [it, fresh] = middle.emplace(std::minmax(a, b), mesh.num_nodes() + static_cast<int>(added.size()));
      if (fresh) added.emplace_back((mesh.points.col(a) + mesh.points.col(b)) / 2);
      out.cells(mesh.dim + 1 + e, c) = it->second;
    }
  }
  out.points.conservativeResize(mesh.dim, mesh.num_nodes() + static_cast<Eigen::Index>(added.size()));
  for (std::size_t k = 0; k < added.size(); ++k)
    out.points.col(mesh.num_nodes() + static_cast<Eigen::Index>(k)) = added[k];
  return out;
}

/// Closed, outward oriented boundary and positive cells; returns the volume.
inline double check_mesh_consistency(const Mesh& mesh) {
  EXPECT_NO_THROW(check_orientation(mesh, "mesh"));
  const double volume = total_volume(mesh);
  const Eigen::MatrixXi boundary = boundary_facets(mesh);
  EXPECT_NEAR(divergence_volume(mesh, boundary), volume, 1e-9 * std::abs(volume));
  const double scale = std::pow(std::abs(volume), (mesh.dim - 1.0) / mesh.dim);
  EXPECT_LT(total_area_normal(mesh, boundary).norm(), 1e-9 * scale);
  return volume;
}

}  // namespace conserve::mesh::test
