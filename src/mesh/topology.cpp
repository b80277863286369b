#include "mesh/topology.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <stdexcept>
#include <unordered_map>

#include "core/error.hpp"

namespace conserve::mesh {

namespace {

/// Local node numbers of the outward oriented facets of a positively
/// oriented simplex: facet k is opposite node k.
constexpr int kTetFaces[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
constexpr int kTriEdges[3][2] = {{1, 2}, {2, 0}, {0, 1}};

using FacetKey = std::array<int, 3>;

struct FacetKeyHash {
  std::size_t operator()(const FacetKey& k) const noexcept {
    std::size_t h = 0;
    for (const int v : k) h = h * 0x9E3779B97F4A7C15ULL + static_cast<std::size_t>(v) + (h >> 29);
    return h;
  }
};

/// Facet `k` of cell `c`, outward oriented (dim entries used).
FacetKey oriented_facet(const Mesh& mesh, int c, int k) {
  FacetKey f{-1, -1, -1};
  for (int i = 0; i < mesh.dim; ++i) f[i] = mesh.cells(mesh.dim == 3 ? kTetFaces[k][i] : kTriEdges[k][i], c);
  return f;
}

/// The facet's first `dim` nodes in increasing order (unused entries stay -1).
FacetKey sorted_key(FacetKey f, int dim) {
  if (f[0] > f[1]) std::swap(f[0], f[1]);
  if (dim == 3 && f[1] > f[2]) std::swap(f[1], f[2]);
  if (dim == 3 && f[0] > f[1]) std::swap(f[0], f[1]);
  return f;
}

double longest_edge(const Mesh& mesh, int cell) {
  double longest = 0.0;
  for (int i = 0; i <= mesh.dim; ++i)
    for (int j = i + 1; j <= mesh.dim; ++j)
      longest = std::max(longest, (mesh.points.col(mesh.cells(i, cell)) - mesh.points.col(mesh.cells(j, cell))).norm());
  return longest;
}

/// Keeps the columns of `facets` whose nodes all map to a new index, renumbered.
Eigen::MatrixXi restrict_facets(const Eigen::MatrixXi& facets, const std::vector<int>& new_index) {
  const auto kept_node = [&](int v) {
    return v >= 0 && v < static_cast<int>(new_index.size()) && new_index[static_cast<std::size_t>(v)] >= 0;
  };
  std::vector<int> kept;
  for (int f = 0; f < facets.cols(); ++f)
    if (std::all_of(facets.col(f).data(), facets.col(f).data() + facets.rows(), kept_node)) kept.push_back(f);
  Eigen::MatrixXi out(facets.rows(), static_cast<Eigen::Index>(kept.size()));
  for (std::size_t j = 0; j < kept.size(); ++j)
    for (int i = 0; i < facets.rows(); ++i) out(i, static_cast<Eigen::Index>(j)) = new_index[facets(i, kept[j])];
  return out;
}

/// New index of each node used by `cells`, in increasing old order (-1: unused).
std::vector<int> number_nodes_of(const Mesh& mesh, const std::vector<int>& cells) {
  std::vector<bool> used(static_cast<std::size_t>(mesh.num_nodes()), false);
  for (const int c : cells)
    for (int i = 0; i <= mesh.dim; ++i) used[static_cast<std::size_t>(mesh.cells(i, c))] = true;
  std::vector<int> new_index(used.size(), -1);
  int next = 0;
  for (std::size_t n = 0; n < used.size(); ++n)
    if (used[n]) new_index[n] = next++;
  return new_index;
}

/// Cell groups renumbered by `new_cell` (-1: cell dropped); empty groups dropped.
std::map<std::string, std::vector<int>> restrict_cell_groups(const std::map<std::string, std::vector<int>>& groups,
                                                             const std::vector<int>& new_cell) {
  std::map<std::string, std::vector<int>> out;
  for (const auto& [name, members] : groups) {
    std::vector<int> kept;
    for (const int c : members)
      if (new_cell[static_cast<std::size_t>(c)] >= 0) kept.push_back(new_cell[static_cast<std::size_t>(c)]);
    if (!kept.empty()) out[name] = std::move(kept);
  }
  return out;
}

std::vector<int> selected_cells(const Mesh& mesh, const std::string& group) {
  if (group.empty()) {
    std::vector<int> all(static_cast<std::size_t>(mesh.num_cells()));
    for (int c = 0; c < mesh.num_cells(); ++c) all[static_cast<std::size_t>(c)] = c;
    return all;
  }
  const auto it = mesh.cell_groups.find(group);
  if (it != mesh.cell_groups.end()) return it->second;
  std::string names;
  for (const auto& [name, cells] : mesh.cell_groups) names += (names.empty() ? "" : ", ") + name;
  throw InputError(fmt::format("mesh: unknown cell group '{}' (available: {})", group, names.empty() ? "none" : names));
}

}  // namespace

Eigen::MatrixXi boundary_facets(const Mesh& mesh) {
  // Every cell's facets by their sorted nodes, sorted: a facet that comes
  // once is on the boundary (an interior one twice). A facet is named by
  // its use c·(dim+1) + k, and the boundary keeps the order of the uses.
  const int dim = mesh.dim, per = dim + 1;
  struct Use {
    FacetKey key;
    int use;
  };
  std::vector<Use> uses(static_cast<std::size_t>(mesh.num_cells()) * static_cast<std::size_t>(per));
#pragma omp parallel for schedule(static) if (mesh.num_cells() >= 65536)
  for (int c = 0; c < mesh.num_cells(); ++c)
    for (int k = 0; k < per; ++k)
      uses[static_cast<std::size_t>(c) * per + k] = {sorted_key(oriented_facet(mesh, c, k), dim), c * per + k};
  std::sort(uses.begin(), uses.end(), [](const Use& a, const Use& b) { return a.key < b.key; });
  std::vector<int> once;
  for (std::size_t first = 0, last = 0; first < uses.size(); first = last) {
    last = first + 1;
    while (last < uses.size() && uses[last].key == uses[first].key) ++last;
    if (last == first + 1) once.push_back(uses[first].use);
  }
  uses = {};
  std::sort(once.begin(), once.end());
  Eigen::MatrixXi out(dim, static_cast<Eigen::Index>(once.size()));
  for (std::size_t f = 0; f < once.size(); ++f) {
    const FacetKey facet = oriented_facet(mesh, once[f] / per, once[f] % per);
    for (int i = 0; i < dim; ++i) out(i, static_cast<Eigen::Index>(f)) = facet[static_cast<std::size_t>(i)];
  }
  return out;
}

int orient_outward(Eigen::MatrixXi& facets, const Eigen::MatrixXi& boundary) {
  const int dim = static_cast<int>(boundary.rows());
  const auto key_of = [dim](const auto& column) {
    FacetKey f{-1, -1, -1};
    for (int i = 0; i < dim; ++i) f[static_cast<std::size_t>(i)] = column(i);
    return sorted_key(f, dim);
  };
  std::unordered_map<FacetKey, int, FacetKeyHash> column;
  column.reserve(static_cast<std::size_t>(boundary.cols()));
  for (int f = 0; f < boundary.cols(); ++f) column.emplace(key_of(boundary.col(f)), f);
  int not_on_boundary = 0;
  for (int f = 0; f < facets.cols(); ++f) {
    const auto it = column.find(key_of(facets.col(f)));
    if (it == column.end())
      ++not_on_boundary;
    else
      facets.col(f) = boundary.col(it->second);
  }
  return not_on_boundary;
}

Mesh extract(const Mesh& mesh, const std::string& group) {
  const std::vector<int> cells = selected_cells(mesh, group);
  const std::vector<int> new_index = number_nodes_of(mesh, cells);
  Mesh out;
  out.dim = mesh.dim;
  out.points.resize(mesh.dim, std::count_if(new_index.begin(), new_index.end(), [](int i) { return i >= 0; }));
  for (int n = 0; n < mesh.num_nodes(); ++n)
    if (new_index[static_cast<std::size_t>(n)] >= 0)
      out.points.col(new_index[static_cast<std::size_t>(n)]) = mesh.points.col(n);
  out.cells.resize(mesh.dim + 1, static_cast<Eigen::Index>(cells.size()));
  std::vector<int> new_cell(static_cast<std::size_t>(mesh.num_cells()), -1);
  for (std::size_t j = 0; j < cells.size(); ++j) {
    new_cell[static_cast<std::size_t>(cells[j])] = static_cast<int>(j);
    for (int i = 0; i <= mesh.dim; ++i)
      out.cells(i, static_cast<Eigen::Index>(j)) = new_index[static_cast<std::size_t>(mesh.cells(i, cells[j]))];
  }
  out.cell_groups = restrict_cell_groups(mesh.cell_groups, new_cell);
  for (const auto& [name, group_facets] : mesh.facet_groups) {
    FacetGroup restricted{restrict_facets(group_facets.facets, new_index)};
    if (restricted.facets.cols() > 0) out.facet_groups[name] = std::move(restricted);
  }
  return out;
}

void node_graph(const Mesh& mesh, std::vector<int>& offsets, std::vector<int>& neighbours) {
  std::vector<std::vector<int>> adjacent(static_cast<std::size_t>(mesh.num_nodes()));
  for (int c = 0; c < mesh.num_cells(); ++c)
    for (int a = 0; a <= mesh.dim; ++a)
      for (int b = 0; b <= mesh.dim; ++b)
        if (a != b) adjacent[static_cast<std::size_t>(mesh.cells(a, c))].push_back(mesh.cells(b, c));
  offsets.assign(1, 0);
  neighbours.clear();
  for (auto& list : adjacent) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
    neighbours.insert(neighbours.end(), list.begin(), list.end());
    offsets.push_back(static_cast<int>(neighbours.size()));
  }
}

Mesh renumbered(const Mesh& mesh, const std::vector<int>& order) {
  const auto n = static_cast<std::size_t>(mesh.num_nodes());
  std::vector<int> new_index(n, -1);
  if (order.size() != n) throw std::invalid_argument("renumbered: the order does not list every node");
  for (std::size_t k = 0; k < n; ++k) {
    const int v = order[k];
    if (v < 0 || v >= mesh.num_nodes() || new_index[static_cast<std::size_t>(v)] >= 0)
      throw std::invalid_argument("renumbered: the order is not a permutation of the nodes");
    new_index[static_cast<std::size_t>(v)] = static_cast<int>(k);
  }
  Mesh out;
  out.dim = mesh.dim;
  out.points.resize(mesh.points.rows(), mesh.points.cols());
  for (std::size_t k = 0; k < n; ++k) out.points.col(static_cast<Eigen::Index>(k)) = mesh.points.col(order[k]);
  std::vector<int> lowest(static_cast<std::size_t>(mesh.num_cells()));
  for (int c = 0; c < mesh.num_cells(); ++c) {
    int low = mesh.num_nodes();
    for (int a = 0; a <= mesh.dim; ++a) low = std::min(low, new_index[static_cast<std::size_t>(mesh.cells(a, c))]);
    lowest[static_cast<std::size_t>(c)] = low;
  }
  std::vector<int> cell_order(lowest.size());
  for (std::size_t c = 0; c < cell_order.size(); ++c) cell_order[c] = static_cast<int>(c);
  std::stable_sort(cell_order.begin(), cell_order.end(), [&](int a, int b) {
    return lowest[static_cast<std::size_t>(a)] < lowest[static_cast<std::size_t>(b)];
  });
  std::vector<int> new_cell(cell_order.size());
  out.cells.resize(mesh.cells.rows(), mesh.cells.cols());
  for (std::size_t j = 0; j < cell_order.size(); ++j) {
    new_cell[static_cast<std::size_t>(cell_order[j])] = static_cast<int>(j);
    for (int a = 0; a <= mesh.dim; ++a)  // the local order, and so the orientation, is kept
      out.cells(a, static_cast<Eigen::Index>(j)) = new_index[static_cast<std::size_t>(mesh.cells(a, cell_order[j]))];
  }
  out.cell_groups = restrict_cell_groups(mesh.cell_groups, new_cell);
  for (auto& [name, members] : out.cell_groups) std::sort(members.begin(), members.end());
  for (const auto& [name, group_facets] : mesh.facet_groups)
    out.facet_groups[name] = FacetGroup{restrict_facets(group_facets.facets, new_index)};
  return out;
}

double signed_volume(const Mesh& mesh, int cell) {
  const auto p = [&](int i) { return mesh.points.col(mesh.cells(i, cell)); };
  if (mesh.dim == 2) {
    const Eigen::Vector2d a = p(1) - p(0), b = p(2) - p(0);
    return 0.5 * (a.x() * b.y() - a.y() * b.x());
  }
  const Eigen::Vector3d a = p(1) - p(0), b = p(2) - p(0), c = p(3) - p(0);
  return a.dot(b.cross(c)) / 6.0;
}

CellOrientation cell_orientation(const Mesh& mesh, int cell) {
  const double volume = signed_volume(mesh, cell);
  const double h = longest_edge(mesh, cell);
  if (!(std::abs(volume) > 1e-12 * std::pow(h, mesh.dim))) return CellOrientation::degenerate;
  return volume > 0.0 ? CellOrientation::positive : CellOrientation::inverted;
}

double total_volume(const Mesh& mesh) {
  double sum = 0.0;
  for (int c = 0; c < mesh.num_cells(); ++c) sum += signed_volume(mesh, c);
  return sum;
}

void check_orientation(const Mesh& mesh, const std::string& name) {
  for (int c = 0; c < mesh.num_cells(); ++c) {
    const CellOrientation o = cell_orientation(mesh, c);
    if (o == CellOrientation::positive) continue;
    throw InputError(fmt::format("{}: cell {} is {} (signed volume {:g})", name, c,
                                 o == CellOrientation::inverted ? "inverted" : "degenerate", signed_volume(mesh, c)));
  }
}

}  // namespace conserve::mesh
