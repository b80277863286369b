// Gmsh MSH 4.1 reader: the section loop (msh_sections.cpp parses each
// section) and the assembly of the Mesh from what the sections hold: cells,
// linear or quadratic (every node kept, in Gmsh's order), or for a rigid
// body's file without cells, a bare surface.
#include "mesh/msh_reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "core/error.hpp"
#include "mesh/msh_sections.hpp"
#include "mesh/surface_mesh.hpp"
#include "mesh/topology.hpp"

namespace conserve::mesh {

namespace {

using detail::MshContent;
using detail::MshCursor;
using detail::RawElement;

/// Binary sections: their data start on the line after the header.
bool has_binary_data(std::string_view section) {
  return section == "$Entities" || section == "$Nodes" || section == "$Elements";
}

void parse_section(MshCursor& in, MshContent& content, std::string_view section) {
  if (in.binary_values() && has_binary_data(section)) in.skip_line();
  if (section == "$MeshFormat") return detail::parse_mesh_format(in, content);
  if (section == "$PhysicalNames") return detail::parse_physical_names(in, content);
  if (section == "$Entities") return detail::parse_entities(in, content);
  if (section == "$Nodes") return detail::parse_nodes(in, content);
  if (section == "$Elements") return detail::parse_elements(in, content);
  if (section == "$PartitionedEntities")  // elements would refer to partition entities we do not map
    in.fail(in.offset(), "partitioned meshes are not supported (expected a mesh saved without partitions)");
  in.skip_section();  // $Periodic, $NodeData, $GhostElements, ...: not needed
}

void parse_sections(MshCursor& in, MshContent& content) {
  while (!in.at_end()) {
    const std::size_t at = in.offset();
    const std::string_view header = in.word();
    if (!content.has_format && header != "$MeshFormat")
      in.fail(at, fmt::format("missing $MeshFormat: found '{}' (expected a Gmsh .msh 4.1 file starting with "
                              "$MeshFormat)",
                              detail::printable(header)));
    if (header.size() < 2 || header.front() != '$' || header.starts_with("$End"))
      in.fail(at, fmt::format("found '{}' (expected a section header such as $Nodes)", detail::printable(header)));
    if (content.has_format && header == "$MeshFormat") in.fail(at, "second $MeshFormat section (expected one)");
    in.set_section(header);
    parse_section(in, content, header);
  }
  if (!content.has_format) in.fail(0, "missing $MeshFormat: the file is empty (expected a Gmsh .msh 4.1 file)");
}

/// Position of node `tag` in file order; fails if there is no such node.
int node_position(const MshCursor& in, const MshContent& content, const RawElement& element, std::uint64_t tag) {
  const auto it = content.node_index.find(tag);
  if (it == content.node_index.end())
    in.fail(element.offset, fmt::format("element {} references node {}, which is not in $Nodes", element.tag, tag));
  return it->second;
}

/// The file's order (1 if it has neither cells nor facets).
int order_of(const MshContent& content) { return content.order == 0 ? 1 : content.order; }

/// New index of every node in file order (-1: used by no cell); a
/// quadratic cell's midside nodes are kept as its vertices are.
std::vector<int> number_kept_nodes(const MshCursor& in, const MshContent& content) {
  std::vector<bool> used(content.node_tags.size(), false);
  const int nodes = cell_nodes(content.dim, order_of(content));
  for (const RawElement& cell : content.cells)
    for (int i = 0; i < nodes; ++i) {
      const int position = node_position(in, content, cell, cell.nodes[static_cast<std::size_t>(i)]);
      used[static_cast<std::size_t>(position)] = true;
    }
  std::vector<int> new_index(used.size(), -1);
  int next = 0;
  for (std::size_t n = 0; n < used.size(); ++n)
    if (used[n]) new_index[n] = next++;
  return new_index;
}

Eigen::MatrixXd kept_points(const MshCursor& in, const MshContent& content, const std::vector<int>& new_index) {
  const int dim = content.dim;
  Eigen::MatrixXd points(dim, *std::max_element(new_index.begin(), new_index.end()) + 1);
  double scale = 0.0;
  for (std::size_t n = 0; n < new_index.size(); ++n)
    if (new_index[n] >= 0)
      for (int k = 0; k < dim; ++k) {
        points(k, new_index[n]) = content.node_xyz[3 * n + static_cast<std::size_t>(k)];
        scale = std::max(scale, std::abs(points(k, new_index[n])));
      }
  for (std::size_t n = 0; dim == 2 && n < new_index.size(); ++n)
    if (new_index[n] >= 0 && std::abs(content.node_xyz[3 * n + 2]) > 1e-10 * scale)
      in.fail(content.node_offsets[n], fmt::format("node {} has z = {:g} (expected z = 0 in a 2D mesh)",
                                                   content.node_tags[n], content.node_xyz[3 * n + 2]));
  return points;
}

Eigen::MatrixXi kept_cells(const MshCursor& in, const MshContent& content, const std::vector<int>& new_index) {
  const int nodes = cell_nodes(content.dim, order_of(content));
  Eigen::MatrixXi cells(nodes, static_cast<Eigen::Index>(content.cells.size()));
  for (std::size_t c = 0; c < content.cells.size(); ++c)
    for (int i = 0; i < nodes; ++i) {
      const RawElement& cell = content.cells[c];
      const int position = node_position(in, content, cell, cell.nodes[static_cast<std::size_t>(i)]);
      cells(i, static_cast<Eigen::Index>(c)) = new_index[static_cast<std::size_t>(position)];
    }
  return cells;
}

/// Each cell's vertex simplex is positive and, for a quadratic cell, so is
/// its map's Jacobian determinant at the vertices and the centroid.
void check_cells(const MshCursor& in, const MshContent& content, const Mesh& mesh) {
  for (int c = 0; c < mesh.num_cells(); ++c) {
    const CellOrientation o = cell_orientation(mesh, c);
    const RawElement& cell = content.cells[static_cast<std::size_t>(c)];
    if (o != CellOrientation::positive)
      in.fail(cell.offset, fmt::format("element {} is {} (signed {} {:g}; expected a positive one)", cell.tag,
                                       o == CellOrientation::inverted ? "inverted" : "degenerate",
                                       mesh.dim == 3 ? "volume" : "area", vertex_volume(mesh, c)));
    if (is_folded(mesh, c))
      in.fail(cell.offset, fmt::format("element {} is folded: the Jacobian determinant of its quadratic map is {:g} "
                                       "at a vertex or the centroid (expected positive: is a midside node far "
                                       "off its edge?)",
                                       cell.tag, min_jacobian_determinant(mesh, c)));
  }
}

/// Names of the physical groups of dimension `dim` of entity `entity`
/// (a group without a name in $PhysicalNames is named by its number).
std::vector<std::string> group_names(const MshContent& content, int dim, int entity) {
  std::vector<std::string> names;
  const auto it = content.entity_physicals.find({dim, entity});
  if (it == content.entity_physicals.end()) return names;
  for (const int tag : it->second) {
    const auto name = content.physical_names.find({dim, tag});
    names.push_back(name != content.physical_names.end() ? name->second : std::to_string(tag));
  }
  std::sort(names.begin(), names.end());
  names.erase(std::unique(names.begin(), names.end()), names.end());
  return names;
}

void add_cell_groups(const MshContent& content, Mesh& mesh) {
  for (std::size_t c = 0; c < content.cells.size(); ++c)
    for (const std::string& name : group_names(content, content.dim, content.cells[c].entity))
      mesh.cell_groups[name].push_back(static_cast<int>(c));
}

void add_facet_groups(const MshCursor& in, const MshContent& content, const std::vector<int>& new_index, Mesh& mesh) {
  const int nodes = facet_nodes(content.dim, order_of(content));
  std::map<std::string, std::vector<int>> columns;
  for (const RawElement& facet : content.facets) {
    const std::vector<std::string> names = group_names(content, content.dim - 1, facet.entity);
    for (int i = 0; i < nodes && !names.empty(); ++i) {
      const std::uint64_t tag = facet.nodes[static_cast<std::size_t>(i)];
      const int index = new_index[static_cast<std::size_t>(node_position(in, content, facet, tag))];
      if (index < 0)
        in.fail(facet.offset, fmt::format("element {} of group '{}' uses node {}, which belongs to no {}D cell",
                                          facet.tag, names.front(), tag, content.dim));
      for (const std::string& name : names) columns[name].push_back(index);
    }
  }
  const Eigen::MatrixXi boundary = columns.empty() ? Eigen::MatrixXi() : boundary_facets(mesh);
  for (const auto& [name, group_nodes] : columns) {
    Eigen::MatrixXi& facets = mesh.facet_groups[name].facets;
    facets = Eigen::Map<const Eigen::MatrixXi>(group_nodes.data(), nodes,
                                               static_cast<Eigen::Index>(group_nodes.size()) / nodes);
    orient_outward(facets, boundary);  // facets inside the body keep the file's order
  }
}

/// "3-node triangles", "3-node lines", ...: the facets of that order, plural.
std::string facet_name(int dim, int order) {
  return std::string(detail::find_element_type(detail::facet_type(dim, order))->name) + "s";
}

/// The surface's facets, its nodes numbered in the order the facets first
/// use them; `tags` gets each new node's tag in the file.
Eigen::MatrixXi surface_facets(const MshCursor& in, const MshContent& content, std::vector<int>& new_index,
                               std::vector<std::uint64_t>& tags) {
  const int dim = content.dim;
  new_index.assign(content.node_tags.size(), -1);
  Eigen::MatrixXi facets(dim, static_cast<Eigen::Index>(content.facets.size()));
  for (std::size_t f = 0; f < content.facets.size(); ++f)
    for (int i = 0; i < dim; ++i) {
      const RawElement& facet = content.facets[f];
      const auto position =
          static_cast<std::size_t>(node_position(in, content, facet, facet.nodes[static_cast<std::size_t>(i)]));
      if (new_index[position] < 0) {
        new_index[position] = static_cast<int>(tags.size());
        tags.push_back(content.node_tags[position]);
      }
      facets(i, static_cast<Eigen::Index>(f)) = new_index[position];
    }
  return facets;
}

void check_surface(const MshCursor& in, const MshContent& content, const Mesh& mesh,
                   const std::vector<std::uint64_t>& tags) {
  const Eigen::MatrixXi& facets = mesh.facet_groups.at("surface").facets;
  if (const auto f = degenerate_facet(mesh.points, facets)) {
    const RawElement& facet = content.facets[static_cast<std::size_t>(*f)];
    in.fail(facet.offset,
            fmt::format("element {} is degenerate (its nodes coincide or are aligned; expected a {} "
                        "of positive {})",
                        facet.tag, mesh.dim == 3 ? "triangle" : "segment", mesh.dim == 3 ? "area" : "length"));
  }
  const auto clash = orientation_clash(facets);
  if (!clash) return;
  const RawElement& first = content.facets[static_cast<std::size_t>(clash->first)];
  const RawElement& second = content.facets[static_cast<std::size_t>(clash->second)];
  const auto tag = [&tags](int node) { return tags[static_cast<std::size_t>(node)]; };
  const std::string shared = mesh.dim == 3 ? fmt::format("share the edge from node {} to node {} in the same direction",
                                                         tag(clash->from), tag(clash->to))
                                           : fmt::format("both {} at node {}", clash->to < 0 ? "start" : "end",
                                                         tag(clash->to < 0 ? clash->from : clash->to));
  in.fail(second.offset,
          fmt::format("elements {} and {} {}: the surface's facets are not consistently oriented (expected {}, so "
                      "that all normals point to one side)",
                      first.tag, second.tag, shared,
                      mesh.dim == 3 ? "each edge of two triangles to run once each way"
                                    : "each node of two lines to end one and start the other"));
}

/// A file without cells read as a bare surface (read_msh with
/// BareSurface::accepted); its facets must be linear.
Mesh assemble_surface(const MshCursor& in, const MshContent& content) {
  const auto refuse = [&](int number, std::size_t at) {
    const detail::ElementType& type = *detail::find_element_type(number);
    in.fail(at, fmt::format("element type {} ({}) in a surface mesh: conserve needs {}", type.number, type.name,
                            facet_name(content.dim, 1)));
  };
  if (content.other_facet_type != 0) refuse(content.other_facet_type, content.other_facet_offset);
  if (content.order == 2) refuse(content.order_type, content.order_offset);
  std::vector<int> new_index;
  std::vector<std::uint64_t> tags;
  Eigen::MatrixXi facets = surface_facets(in, content, new_index, tags);
  Mesh mesh = bare_surface(content.dim, kept_points(in, content, new_index), std::move(facets));
  check_surface(in, content, mesh, tags);
  std::map<std::string, std::vector<int>> groups;  // name → facet columns
  for (std::size_t f = 0; f < content.facets.size(); ++f)
    for (const std::string& name : group_names(content, content.dim - 1, content.facets[f].entity))
      groups[name].push_back(static_cast<int>(f));
  const Eigen::MatrixXi& all = mesh.facet_groups.at("surface").facets;
  for (const auto& [name, columns] : groups) mesh.facet_groups[name].facets = all(Eigen::all, columns);
  return mesh;
}

Mesh assemble(const MshCursor& in, const MshContent& content, const std::string& name, BareSurface bare) {
  if (content.cells.empty() && bare == BareSurface::accepted &&
      (!content.facets.empty() || content.other_facet_type != 0))
    return assemble_surface(in, content);
  if (content.cells.empty())
    throw InputError(fmt::format(
        "{}: no {} (element type {}) in the file (expected a {}D mesh{})", name,
        content.dim == 3 ? "4-node tetrahedra" : "3-node triangles", content.dim == 3 ? 4 : 2, content.dim,
        content.facets.empty() ? std::string()
                               : fmt::format("; its {} {} make a bare surface, which only a rigid body may be",
                                             content.facets.size(), facet_name(content.dim, order_of(content)))));
  const std::vector<int> new_index = number_kept_nodes(in, content);
  Mesh mesh;
  mesh.dim = content.dim;
  mesh.points = kept_points(in, content, new_index);
  mesh.cells = kept_cells(in, content, new_index);
  check_cells(in, content, mesh);
  add_cell_groups(content, mesh);
  add_facet_groups(in, content, new_index, mesh);
  return mesh;
}

}  // namespace

Mesh parse_msh(std::string_view bytes, const std::string& name, int dim, BareSurface bare) {
  if (dim != 2 && dim != 3) throw InputError(fmt::format("{}: mesh dimension {} (expected 2 or 3)", name, dim));
  MshCursor in(bytes, name);
  MshContent content;
  content.dim = dim;
  parse_sections(in, content);
  return assemble(in, content, name, bare);
}

Mesh read_msh(const std::filesystem::path& file, int dim, BareSurface bare) {
  std::error_code ec;
  std::ifstream stream(file, std::ios::binary);
  if (!stream || std::filesystem::is_directory(file, ec))
    throw InputError(fmt::format("{}: cannot open the mesh file (expected a readable .msh file)", file.string()));
  std::ostringstream bytes;
  bytes << stream.rdbuf();
  if (stream.bad()) throw InputError(fmt::format("{}: error while reading the mesh file", file.string()));
  return parse_msh(bytes.str(), file.string(), dim, bare);
}

}  // namespace conserve::mesh
