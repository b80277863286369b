#pragma once
// Helpers shared by the mesh tests: file access and geometric checks.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <array>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

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

/// Σ (1/dim) x·n dA over the facets: the enclosed volume (area in 2D) when
/// they form a closed, outward oriented surface.
inline double divergence_volume(const Mesh& mesh, const Eigen::MatrixXi& facets) {
  double sum = 0.0;
  for (int f = 0; f < facets.cols(); ++f) {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int i = 0; i < mesh.dim; ++i) centroid.head(mesh.dim) += mesh.points.col(facets(i, f)) / mesh.dim;
    sum += centroid.dot(area_normal(mesh, facets, f)) / mesh.dim;
  }
  return sum;
}

/// Σ n dA over the facets (zero for a closed surface).
inline Eigen::Vector3d total_area_normal(const Mesh& mesh, const Eigen::MatrixXi& facets) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int f = 0; f < facets.cols(); ++f) sum += area_normal(mesh, facets, f);
  return sum;
}

/// Each facet of `group` is a column of `boundary` with the same node order
/// up to a cyclic rotation (so the same orientation).
inline void expect_oriented_subset(const Eigen::MatrixXi& group, const Eigen::MatrixXi& boundary) {
  const auto canonical = [](Eigen::VectorXi f) {  // triangles: rotate the smallest node first
    std::array<int, 3> out{-1, -1, -1};
    Eigen::Index first = 0;
    if (f.size() == 3) f.minCoeff(&first);
    for (Eigen::Index i = 0; i < f.size(); ++i) out[static_cast<std::size_t>(i)] = f((first + i) % f.size());
    return out;
  };
  std::map<std::array<int, 3>, int> present;
  for (int f = 0; f < boundary.cols(); ++f) ++present[canonical(boundary.col(f))];
  for (int f = 0; f < group.cols(); ++f) EXPECT_TRUE(present.contains(canonical(group.col(f)))) << "facet " << f;
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
