#include "model/model.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <numeric>
#include <set>

#include "core/error.hpp"

namespace conserve::model {

namespace {

/// The mesh's shape fits a D-dimensional model: D coordinates, the nodes
/// per cell of a linear or quadratic simplex, of the order of the model's
/// other bodies (any number of cells, also none: a bare surface).
template <int D>
void check_shape(const Model<D>& model, const mesh::Mesh& mesh, const std::string& name) {
  if (mesh.dim != D) throw InputError(fmt::format("body '{}': mesh is {}D but the scenario is {}D", name, mesh.dim, D));
  if (mesh.points.rows() < D)
    throw InputError(
        fmt::format("body '{}': mesh points have {} coordinates (expected {})", name, mesh.points.rows(), D));
  if (mesh.num_cells() == 0) return;
  constexpr int linear = D + 1, quadratic = fem::Quadratic<D>::kNodes;
  if (mesh.cells.rows() != linear && mesh.cells.rows() != quadratic)
    throw InputError(fmt::format("body '{}': mesh cells have {} nodes (expected {} or {})", name, mesh.cells.rows(),
                                 linear, quadratic));
  const int order = mesh.cells.rows() == linear ? 1 : 2;
  if (model.num_cells() > 0 && order != model.order)
    throw InputError(fmt::format("body '{}': its cells are of order {} but the other bodies' of order {} (one order "
                                 "per scenario: set order = {} on every [body.mesh])",
                                 name, order, model.order, model.order));
}

}  // namespace

/// A mesh without cells (a bare surface of a rigid body) gives a body with
/// num_cells = 0 whose nodes are the mesh's points.
template <int D>
Body& add_body(Model<D>& model, const mesh::Mesh& mesh, const std::string& name,
               std::shared_ptr<const material::Law> law, double density, double thickness) {
  check_shape<D>(model, mesh, name);
  Body body{name,    model.num_nodes(), mesh.num_nodes(), model.num_cells(), mesh.num_cells(), std::move(law),
            density, {}, D == 2 ? thickness : 1.0};
  if (body.num_cells > 0 && model.num_cells() == 0) model.order = mesh.cells.rows() == D + 1 ? 1 : 2;
  const int nodes = model.order == 1 ? D + 1 : fem::Quadratic<D>::kNodes;
  model.X.conservativeResize(D, body.first_node + body.num_nodes);
  model.X.rightCols(body.num_nodes) = mesh.points.topRows(D);
  model.cells.conservativeResize(nodes, body.first_cell + body.num_cells);
  if (body.num_cells > 0) model.cells.rightCols(body.num_cells) = mesh.cells.array() + body.first_node;
  const auto cells = static_cast<std::size_t>(body.num_cells);
  if (model.order == 1)
    model.geometry.reserve(model.geometry.size() + cells);  // no growth slack
  else
    model.quadratic.reserve(model.quadratic.size() + cells);
  model.cell_body.reserve(model.cell_body.size() + cells);
  const auto refuse = [&](int c, double measure) {
    if (!(measure > 0.0))
      throw InputError(fmt::format("body '{}': cell {} is {} ({} {:.3e})", name, c,
                                   measure < 0.0 ? "inverted" : "degenerate",
                                   model.order == 1 ? "signed volume" : "smallest Jacobian determinant", measure));
  };
  for (int c = 0; c < body.num_cells; ++c) {
    if (model.order == 1) {
      fem::NodeMatrix<D> Xc;
      for (int a = 0; a <= D; ++a) Xc.col(a) = model.X.col(model.cells(a, body.first_cell + c));
      refuse(c, fem::signed_measure<D>(Xc));
      model.geometry.push_back(fem::simplex_geometry<D>(Xc, thickness));
    } else {
      fem::QuadraticNodes<D> Xc;
      for (int a = 0; a < nodes; ++a) Xc.col(a) = model.X.col(model.cells(a, body.first_cell + c));
      refuse(c, fem::min_jacobian<D>(Xc));
      model.quadratic.push_back(fem::quadratic_geometry<D>(Xc, thickness));
    }
    model.cell_body.push_back(static_cast<int>(model.bodies.size()));
  }
  for (const auto& [group, facets] : mesh.facet_groups)
    body.facet_groups[group] = facets.facets.array() + body.first_node;
  model.bodies.push_back(std::move(body));
  return model.bodies.back();
}

std::vector<int> group_nodes(const Body& body, const std::string& group) {
  if (group == "all") {
    std::vector<int> nodes(body.num_nodes);
    std::iota(nodes.begin(), nodes.end(), body.first_node);
    return nodes;
  }
  const auto it = body.facet_groups.find(group);
  if (it == body.facet_groups.end()) {
    std::string known = "all";
    for (const auto& [name, facets] : body.facet_groups) known += ", " + name;
    throw InputError(fmt::format("body '{}' has no group '{}' (groups: {})", body.name, group, known));
  }
  std::vector<int> nodes(it->second.data(), it->second.data() + it->second.size());
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  return nodes;
}

Eigen::MatrixXi distinct_facets(const Body& body) {
  std::set<std::vector<int>> seen;
  std::vector<Eigen::VectorXi> kept;
  for (const auto& [group, facets] : body.facet_groups) {
    for (Eigen::Index f = 0; f < facets.cols(); ++f) {
      std::vector<int> key(facets.col(f).data(), facets.col(f).data() + facets.rows());
      std::sort(key.begin(), key.end());
      if (seen.insert(std::move(key)).second) kept.emplace_back(facets.col(f));
    }
  }
  Eigen::MatrixXi out(kept.empty() ? 0 : kept.front().size(), static_cast<Eigen::Index>(kept.size()));
  for (std::size_t f = 0; f < kept.size(); ++f) out.col(static_cast<Eigen::Index>(f)) = kept[f];
  return out;
}

template <int D>
void keep_cells(Model<D>& model, const std::vector<int>& kept) {
  Eigen::MatrixXi cells(model.cells.rows(), static_cast<Eigen::Index>(kept.size()));
  std::vector<fem::SimplexGeometry<D>> geometry;
  std::vector<fem::QuadraticGeometry<D>> quadratic;
  std::vector<int> body, ids;
  if (model.order == 1)
    geometry.reserve(kept.size());
  else
    quadratic.reserve(kept.size());
  body.reserve(kept.size());
  ids.reserve(kept.size());
  for (std::size_t k = 0; k < kept.size(); ++k) {
    const int c = kept[k];
    cells.col(static_cast<Eigen::Index>(k)) = model.cells.col(c);
    if (model.order == 1)
      geometry.push_back(model.geometry[static_cast<std::size_t>(c)]);
    else
      quadratic.push_back(model.quadratic[static_cast<std::size_t>(c)]);
    body.push_back(model.cell_body[static_cast<std::size_t>(c)]);
    ids.push_back(model.global_cell(c));
  }
  model.cells = std::move(cells);
  model.geometry = std::move(geometry);
  model.quadratic = std::move(quadratic);
  model.cell_body = std::move(body);
  model.cell_ids = std::move(ids);
}

template void keep_cells<2>(Model<2>&, const std::vector<int>&);
template void keep_cells<3>(Model<3>&, const std::vector<int>&);
template Body& add_body<2>(Model<2>&, const mesh::Mesh&, const std::string&, std::shared_ptr<const material::Law>,
                           double, double);
template Body& add_body<3>(Model<3>&, const mesh::Mesh&, const std::string&, std::shared_ptr<const material::Law>,
                           double, double);

}  // namespace conserve::model
