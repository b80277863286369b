#include "mesh/gmsh_mesher.hpp"

#include <fmt/format.h>
#include <gmsh.h>

#include <algorithm>
#include <map>
#include <mutex>
#include <unordered_map>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "core/error.hpp"
#include "mesh/msh_sections.hpp"
#include "mesh/topology.hpp"

namespace conserve::mesh::detail {

namespace {

using Tags = std::vector<std::size_t>;

std::mutex& gmsh_mutex() {
  static std::mutex mutex;
  return mutex;
}

EntityShape shape_of(int dim, int tag) {
  EntityShape s;
  gmsh::model::occ::getCenterOfMass(dim, tag, s.centre.x(), s.centre.y(), s.centre.z());
  gmsh::model::getBoundingBox(dim, tag, s.lo.x(), s.lo.y(), s.lo.z(), s.hi.x(), s.hi.y(), s.hi.z());
  return s;
}

/// Physical groups: "body" on all cells' entities, the named groups on the
/// boundary entities the recipe classifies.
void add_physical_groups(const GmshRecipe& recipe) {
  gmsh::vectorpair entities;
  gmsh::model::getEntities(entities, recipe.dim);
  std::vector<int> body;
  for (const auto& [d, tag] : entities) body.push_back(tag);
  gmsh::model::setPhysicalName(recipe.dim, gmsh::model::addPhysicalGroup(recipe.dim, body), "body");
  gmsh::model::getEntities(entities, recipe.dim - 1);
  std::map<std::string, std::vector<int>> groups;
  for (const auto& [d, tag] : entities) {
    const std::string name = recipe.classify(shape_of(d, tag));
    if (!name.empty()) groups[name].push_back(tag);
  }
  for (const auto& [name, tags] : groups)
    gmsh::model::setPhysicalName(recipe.dim - 1, gmsh::model::addPhysicalGroup(recipe.dim - 1, tags), name);
}

/// For order 2, Gmsh puts the midside nodes on the geometry
/// (SecondOrderLinear = 0: the true curved boundary, not the chord) and
/// then moves the interior ones of cells this folds (HighOrderOptimize = 2:
/// elastic analogy and optimisation; boundary nodes stay on the geometry).
void set_mesh_options(double size, int order) {
  gmsh::option::setNumber("Mesh.MeshSizeMax", size);
  gmsh::option::setNumber("Mesh.MeshSizeMin", 0.1 * size);
  gmsh::option::setNumber("Mesh.ElementOrder", order);
  if (order == 2) {
    gmsh::option::setNumber("Mesh.SecondOrderLinear", 0);
    gmsh::option::setNumber("Mesh.HighOrderOptimize", 2);
  }
}

/// Node tags of the elements of type `type` on entity (dim, tag) (tag -1: all).
Tags element_nodes(int dim, int tag, int type) {
  std::vector<int> types;
  std::vector<Tags> element_tags, node_tags;
  gmsh::model::mesh::getElements(types, element_tags, node_tags, dim, tag);
  Tags out;
  for (std::size_t i = 0; i < types.size(); ++i)
    if (types[i] == type) out.insert(out.end(), node_tags[i].begin(), node_tags[i].end());
  return out;
}

/// Mesh points and cells; `index` maps Gmsh node tags to mesh node indices.
Mesh cells_and_points(const GmshRecipe& recipe, std::unordered_map<std::size_t, int>& index) {
  Tags tags;
  std::vector<double> xyz, parametric;
  gmsh::model::mesh::getNodes(tags, xyz, parametric, -1, -1, false, false);
  const Tags tags_of_cells = element_nodes(recipe.dim, -1, cell_type(recipe.dim, recipe.order));
  for (const std::size_t tag : tags_of_cells) index[tag] = -1;
  Mesh mesh;
  mesh.dim = recipe.dim;
  mesh.points.resize(recipe.dim, static_cast<Eigen::Index>(index.size()));
  int next = 0;
  for (std::size_t n = 0; n < tags.size(); ++n) {
    const auto it = index.find(tags[n]);
    if (it == index.end()) continue;
    for (int k = 0; k < recipe.dim; ++k) mesh.points(k, next) = recipe.scale * xyz[3 * n + static_cast<std::size_t>(k)];
    it->second = next++;
  }
  if (next != static_cast<int>(index.size())) throw Error(recipe.name + ": Gmsh returned elements without nodes");
  const int per = cell_nodes(recipe.dim, recipe.order);
  const Eigen::Index n_cells = static_cast<Eigen::Index>(tags_of_cells.size()) / per;
  mesh.cells.resize(per, n_cells);
  for (Eigen::Index c = 0; c < n_cells; ++c)
    for (int i = 0; i < per; ++i) mesh.cells(i, c) = index.at(tags_of_cells[static_cast<std::size_t>(c * per + i)]);
  return mesh;
}

/// Flips negatively oriented cells (Gmsh's 2D triangles follow the surface
/// normal); a degenerate or (quadratic) folded cell is an error.
void orient_cells(const std::string& name, Mesh& mesh) {
  for (int c = 0; c < mesh.num_cells(); ++c) {
    const CellOrientation o = cell_orientation(mesh, c);
    if (o == CellOrientation::inverted) flip_cell(mesh, c);  // with its midside nodes
    if (o == CellOrientation::degenerate)
      throw InputError(fmt::format("generator '{}': Gmsh made a degenerate cell (expected a smaller size)", name));
    if (is_folded(mesh, c))
      throw InputError(
          fmt::format("generator '{}': Gmsh made a folded quadratic cell (Jacobian determinant {:g} at a vertex or the "
                      "centroid; expected a smaller size)",
                      name, min_jacobian_determinant(mesh, c)));
  }
}

/// The facet groups Gmsh's physical groups hold, each facet oriented like
/// the same facet of "boundary" (outward).
void add_named_groups(const GmshRecipe& recipe, const std::unordered_map<std::size_t, int>& index, Mesh& mesh) {
  const int dim = recipe.dim, rows = facet_nodes(dim, recipe.order);
  gmsh::vectorpair groups;
  gmsh::model::getPhysicalGroups(groups, dim - 1);
  for (const auto& [d, physical] : groups) {
    std::string name;
    gmsh::model::getPhysicalName(d, physical, name);
    std::vector<int> entities, nodes;
    gmsh::model::getEntitiesForPhysicalGroup(d, physical, entities);
    for (const int entity : entities)
      for (const std::size_t tag : element_nodes(d, entity, facet_type(dim, recipe.order)))
        nodes.push_back(index.at(tag));
    Eigen::MatrixXi facets =
        Eigen::Map<const Eigen::MatrixXi>(nodes.data(), rows, static_cast<Eigen::Index>(nodes.size()) / rows);
    if (orient_outward(facets, mesh.facet_groups.at("boundary").facets) != 0)
      throw Error(fmt::format("{}: a facet of group '{}' is not on the boundary", recipe.name, name));
    mesh.facet_groups[name].facets = std::move(facets);
  }
}

Mesh generate_locked(const GmshRecipe& recipe) {
  gmsh::model::add("conserve");
  recipe.build();
  gmsh::model::occ::synchronize();
  add_physical_groups(recipe);
  set_mesh_options(recipe.size, recipe.order);
  gmsh::model::mesh::generate(recipe.dim);
  std::unordered_map<std::size_t, int> index;
  Mesh mesh = cells_and_points(recipe, index);
  if (mesh.num_cells() == 0) throw InputError(fmt::format("generator '{}': Gmsh made no cells", recipe.name));
  orient_cells(recipe.name, mesh);
  mesh.cell_groups["body"].resize(static_cast<std::size_t>(mesh.num_cells()));
  for (int c = 0; c < mesh.num_cells(); ++c) mesh.cell_groups["body"][static_cast<std::size_t>(c)] = c;
  mesh.facet_groups["boundary"].facets = boundary_facets(mesh);
  add_named_groups(recipe, index, mesh);
  return mesh;
}

}  // namespace

GmshSession::GmshSession() : lock_(gmsh_mutex()) {
#ifdef _OPENMP
  threads_ = omp_get_max_threads();
#endif
  gmsh::initialize(0, nullptr, false);
  gmsh::option::setNumber("General.Terminal", 0);
}

GmshSession::~GmshSession() {
  gmsh::finalize();
#ifdef _OPENMP
  omp_set_num_threads(threads_);
#endif
}

Mesh mesh_with_gmsh(const GmshRecipe& recipe) {
  static constexpr const char* kHint = " (expected a mesh size small enough for the thinnest part)";
  const GmshSession session;
  try {
    return generate_locked(recipe);
  } catch (const conserve::Error&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(fmt::format("generator '{}': Gmsh failed: {}{}", recipe.name, e.what(), kHint));
  } catch (const std::string& message) {  // what Gmsh 4.8 throws on errors
    throw InputError(fmt::format("generator '{}': Gmsh failed: {}{}", recipe.name, message, kHint));
  } catch (...) {
    std::string last;
    gmsh::logger::getLastError(last);
    throw InputError(
        fmt::format("generator '{}': Gmsh failed: {}{}", recipe.name, last.empty() ? "unknown error" : last, kHint));
  }
}

}  // namespace conserve::mesh::detail
