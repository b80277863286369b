// Bare surfaces: construction, the orientation check and the statement of
// which way the normals point.
#include "mesh/surface_mesh.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace conserve::mesh {

namespace {

Eigen::Vector3d point3(const Eigen::MatrixXd& points, int node) {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  p.head(points.rows()) = points.col(node);
  return p;
}

/// The facet's normal scaled by its area (3D) or length (2D).
Eigen::Vector3d area_normal(const Eigen::MatrixXd& points, const Eigen::MatrixXi& facets, int f) {
  const Eigen::Vector3d x0 = point3(points, facets(0, f)), t = point3(points, facets(1, f)) - x0;
  if (facets.rows() == 2) return {t.y(), -t.x(), 0.0};
  return 0.5 * t.cross(point3(points, facets(2, f)) - x0);
}

/// A directed side as a key: the edge from → to in 3D; in 2D the node with
/// whether the segment starts or ends there.
std::uint64_t directed_key(int from, int to) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(from)) << 32) | static_cast<std::uint32_t>(to);
}

std::uint64_t undirected_key(int a, int b) { return directed_key(std::min(a, b), std::max(a, b)); }

/// Connected components of the facets' nodes (union-find); returns their count.
int count_pieces(const Eigen::MatrixXi& facets) {
  std::vector<int> parent(facets.size() > 0 ? facets.maxCoeff() + 1 : 0, -1);  // -1: no facet uses it
  const auto root = [&parent](int v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (Eigen::Index k = 0; k < facets.size(); ++k) parent[facets.data()[k]] = facets.data()[k];
  for (int f = 0; f < facets.cols(); ++f)
    for (int i = 1; i < facets.rows(); ++i) parent[root(facets(i, f))] = root(facets(0, f));
  int pieces = 0;
  for (int v = 0; v < static_cast<int>(parent.size()); ++v) pieces += parent[v] == v;
  return pieces;
}

/// Whether every side (edge in 3D, node in 2D) is shared by two or more facets.
bool has_no_border(const Eigen::MatrixXi& facets) {
  std::unordered_map<std::uint64_t, int> uses;
  for (int f = 0; f < facets.cols(); ++f)
    for (int i = 0; i < facets.rows(); ++i) {
      const int a = facets(i, f), b = facets((i + 1) % facets.rows(), f);
      ++uses[facets.rows() == 2 ? directed_key(a, 0) : undirected_key(a, b)];
    }
  return std::all_of(uses.begin(), uses.end(), [](const auto& entry) { return entry.second >= 2; });
}

std::string rounded(double v) { return fmt::format("{:.2f}", std::abs(v) < 0.005 ? 0.0 : v); }

}  // namespace

Mesh bare_surface(int dim, Eigen::MatrixXd points, Eigen::MatrixXi facets) {
  Mesh mesh;
  mesh.dim = dim;
  mesh.points = std::move(points);
  mesh.cells.resize(dim + 1, 0);
  mesh.cell_groups["body"] = {};
  mesh.facet_groups["surface"].facets = facets;
  mesh.facet_groups["boundary"].facets = std::move(facets);
  return mesh;
}

void flip_normals(Mesh& mesh) {
  for (auto& [name, group] : mesh.facet_groups) {
    Eigen::MatrixXi& facets = group.facets;
    if (facets.rows() < 2) continue;
    if (mesh.dim == 2) {
      facets.row(0).swap(facets.row(1));  // a line3's middle (row 2) stays
      continue;
    }
    facets.row(1).swap(facets.row(2));
    if (facets.rows() == 6) facets.row(3).swap(facets.row(5));  // tri6: (0,1) ↔ (2,0)
  }
}

std::optional<OrientationClash> orientation_clash(const Eigen::MatrixXi& facets) {
  const bool plane = facets.rows() == 2;
  std::unordered_map<std::uint64_t, int> first_use;  // directed side → facet
  first_use.reserve(static_cast<std::size_t>(facets.size()));
  for (int f = 0; f < facets.cols(); ++f)
    for (int i = 0; i < (plane ? 2 : 3); ++i) {
      // 2D: side i = 0 is where the segment starts, i = 1 where it ends
      const int from = plane ? (i == 0 ? facets(0, f) : -1) : facets(i, f);
      const int to = plane ? (i == 0 ? -1 : facets(1, f)) : facets((i + 1) % 3, f);
      const auto [it, fresh] = first_use.emplace(directed_key(from, to), f);
      if (!fresh) return OrientationClash{it->second, f, from, to};
    }
  return std::nullopt;
}

std::optional<int> degenerate_facet(const Eigen::MatrixXd& points, const Eigen::MatrixXi& facets) {
  const double diagonal = points.cols() > 0 ? (points.rowwise().maxCoeff() - points.rowwise().minCoeff()).norm() : 0.0;
  for (int f = 0; f < facets.cols(); ++f) {
    const double measure = area_normal(points, facets, f).norm();
    double scale = diagonal;
    if (facets.rows() == 3) {
      scale = 0.0;
      for (int i = 0; i < 3; ++i)
        scale = std::max(scale, (points.col(facets(i, f)) - points.col(facets((i + 1) % 3, f))).squaredNorm());
    }
    if (!(measure > 1e-12 * scale)) return f;
  }
  return std::nullopt;
}

SurfaceSummary summarize_surface(const Eigen::MatrixXd& points, const Eigen::MatrixXi& facets) {
  SurfaceSummary s;
  s.dim = static_cast<int>(facets.rows());
  s.facets = static_cast<int>(facets.cols());
  s.pieces = count_pieces(facets);
  s.closed = s.facets > 0 && has_no_border(facets);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int f = 0; f < facets.cols(); ++f) {
    const Eigen::Vector3d n = area_normal(points, facets, f);
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int i = 0; i < facets.rows(); ++i) centroid += point3(points, facets(i, f)) / static_cast<double>(s.dim);
    sum += n;
    s.measure += n.norm();
    s.enclosed += centroid.dot(n) / s.dim;
  }
  if (s.measure > 0.0) s.mean_normal = sum / s.measure;
  return s;
}

std::string describe_surface(const SurfaceSummary& s) {
  const std::string what =
      fmt::format("{}{} of {} {}{}", s.closed ? "closed " : "", s.dim == 3 ? "surface" : "line", s.facets,
                  s.dim == 3 ? "triangles" : "segments", s.pieces > 1 ? fmt::format(" in {} pieces", s.pieces) : "");
  if (s.closed)
    return fmt::format("{}, normals point {} (enclosing {:.3g} {}): the slaves belong {}", what,
                       s.enclosed >= 0 ? "outward" : "inward", std::abs(s.enclosed), s.dim == 3 ? "m³" : "m²",
                       s.enclosed >= 0 ? "outside" : "inside");
  const Eigen::Vector3d& n = s.mean_normal;
  const std::string mean = s.dim == 3 ? fmt::format("({}, {}, {})", rounded(n.x()), rounded(n.y()), rounded(n.z()))
                                      : fmt::format("({}, {})", rounded(n.x()), rounded(n.y()));
  if (n.norm() < 0.1)
    return fmt::format(
        "{}, normals with no main direction (area-weighted mean normal {}): the slaves belong on the "
        "side each facet's normal points to",
        what, mean);
  Eigen::Index axis = 0;
  n.cwiseAbs().maxCoeff(&axis);
  return fmt::format("{}, normals point mostly {}{} (area-weighted mean normal {}): the slaves belong on that side",
                     what, n(axis) > 0 ? '+' : '-', "xyz"[axis], mean);
}

}  // namespace conserve::mesh
