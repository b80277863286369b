#pragma once
/// The discretised problem: all bodies' nodes and cells in one numbering,
/// materials, constant loads and prescribed displacements. Plain data;
/// built once (simulation/setup) and read by every layer above.
#include <map>
#include <string>
#include <vector>

#include <memory>

#include "fem/quadratic.hpp"
#include "fem/simplex.hpp"

#include "material/law.hpp"
#include "mesh/mesh.hpp"
#include "model/loads.hpp"
#include "model/prescribed.hpp"

namespace conserve::model {

/// One body: a contiguous range of nodes and of cells.
struct Body {
  std::string name;
  int first_node = 0;
  int num_nodes = 0;
  int first_cell = 0;
  int num_cells = 0;
  std::shared_ptr<const material::Law> law;  ///< the body's point law (never null)
  double density = 0.0;                      ///< [kg/m³]
  /// Named boundary facet groups, in global node numbers (dim × n).
  std::map<std::string, Eigen::MatrixXi> facet_groups;
  double thickness = 1.0;  ///< out-of-plane size in 2D [m] (1 in 3D)
  /// Quadratic cells with the cell's mean dilatation (fem/mean_dilatation.hpp).
  bool mean_dilatation = false;
};


/// Global degree of freedom of node `node`, component `i` (node-major).
template <int D>
constexpr int dof(int node, int i) {
  return node * D + i;
}

/// A free rigid body (time/free_bodies.hpp): its nodes move rigidly, as its
/// centre and rotation say; their degrees of freedom are held out of the
/// nodal system as prescribed ones are.
struct FreeBody {
  int body = -1;  ///< index into Model::bodies
  int first_node = 0, num_nodes = 0;
};

template <int D>
struct Model {
  Eigen::Matrix<double, D, Eigen::Dynamic> X;     ///< reference coordinates, D × n_nodes [m]
  /// Nodes × n_cells, global node numbers: D+1 rows (linear cells) or
  /// (D+1)(D+2)/2 (quadratic, Gmsh's order, fem/lagrange.hpp).
  Eigen::MatrixXi cells;
  int order = 1;                                  ///< every cell's: 1 or 2
  std::vector<fem::SimplexGeometry<D>> geometry;  ///< per cell, order 1
  std::vector<fem::QuadraticGeometry<D>> quadratic;  ///< per cell, order 2
  std::vector<int> cell_body;                     ///< body index per cell
  std::vector<Body> bodies;
  Vec<D> gravity = Vec<D>::Zero();  ///< [m/s²]
  int gravity_curve = -1;           ///< index into prescribed.curves scaling gravity; −1: constant
  std::vector<SurfaceLoad> loads;
  Prescribed prescribed;
  std::vector<FreeBody> free_bodies;
  /// The ranks' shares of a distributed run: rank r owns the nodes
  /// [rank_nodes[r], rank_nodes[r+1]), their rows of every matrix (the rows
  /// beyond the nodes' are the last rank's), and adds each term of the
  /// system whose node it owns; this process is rank `rank`. Empty: one
  /// rank, all nodes.
  std::vector<int> rank_nodes;
  int rank = 0;
  /// N if the nodes are numbered by the graph parts of N ranks
  /// (simulation/rank_numbering.hpp), so that the numbering is this rank
  /// count's alone; 0: the meshes' numbering, the same on any count.
  int numbered_for_ranks = 0;
  /// On several ranks, once the run is wired (keep_cells): the global
  /// number of each cell this rank holds, which are the cells with a corner
  /// among its nodes, in ascending order; `cells`, `geometry` and
  /// `cell_body` hold those alone, while Body::first_cell and num_cells
  /// keep the global numbering. Empty: every cell, in order.
  std::vector<int> cell_ids;

  [[nodiscard]] int num_nodes() const { return static_cast<int>(X.cols()); }
  /// The cells held (this rank's after keep_cells).
  [[nodiscard]] int num_cells() const { return static_cast<int>(cells.cols()); }
  /// The global number of held cell c.
  [[nodiscard]] int global_cell(int c) const { return cell_ids.empty() ? c : cell_ids[static_cast<std::size_t>(c)]; }
  /// The body holding global cell `cell`.
  [[nodiscard]] int body_of_cell(int cell) const {
    for (std::size_t b = 0; b < bodies.size(); ++b)
      if (cell >= bodies[b].first_cell && cell < bodies[b].first_cell + bodies[b].num_cells) return static_cast<int>(b);
    return -1;
  }
  [[nodiscard]] int num_dofs() const { return D * num_nodes(); }
  /// Reference volume of held cell c [m³] (2D: area × thickness).
  [[nodiscard]] double cell_volume(int c) const {
    return order == 1 ? geometry[static_cast<std::size_t>(c)].volume : quadratic[static_cast<std::size_t>(c)].volume;
  }
  [[nodiscard]] int num_ranks() const { return rank_nodes.empty() ? 1 : static_cast<int>(rank_nodes.size()) - 1; }
  /// This rank's nodes [first, end).
  [[nodiscard]] int first_owned() const { return rank_nodes.empty() ? 0 : rank_nodes[rank]; }
  [[nodiscard]] int end_owned() const { return rank_nodes.empty() ? num_nodes() : rank_nodes[rank + 1]; }
  /// Whether this rank owns `node`'s rows (and adds the terms of the
  /// constraints, couplings and loads whose slave or first node it is).
  [[nodiscard]] bool owns(int node) const { return node >= first_owned() && node < end_owned(); }
  /// Whether this rank owns the rows beyond the nodes' (multipliers, free
  /// bodies' unknowns) and adds the terms that belong to no node.
  [[nodiscard]] bool owns_extra_rows() const { return rank == num_ranks() - 1; }
  /// The dofs the nodal system holds: the prescribed ones, then the free
  /// rigid bodies' (whose motion has its own unknowns).
  [[nodiscard]] std::vector<int> held_dofs() const {
    std::vector<int> dofs = prescribed.dofs;
    for (const FreeBody& b : free_bodies)
      for (int d = b.first_node * D; d < (b.first_node + b.num_nodes) * D; ++d) dofs.push_back(d);
    return dofs;
  }
  /// Diagonal of the bounding box of the reference configuration [m].
  [[nodiscard]] double size() const {
    return num_nodes() ? (X.rowwise().maxCoeff() - X.rowwise().minCoeff()).norm() : 0.0;
  }
};

/// Appends a body made from `mesh` (already placed). Throws InputError
/// naming `name` if the mesh's dimension is not D or a cell is inverted or
/// degenerate. `thickness` [m] is the out-of-plane size in 2D.
template <int D>
Body& add_body(Model<D>& model, const mesh::Mesh& mesh, const std::string& name,
               std::shared_ptr<const material::Law> law, double density, double thickness);

/// Keeps the held cells `kept` (ascending indices into the cells held
/// now) and drops the others (Model::cell_ids): what a rank of a
/// distributed run keeps once everything that needs every cell (contact
/// surfaces, the mass matrix, checkpoints' fingerprint) is built.
template <int D>
void keep_cells(Model<D>& model, const std::vector<int>& kept);

/// Node numbers (global, sorted, unique) of a body's group; "all" is every
/// node of the body. Throws InputError listing the groups if unknown.
std::vector<int> group_nodes(const Body& body, const std::string& group);

/// The distinct facets of all the body's facet groups, d × n in global node
/// numbers (d = 2 in 2D, 3 in 3D): a facet in several groups (e.g. the
/// `surface` and `boundary` of a generated bare surface) comes once, as its
/// first group in name order has it. What shows a bare surface (a rigid
/// body without cells) in the output.
Eigen::MatrixXi distinct_facets(const Body& body);

/// The mean of the diagonal of the dofs' mass matrix M_AB ⊗ I_D [kg], from
/// the nodes' M_AB: each node's entry D times, summed in dof order.
template <int D>
double mean_dof_mass(const SparseMatrix& node_mass) {
  const Eigen::VectorXd diagonal = node_mass.diagonal();
  double sum = 0.0;
  for (const double m : diagonal)
    for (int i = 0; i < D; ++i) sum += m;
  return sum / static_cast<double>(D * diagonal.size());
}

}  // namespace conserve::model
