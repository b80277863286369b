#include "contact/surface.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <set>
#include <tuple>

#include "core/error.hpp"
#include "mesh/topology.hpp"

namespace conserve::contact {

namespace {

/// All boundary facets of a body with cells, outward, in global numbers.
template <int D>
Eigen::MatrixXi body_boundary(const model::Model<D>& model, const model::Body& body) {
  mesh::Mesh cells_only;
  cells_only.dim = D;
  cells_only.points = model.X.middleCols(body.first_node, body.num_nodes);
  cells_only.cells = model.cells.middleCols(body.first_cell, body.num_cells).array() - body.first_node;
  return mesh::boundary_facets(cells_only).array() + body.first_node;
}

/// The facet's vertices (its first `dim` nodes) sorted, as a key for "same
/// facet, any orientation".
std::array<int, 3> facet_key(const Eigen::MatrixXi& facets, int f, int dim) {
  std::array<int, 3> key{-1, -1, -1};
  for (int i = 0; i < dim; ++i) key[static_cast<std::size_t>(i)] = facets(i, f);
  std::sort(key.begin(), key.begin() + dim);
  return key;
}

/// The union of all facet groups of a body without cells (duplicates,
/// in either orientation, kept once: the first one met).
Eigen::MatrixXi union_of_groups(const model::Body& body, int dim) {
  std::set<std::array<int, 3>> seen;
  std::vector<int> columns;  // (group-major) facet columns kept
  const Eigen::Index rows = body.facet_groups.empty() ? dim : body.facet_groups.begin()->second.rows();
  Eigen::MatrixXi all(rows, 0);
  for (const auto& [name, group] : body.facet_groups) {
    const Eigen::Index start = all.cols();
    all.conservativeResize(rows, start + group.cols());
    all.rightCols(group.cols()) = group;
    for (int f = 0; f < group.cols(); ++f) {
      const auto key = facet_key(all, static_cast<int>(start) + f, dim);
      if (seen.insert(key).second) columns.push_back(static_cast<int>(start) + f);
    }
  }
  Eigen::MatrixXi out(rows, static_cast<Eigen::Index>(columns.size()));
  for (std::size_t j = 0; j < columns.size(); ++j) out.col(static_cast<Eigen::Index>(j)) = all.col(columns[j]);
  return out;
}

std::string group_names(const model::Body& body) {
  std::string names = "boundary";
  for (const auto& [name, facets] : body.facet_groups)
    if (name != "boundary") names += ", " + name;
  return names;
}

/// The facets of `group` (see make_surface), outward oriented.
template <int D>
Eigen::MatrixXi group_facets(const model::Model<D>& model, const model::Body& body, const std::string& group) {
  const bool has_cells = body.num_cells > 0;
  const auto it = body.facet_groups.find(group);
  if (group == "boundary" && it == body.facet_groups.end())
    return has_cells ? body_boundary(model, body) : union_of_groups(body, D);
  if (it == body.facet_groups.end())
    throw InputError(fmt::format("contact surface: body '{}' has no facet group '{}' (groups: {})", body.name, group,
                                 group_names(body)));
  Eigen::MatrixXi facets = it->second;
  if (facets.cols() > 0 && has_cells) {
    const int off = mesh::orient_outward(facets, body_boundary(model, body));
    if (off > 0)
      throw InputError(
          fmt::format("contact surface: body '{}', group '{}': {} of its {} facets are not on the body's "
                      "boundary",
                      body.name, group, off, facets.cols()));
  }
  return facets;
}

/// Whether every dof of every node is held (prescribed, or a free rigid body's).
template <int D>
bool all_prescribed(const std::vector<int>& nodes, std::vector<int> dofs) {
  std::sort(dofs.begin(), dofs.end());
  return std::all_of(nodes.begin(), nodes.end(), [&](int node) {
    for (int i = 0; i < D; ++i)
      if (!std::binary_search(dofs.begin(), dofs.end(), model::dof<D>(node, i))) return false;
    return true;
  });
}

/// One side of a facet (an edge in 3D, a vertex in 2D) opposite local node k.
struct Side {
  std::int64_t key;
  int facet;
  int local;
  bool operator<(const Side& other) const {
    return std::tie(key, facet, local) < std::tie(other.key, other.facet, other.local);
  }
};

Side side_of(const Eigen::MatrixXi& facets, int f, int k, int dim) {
  if (dim == 2) return {facets(1 - k, f), f, k};
  const std::int64_t a = facets((k + 1) % 3, f);
  const std::int64_t b = facets((k + 2) % 3, f);
  return {std::min(a, b) * (std::int64_t{1} << 32) + std::max(a, b), f, k};
}

void build_neighbours(ContactSurface& surface, int dim) {
  const int n = surface.num_facets();
  std::vector<Side> sides;
  sides.reserve(static_cast<std::size_t>(dim) * static_cast<std::size_t>(n));
  for (int f = 0; f < n; ++f)
    for (int k = 0; k < dim; ++k) sides.push_back(side_of(surface.facets, f, k, dim));
  std::sort(sides.begin(), sides.end());
  surface.facet_neighbours = Eigen::MatrixXi::Constant(dim, n, -1);
  for (std::size_t i = 0; i < sides.size();) {
    std::size_t j = i;
    while (j < sides.size() && sides[j].key == sides[i].key) ++j;
    if (j - i == 2) {  // manifold: exactly two facets share it
      const Side& a = sides[i];
      const Side& b = sides[i + 1];
      surface.facet_neighbours(a.local, a.facet) = b.facet;
      surface.facet_neighbours(b.local, b.facet) = a.facet;
    }
    i = j;
  }
}

}  // namespace

int ContactSurface::local_node(int global) const {
  const auto it = std::lower_bound(nodes.begin(), nodes.end(), global);
  return it != nodes.end() && *it == global ? static_cast<int>(it - nodes.begin()) : -1;
}

void build_adjacency(ContactSurface& surface, int dim) {
  const Eigen::MatrixXi& facets = surface.facets;
  surface.nodes.assign(facets.data(), facets.data() + facets.size());
  std::sort(surface.nodes.begin(), surface.nodes.end());
  surface.nodes.erase(std::unique(surface.nodes.begin(), surface.nodes.end()), surface.nodes.end());
  surface.node_facets.assign(surface.nodes.size(), {});
  for (int f = 0; f < facets.cols(); ++f)
    for (int i = 0; i < facets.rows(); ++i)
      surface.node_facets[static_cast<std::size_t>(surface.local_node(facets(i, f)))].push_back(f);
  build_neighbours(surface, dim);
}

template <int D>
ContactSurface make_surface(const model::Model<D>& model, int body, const std::string& group) {
  if (body < 0 || body >= static_cast<int>(model.bodies.size()))
    throw InputError(fmt::format("contact surface: no body number {} (the model has {})", body, model.bodies.size()));
  const model::Body& b = model.bodies[static_cast<std::size_t>(body)];
  ContactSurface surface;
  surface.name = b.name + ":" + group;
  surface.body = body;
  surface.facets = group_facets(model, b, group);
  if (surface.facets.cols() == 0)
    throw InputError(fmt::format("contact surface: body '{}', group '{}' has no facets", b.name, group));
  build_adjacency(surface, D);
  surface.rigid = all_prescribed<D>(surface.nodes, model.held_dofs());
  return surface;
}

template <int D>
std::vector<double> facet_sizes(const ContactSurface& surface, const Eigen::Matrix<double, D, Eigen::Dynamic>& x) {
  std::vector<double> size(static_cast<std::size_t>(surface.num_facets()), 0.0);
  for (int f = 0; f < surface.num_facets(); ++f)
    for (int a = 0; a < D; ++a)
      for (int b = a + 1; b < D; ++b)
        size[static_cast<std::size_t>(f)] =
            std::max(size[static_cast<std::size_t>(f)], (x.col(surface.facets(a, f)) - x.col(surface.facets(b, f))).norm());
  return size;
}

template <int D>
double median_facet_size(const ContactSurface& surface, const Eigen::Matrix<double, D, Eigen::Dynamic>& x) {
  std::vector<double> sizes = facet_sizes<D>(surface, x);
  if (sizes.empty()) return 0.0;
  const auto middle = sizes.begin() + static_cast<std::ptrdiff_t>(sizes.size() / 2);
  std::nth_element(sizes.begin(), middle, sizes.end());
  return *middle;
}

template double median_facet_size<2>(const ContactSurface&, const Eigen::Matrix<double, 2, Eigen::Dynamic>&);
template double median_facet_size<3>(const ContactSurface&, const Eigen::Matrix<double, 3, Eigen::Dynamic>&);
template std::vector<double> facet_sizes<2>(const ContactSurface&, const Eigen::Matrix<double, 2, Eigen::Dynamic>&);
template std::vector<double> facet_sizes<3>(const ContactSurface&, const Eigen::Matrix<double, 3, Eigen::Dynamic>&);
template ContactSurface make_surface<2>(const model::Model<2>&, int, const std::string&);
template ContactSurface make_surface<3>(const model::Model<3>&, int, const std::string&);

}  // namespace conserve::contact
