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
/// The midside node of each edge of a quadratic simplex, {node, a, b}, in
/// Gmsh's order (mesh.hpp).
constexpr int kTri6Midsides[3][3] = {{3, 0, 1}, {4, 1, 2}, {5, 2, 0}};
constexpr int kTet10Midsides[6][3] = {{4, 0, 1}, {5, 1, 2}, {6, 2, 0}, {7, 3, 0}, {8, 3, 2}, {9, 3, 1}};
/// The same facets of a quadratic simplex (tet10 faces as tri6, tri6 edges
/// as line3): the vertices of kTetFaces / kTriEdges, then the midside node
/// of each edge of the facet in its vertex order, (v0,v1), (v1,v2), (v2,v0);
/// e.g. face 0 = (1, 2, 3): 5 = (1,2), 8 = (3,2), 9 = (3,1).
constexpr int kTet10Faces[4][6] = {{1, 2, 3, 5, 8, 9}, {0, 3, 2, 7, 8, 6}, {0, 1, 3, 4, 9, 7}, {0, 2, 1, 6, 5, 4}};
constexpr int kTri6Edges[3][3] = {{1, 2, 4}, {2, 0, 5}, {0, 1, 3}};

/// The midside node of edge (a, b) of a tet10 (tri6: the same for a, b < 3), or -1.
constexpr int midside_of(int a, int b) {
  for (const auto& e : kTet10Midsides)
    if ((e[1] == a && e[2] == b) || (e[1] == b && e[2] == a)) return e[0];
  return -1;
}

/// The quadratic facet tables hold the linear ones' vertices, then the
/// midside node of each facet edge in the facet's vertex order.
constexpr bool quadratic_facets_match() {
  for (int k = 0; k < 4; ++k)
    for (int i = 0; i < 3; ++i)
      if (kTet10Faces[k][i] != kTetFaces[k][i] ||
          kTet10Faces[k][3 + i] != midside_of(kTetFaces[k][i], kTetFaces[k][(i + 1) % 3]))
        return false;
  for (int k = 0; k < 3; ++k) {
    if (kTri6Edges[k][0] != kTriEdges[k][0] || kTri6Edges[k][1] != kTriEdges[k][1]) return false;
    bool found = false;
    for (const auto& e : kTri6Midsides)
      found = found || (e[0] == kTri6Edges[k][2] && ((e[1] == kTriEdges[k][0] && e[2] == kTriEdges[k][1]) ||
                                                     (e[1] == kTriEdges[k][1] && e[2] == kTriEdges[k][0])));
    if (!found) return false;
  }
  for (int e = 0; e < 3; ++e)  // tri6's midsides are tet10's first three
    if (kTri6Midsides[e][0] + 1 != kTet10Midsides[e][0] || kTri6Midsides[e][1] != kTet10Midsides[e][1] ||
        kTri6Midsides[e][2] != kTet10Midsides[e][2])
      return false;
  return true;
}
static_assert(quadratic_facets_match(), "quadratic facet tables disagree with the linear ones");

using FacetKey = std::array<int, 3>;    ///< a facet's vertices, sorted (-1: unused)
using FacetNodes = std::array<int, 6>;  ///< a facet's nodes, outward order (-1: unused)

struct FacetKeyHash {
  std::size_t operator()(const FacetKey& k) const noexcept {
    std::size_t h = 0;
    for (const int v : k) h = h * 0x9E3779B97F4A7C15ULL + static_cast<std::size_t>(v) + (h >> 29);
    return h;
  }
};

/// Local node `i` of the outward facet `k` of a cell of dimension `dim`.
int facet_local(int dim, int order, int k, int i) {
  if (dim == 3) return order == 2 ? kTet10Faces[k][i] : kTetFaces[k][i];
  return order == 2 ? kTri6Edges[k][i] : kTriEdges[k][i];
}

/// Facet `k` of cell `c`, outward oriented (facet_nodes(dim, order) entries used).
FacetNodes oriented_facet(const Mesh& mesh, int order, int c, int k) {
  FacetNodes f{-1, -1, -1, -1, -1, -1};
  for (int i = 0; i < facet_nodes(mesh.dim, order); ++i)
    f[static_cast<std::size_t>(i)] = mesh.cells(facet_local(mesh.dim, order, k, i), c);
  return f;
}

/// The first `n` (2 or 3) entries of `f` in increasing order (unused entries stay -1).
FacetKey sorted_key(FacetKey f, int n) {
  if (f[0] > f[1]) std::swap(f[0], f[1]);
  if (n == 3 && f[1] > f[2]) std::swap(f[1], f[2]);
  if (n == 3 && f[0] > f[1]) std::swap(f[0], f[1]);
  return f;
}

/// A facet's key: its `dim` vertices, sorted.
FacetKey vertex_key(const FacetNodes& f, int dim) { return sorted_key({f[0], f[1], dim == 3 ? f[2] : -1}, dim); }

double longest_edge(const Mesh& mesh, int cell) {
  double longest = 0.0;
  for (int i = 0; i <= mesh.dim; ++i)
    for (int j = i + 1; j <= mesh.dim; ++j)
      longest = std::max(longest, (mesh.points.col(mesh.cells(i, cell)) - mesh.points.col(mesh.cells(j, cell))).norm());
  return longest;
}

/// Barycentric coordinates λ_0 … λ_dim of a point of the reference simplex
/// (λ_0 = 1 − Σ ξ, λ_i = ξ_i; λ_3 unused in 2D).
using Barycentric = std::array<double, 4>;

/// det ∂x/∂ξ of quadratic cell `cell` at `l`. Gmsh's shape functions are
/// N_a = λ_a (2 λ_a − 1) at vertex a and N_m = 4 λ_a λ_b at the midside node
/// m of edge (a, b), so ∂x/∂λ_a = (4 λ_a − 1) x_a + Σ_{edges (a, b)} 4 λ_b x_m
/// and ∂x/∂ξ_j = ∂x/∂λ_j − ∂x/∂λ_0. The nodes are taken relative to vertex 0
/// (Σ_n ∂N_n/∂ξ = 0), which keeps the digits of a cell far from the origin.
double jacobian_determinant(const Mesh& mesh, int cell, const Barycentric& l) {
  const int dim = mesh.dim;
  const auto x = [&](int local) {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    p.head(dim) = mesh.points.col(mesh.cells(local, cell)) - mesh.points.col(mesh.cells(0, cell));
    return p;
  };
  Eigen::Matrix<double, 3, 4> g = Eigen::Matrix<double, 3, 4>::Zero();  // column a: ∂x/∂λ_a
  for (int a = 0; a <= dim; ++a) g.col(a) = (4.0 * l[static_cast<std::size_t>(a)] - 1.0) * x(a);
  const auto add_midside = [&](const int(&edge)[3]) {
    const Eigen::Vector3d xm = x(edge[0]);
    g.col(edge[1]) += 4.0 * l[static_cast<std::size_t>(edge[2])] * xm;
    g.col(edge[2]) += 4.0 * l[static_cast<std::size_t>(edge[1])] * xm;
  };
  if (dim == 3)
    for (const auto& edge : kTet10Midsides) add_midside(edge);
  else
    for (const auto& edge : kTri6Midsides) add_midside(edge);
  Eigen::Matrix3d jacobian = Eigen::Matrix3d::Identity();  // 2D: the z column stays e_z
  for (int j = 1; j <= dim; ++j) jacobian.col(j - 1) = g.col(j) - g.col(0);
  return jacobian.determinant();
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
    for (int i = 0; i < mesh.cells.rows(); ++i) used[static_cast<std::size_t>(mesh.cells(i, c))] = true;
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
  // Every cell's facets by their sorted vertices, sorted: a facet that comes
  // once is on the boundary (an interior one twice). A facet is named by
  // its use c·(dim+1) + k, and the boundary keeps the order of the uses.
  // A quadratic facet is keyed on its vertices and gets its midside nodes.
  const int dim = mesh.dim, per = dim + 1, order = mesh.order();
  struct Use {
    FacetKey key;
    int use;
  };
  std::vector<Use> uses(static_cast<std::size_t>(mesh.num_cells()) * static_cast<std::size_t>(per));
#pragma omp parallel for schedule(static) if (mesh.num_cells() >= 65536)
  for (int c = 0; c < mesh.num_cells(); ++c)
    for (int k = 0; k < per; ++k)
      uses[static_cast<std::size_t>(c) * per + k] = {vertex_key(oriented_facet(mesh, order, c, k), dim), c * per + k};
  std::sort(uses.begin(), uses.end(), [](const Use& a, const Use& b) { return a.key < b.key; });
  std::vector<int> once;
  for (std::size_t first = 0, last = 0; first < uses.size(); first = last) {
    last = first + 1;
    while (last < uses.size() && uses[last].key == uses[first].key) ++last;
    if (last == first + 1) once.push_back(uses[first].use);
  }
  uses = {};
  std::sort(once.begin(), once.end());
  const int rows = facet_nodes(dim, order);
  Eigen::MatrixXi out(rows, static_cast<Eigen::Index>(once.size()));
  for (std::size_t f = 0; f < once.size(); ++f) {
    const FacetNodes facet = oriented_facet(mesh, order, once[f] / per, once[f] % per);
    for (int i = 0; i < rows; ++i) out(i, static_cast<Eigen::Index>(f)) = facet[static_cast<std::size_t>(i)];
  }
  return out;
}

int orient_outward(Eigen::MatrixXi& facets, const Eigen::MatrixXi& boundary) {
  if (facets.rows() != boundary.rows() && facets.cols() > 0)
    throw std::invalid_argument("orient_outward: facets and boundary have different numbers of nodes");
  // Keyed on the vertices: the first 3 rows of a tri6 (6 rows); all rows of
  // a line2 (2), a tri3 (3) or a line3 (3: its two ends and its middle, a
  // node no other facet has, so the sorted three name it as well).
  const int keyed = boundary.rows() == 6 ? 3 : static_cast<int>(boundary.rows());
  const auto key_of = [keyed](const auto& column) {
    FacetKey f{-1, -1, -1};
    for (int i = 0; i < keyed; ++i) f[static_cast<std::size_t>(i)] = column(i);
    return sorted_key(f, keyed);
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
  out.cells.resize(mesh.cells.rows(), static_cast<Eigen::Index>(cells.size()));
  std::vector<int> new_cell(static_cast<std::size_t>(mesh.num_cells()), -1);
  for (std::size_t j = 0; j < cells.size(); ++j) {
    new_cell[static_cast<std::size_t>(cells[j])] = static_cast<int>(j);
    for (int i = 0; i < mesh.cells.rows(); ++i)
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
  const auto nodes = static_cast<int>(mesh.cells.rows());
  for (int c = 0; c < mesh.num_cells(); ++c)
    for (int a = 0; a < nodes; ++a)
      for (int b = 0; b < nodes; ++b)
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
    for (int a = 0; a < mesh.cells.rows(); ++a)
      low = std::min(low, new_index[static_cast<std::size_t>(mesh.cells(a, c))]);
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
    for (int a = 0; a < mesh.cells.rows(); ++a)  // the local order, and so the orientation, is kept
      out.cells(a, static_cast<Eigen::Index>(j)) = new_index[static_cast<std::size_t>(mesh.cells(a, cell_order[j]))];
  }
  out.cell_groups = restrict_cell_groups(mesh.cell_groups, new_cell);
  for (auto& [name, members] : out.cell_groups) std::sort(members.begin(), members.end());
  for (const auto& [name, group_facets] : mesh.facet_groups)
    out.facet_groups[name] = FacetGroup{restrict_facets(group_facets.facets, new_index)};
  return out;
}

double vertex_volume(const Mesh& mesh, int cell) {
  const auto p = [&](int i) { return mesh.points.col(mesh.cells(i, cell)); };
  if (mesh.dim == 2) {
    const Eigen::Vector2d a = p(1) - p(0), b = p(2) - p(0);
    return 0.5 * (a.x() * b.y() - a.y() * b.x());
  }
  const Eigen::Vector3d a = p(1) - p(0), b = p(2) - p(0), c = p(3) - p(0);
  return a.dot(b.cross(c)) / 6.0;
}

double signed_volume(const Mesh& mesh, int cell) {
  if (mesh.order() != 2) return vertex_volume(mesh, cell);
  double sum = 0.0;
  if (mesh.dim == 2) {  // 3 points (2/3, 1/6, 1/6) and permutations, weights 1/3: degree 2
    for (int k = 0; k < 3; ++k) {
      Barycentric l{1.0 / 6, 1.0 / 6, 1.0 / 6, 0.0};
      l[static_cast<std::size_t>(k)] = 2.0 / 3;
      sum += jacobian_determinant(mesh, cell, l) / 3.0;
    }
    return sum / 2.0;
  }
  // the centroid with weight -4/5 and (1/2, 1/6, 1/6, 1/6) and
  // permutations with 9/20: degree 3
  sum = -0.8 * jacobian_determinant(mesh, cell, {0.25, 0.25, 0.25, 0.25});
  for (int k = 0; k < 4; ++k) {
    Barycentric l{1.0 / 6, 1.0 / 6, 1.0 / 6, 1.0 / 6};
    l[static_cast<std::size_t>(k)] = 0.5;
    sum += 0.45 * jacobian_determinant(mesh, cell, l);
  }
  return sum / 6.0;
}

CellOrientation cell_orientation(const Mesh& mesh, int cell) {
  const double volume = vertex_volume(mesh, cell);
  const double h = longest_edge(mesh, cell);
  if (!(std::abs(volume) > 1e-12 * std::pow(h, mesh.dim))) return CellOrientation::degenerate;
  return volume > 0.0 ? CellOrientation::positive : CellOrientation::inverted;
}

double min_jacobian_determinant(const Mesh& mesh, int cell) {
  if (mesh.order() != 2) return (mesh.dim == 3 ? 6.0 : 2.0) * vertex_volume(mesh, cell);
  const double centre = 1.0 / (mesh.dim + 1);
  double lowest = jacobian_determinant(mesh, cell, {centre, centre, centre, mesh.dim == 3 ? centre : 0.0});
  for (int a = 0; a <= mesh.dim; ++a) {
    Barycentric l{0.0, 0.0, 0.0, 0.0};
    l[static_cast<std::size_t>(a)] = 1.0;
    lowest = std::min(lowest, jacobian_determinant(mesh, cell, l));
  }
  return lowest;
}

bool is_folded(const Mesh& mesh, int cell) {
  if (mesh.order() != 2) return false;
  return !(min_jacobian_determinant(mesh, cell) > 1e-12 * std::pow(longest_edge(mesh, cell), mesh.dim));
}

void flip_cell(Mesh& mesh, int cell) {
  std::swap(mesh.cells(1, cell), mesh.cells(2, cell));
  if (mesh.order() != 2) return;
  if (mesh.dim == 2) {
    std::swap(mesh.cells(3, cell), mesh.cells(5, cell));
    return;
  }
  std::swap(mesh.cells(4, cell), mesh.cells(6, cell));
  std::swap(mesh.cells(8, cell), mesh.cells(9, cell));
}

double total_volume(const Mesh& mesh) {
  double sum = 0.0;
  for (int c = 0; c < mesh.num_cells(); ++c) sum += signed_volume(mesh, c);
  return sum;
}

void check_orientation(const Mesh& mesh, const std::string& name) {
  for (int c = 0; c < mesh.num_cells(); ++c) {
    const CellOrientation o = cell_orientation(mesh, c);
    if (o != CellOrientation::positive)
      throw InputError(fmt::format("{}: cell {} is {} (signed volume {:g})", name, c,
                                   o == CellOrientation::inverted ? "inverted" : "degenerate", vertex_volume(mesh, c)));
    if (is_folded(mesh, c))
      throw InputError(
          fmt::format("{}: cell {} is folded (the Jacobian determinant of its quadratic map is {:g} at a "
                      "vertex or the centroid; expected positive)",
                      name, c, min_jacobian_determinant(mesh, c)));
  }
}

}  // namespace conserve::mesh
