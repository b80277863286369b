#pragma once
/// Internal to the msh reader: the raw content of a .msh 4.1 file (what
/// the sections hold, before it becomes a Mesh) and the section parsers.
#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "mesh/msh_cursor.hpp"

namespace conserve::mesh::detail {

/// A Gmsh element type: its dimension, number of nodes and a human name.
struct ElementType {
  int number = 0;
  int dim = 0;
  int num_nodes = 0;
  const char* name = "";
};

/// The type with Gmsh number `number`, or nullptr if we do not know it.
const ElementType* find_element_type(int number);

/// The Gmsh types of the cells and of the facets of a mesh of dimension
/// `dim` and order 1 or 2: 2D cells 2 / 9 (3- / 6-node triangles), facets
/// 1 / 8 (2- / 3-node lines); 3D cells 4 / 11 (4- / 10-node tetrahedra),
/// facets 2 / 9 (3- / 6-node triangles).
int cell_type(int dim, int order);
int facet_type(int dim, int order);

/// One element we keep (a cell, or a facet that may be in a named group).
struct RawElement {
  std::uint64_t tag = 0;
  int entity = 0;          ///< tag of the entity it belongs to
  std::size_t offset = 0;  ///< where it is in the file (for messages)
  /// Node tags: cell_nodes(dim, order) for cells, facet_nodes(dim, order)
  /// for facets (at most 10, a 10-node tetrahedron's).
  std::array<std::uint64_t, 10> nodes{};
};

/// What the sections of a file hold.
struct MshContent {
  int dim = 3;  ///< requested mesh dimension (2 or 3)
  bool has_format = false;
  /// (dimension, physical tag) → name, from $PhysicalNames.
  std::map<std::pair<int, int>, std::string> physical_names;
  /// (dimension, entity tag) → physical tags, from $Entities.
  std::map<std::pair<int, int>, std::vector<int>> entity_physicals;
  /// Nodes in file order: tag, coordinates (x, y, z) and where the
  /// coordinates are in the file.
  std::vector<std::uint64_t> node_tags;
  std::vector<double> node_xyz;
  std::vector<std::size_t> node_offsets;
  std::unordered_map<std::uint64_t, int> node_index;  ///< tag → position in node_tags
  std::vector<RawElement> cells;                      ///< elements of dimension dim
  std::vector<RawElement> facets;                     ///< simplices of dimension dim-1
  /// Order of the cells and facets (1 linear, 2 quadratic; 0 while the file
  /// has none): set by the first block of them, which every later one must
  /// match; `order_type` is that block's element type, `order_offset` where
  /// it starts.
  int order = 0;
  int order_type = 0;
  std::size_t order_offset = 0;
  /// The first element of dimension dim-1 that is not a simplex (e.g. a
  /// quadrangle in 3D): its type (0: none) and where its block starts.
  int other_facet_type = 0;
  std::size_t other_facet_offset = 0;
};

void parse_mesh_format(MshCursor& in, MshContent& content);
void parse_physical_names(MshCursor& in, MshContent& content);
void parse_entities(MshCursor& in, MshContent& content);
void parse_nodes(MshCursor& in, MshContent& content);
void parse_elements(MshCursor& in, MshContent& content);

}  // namespace conserve::mesh::detail
