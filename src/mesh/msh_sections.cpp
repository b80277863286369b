// Parsers of the sections of a Gmsh MSH 4.1 file. The layouts follow the
// format description of the Gmsh reference manual ("MSH file format",
// version 4.1); ASCII and binary files hold the same values in the same
// order, so one parser per section serves both modes (see MshCursor).
#include "mesh/msh_sections.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>

namespace conserve::mesh::detail {

namespace {

constexpr ElementType kElementTypes[] = {
    {1, 1, 2, "2-node line"},           {2, 2, 3, "3-node triangle"},       {3, 2, 4, "4-node quadrangle"},
    {4, 3, 4, "4-node tetrahedron"},    {5, 3, 8, "8-node hexahedron"},     {6, 3, 6, "6-node prism"},
    {7, 3, 5, "5-node pyramid"},        {8, 1, 3, "3-node line"},           {9, 2, 6, "6-node triangle"},
    {10, 2, 9, "9-node quadrangle"},    {11, 3, 10, "10-node tetrahedron"}, {12, 3, 27, "27-node hexahedron"},
    {13, 3, 18, "18-node prism"},       {14, 3, 14, "14-node pyramid"},     {15, 0, 1, "1-node point"},
    {16, 2, 8, "8-node quadrangle"},    {17, 3, 20, "20-node hexahedron"},  {18, 3, 15, "15-node prism"},
    {19, 3, 13, "13-node pyramid"},     {20, 2, 9, "9-node triangle"},      {21, 2, 10, "10-node triangle"},
    {22, 2, 12, "12-node triangle"},    {23, 2, 15, "15-node triangle"},    {24, 2, 15, "15-node incomplete triangle"},
    {25, 2, 21, "21-node triangle"},    {26, 1, 4, "4-node line"},          {27, 1, 5, "5-node line"},
    {28, 1, 6, "6-node line"},          {29, 3, 20, "20-node tetrahedron"}, {30, 3, 35, "35-node tetrahedron"},
    {31, 3, 56, "56-node tetrahedron"}, {92, 3, 64, "64-node hexahedron"},  {93, 3, 125, "125-node hexahedron"},
};

int read_dim(MshCursor& in, std::string_view what) {
  const std::size_t at = in.value_start();
  const int dim = in.read_int(what);
  if (dim < 0 || dim > 3) in.fail(at, fmt::format("{} {} is not 0, 1, 2 or 3", what, dim));
  return dim;
}

void skip_values(MshCursor& in, std::uint64_t n, bool doubles, std::string_view what) {
  for (std::uint64_t i = 0; i < n; ++i) doubles ? (void)in.read_double(what) : (void)in.read_int(what);
}

void check_total(MshCursor& in, std::size_t at, std::uint64_t declared, std::uint64_t found, std::string_view what) {
  if (declared != found)
    in.fail(at, fmt::format("the header declares {} {} but the blocks hold {} (file corrupt)", declared, what, found));
}

void read_one_entity(MshCursor& in, MshContent& content, int dim) {
  const int tag = in.read_int("entity tag");
  skip_values(in, dim == 0 ? 3 : 6, true, dim == 0 ? "point coordinate" : "bounding box coordinate");
  const std::uint64_t num_physicals = in.read_count("number of physical tags", 1, 4);
  std::vector<int> physicals;
  for (std::uint64_t i = 0; i < num_physicals; ++i) physicals.push_back(in.read_int("physical tag"));
  if (dim > 0) skip_values(in, in.read_count("number of bounding entities", 1, 4), false, "bounding entity tag");
  if (!physicals.empty()) content.entity_physicals[{dim, tag}] = std::move(physicals);
}

void read_node_block(MshCursor& in, MshContent& content, std::uint64_t& total) {
  const int entity_dim = read_dim(in, "entity dimension");
  in.read_int("entity tag");
  const std::size_t at = in.value_start();
  const int parametric = in.read_int("parametric flag");
  if (parametric != 0 && parametric != 1) in.fail(at, fmt::format("parametric flag {} is not 0 or 1", parametric));
  const std::uint64_t n = in.read_count("number of nodes in block", 4, 32);
  const std::size_t first = content.node_tags.size();
  for (std::uint64_t i = 0; i < n; ++i) {
    const std::size_t tag_at = in.value_start();
    const std::uint64_t tag = in.read_size("node tag");
    const auto [it, inserted] = content.node_index.emplace(tag, static_cast<int>(content.node_tags.size()));
    if (!inserted)
      in.fail(tag_at, fmt::format("duplicate node tag {} (already defined at {})", tag,
                                  in.location(content.node_offsets[static_cast<std::size_t>(it->second)])));
    content.node_tags.push_back(tag);
    content.node_offsets.push_back(tag_at);
  }
  for (std::uint64_t i = 0; i < n; ++i) {
    content.node_offsets[first + i] = in.value_start();
    for (int k = 0; k < 3; ++k) content.node_xyz.push_back(in.read_double("node coordinate"));
    skip_values(in, parametric ? static_cast<std::uint64_t>(entity_dim) : 0, true, "parametric coordinate");
  }
  total += n;
}

enum class Role { cell, facet, skip };

/// 1 or 2 if `type` is the cell or facet type of that order in a mesh of
/// dimension `dim`, else 0.
int simplex_order(const ElementType& type, int dim) {
  for (const int order : {1, 2})
    if (type.number == cell_type(dim, order) || type.number == facet_type(dim, order)) return order;
  return 0;
}

Role element_role(MshCursor& in, std::size_t at, const ElementType& type, int entity_dim, int dim) {
  if (type.dim != entity_dim)
    in.fail(at, fmt::format("element type {} ({}) in an entity of dimension {} (expected dimension {})", type.number,
                            type.name, entity_dim, type.dim));
  const ElementType& cell = *find_element_type(cell_type(dim, 1));
  if (type.dim > dim)
    in.fail(at, fmt::format("element type {} ({}) in a {}D mesh (expected {}; is the mesh {}D?)", type.number,
                            type.name, dim, cell.name, type.dim));
  const int order = simplex_order(type, dim);
  if (type.dim == dim && order == 0)
    in.fail(at, fmt::format("unsupported element type {} ({}): conserve needs {}", type.number, type.name,
                            dim == 3 ? "4-node tetrahedra (type 4) or 10-node ones (type 11)"
                                     : "3-node triangles (type 2) or 6-node ones (type 9)"));
  if (type.dim == dim) return Role::cell;
  return order != 0 ? Role::facet : Role::skip;
}

/// The first block of cells or facets sets the file's order; a block of
/// the other order is refused (a mesh has one order).
void check_order(MshCursor& in, MshContent& content, std::size_t at, const ElementType& type, std::uint64_t n) {
  const int order = simplex_order(type, content.dim);
  if (order == 0 || n == 0) return;
  if (content.order == 0) {
    content.order = order;
    content.order_type = type.number;
    content.order_offset = at;
    return;
  }
  if (order == content.order) return;
  const ElementType& first = *find_element_type(content.order_type);
  const auto kind = [](int o) { return o == 1 ? "linear" : "quadratic"; };
  in.fail(at, fmt::format("element type {} ({}) is {} but the block at {} holds type {} ({}), which is {} "
                          "(expected one order in a file: linear cells and facets, or quadratic ones)",
                          type.number, type.name, kind(order), in.location(content.order_offset), first.number,
                          first.name, kind(content.order)));
}

void read_element_block(MshCursor& in, MshContent& content, std::uint64_t& total) {
  const std::size_t at = in.value_start();
  const int entity_dim = read_dim(in, "entity dimension");
  const int entity = in.read_int("entity tag");
  const int type_number = in.read_int("element type");
  const ElementType* type = find_element_type(type_number);
  if (type == nullptr) in.fail(at, fmt::format("unknown element type {} (expected a Gmsh element type)", type_number));
  const Role role = element_role(in, at, *type, entity_dim, content.dim);
  const auto nn = static_cast<std::size_t>(type->num_nodes);
  const std::uint64_t n = in.read_count("number of elements in block", 1 + nn, 8 * (1 + nn));
  check_order(in, content, at, *type, n);
  for (std::uint64_t i = 0; i < n; ++i) {
    RawElement element{.tag = 0, .entity = entity, .offset = in.value_start(), .nodes = {}};
    element.tag = in.read_size("element tag");
    for (std::size_t k = 0; k < nn; ++k) {
      const std::uint64_t node = in.read_size("node tag");
      if (role != Role::skip) element.nodes[k] = node;  // a kept type has at most 10 nodes
    }
    if (role == Role::cell) content.cells.push_back(element);
    if (role == Role::facet) content.facets.push_back(element);
  }
  if (role == Role::skip && type->dim == content.dim - 1 && n > 0 && content.other_facet_type == 0) {
    content.other_facet_type = type->number;
    content.other_facet_offset = at;
  }
  total += n;
}

}  // namespace

int cell_type(int dim, int order) {
  if (dim == 2) return order == 2 ? 9 : 2;
  return order == 2 ? 11 : 4;
}

int facet_type(int dim, int order) {
  if (dim == 2) return order == 2 ? 8 : 1;
  return order == 2 ? 9 : 2;
}

const ElementType* find_element_type(int number) {
  for (const ElementType& type : kElementTypes)
    if (type.number == number) return &type;
  return nullptr;
}

void parse_mesh_format(MshCursor& in, MshContent& content) {
  in.at_end();
  const std::size_t at = in.offset();
  const std::string_view version = in.word();
  double value = 0.0;
  const auto result = std::from_chars(version.data(), version.data() + version.size(), value);
  if (result.ec != std::errc() || result.ptr != version.data() + version.size() || std::abs(value - 4.1) > 1e-9)
    in.fail(at, fmt::format("unsupported MSH version '{}' (expected 4.1; export with gmsh -format msh41)",
                            printable(version)));
  const std::size_t type_at = in.value_start();
  const int file_type = in.read_int("file type");
  if (file_type != 0 && file_type != 1)
    in.fail(type_at, fmt::format("file type {} (expected 0 for ASCII or 1 for binary)", file_type));
  const std::size_t size_at = in.value_start();
  const int data_size = in.read_int("data size");
  if (data_size != 8) in.fail(size_at, fmt::format("data size {} (expected 8)", data_size));
  if (file_type == 1) {
    in.skip_line();
    in.set_binary(true);
    const std::size_t one_at = in.offset();
    if (in.read_raw_int32() != 1)
      in.fail(one_at,
              "endianness check failed (expected the binary int 1; file written on a machine of the other "
              "byte order, or corrupt)");
  }
  content.has_format = true;
  in.expect_section_end();
}

void parse_physical_names(MshCursor& in, MshContent& content) {
  in.set_text_values(true);
  const std::uint64_t n = in.read_count("number of physical names", 3, 0);
  for (std::uint64_t i = 0; i < n; ++i) {
    const int dim = read_dim(in, "physical dimension");
    const int tag = in.read_int("physical tag");
    content.physical_names[{dim, tag}] = in.quoted();
  }
  in.set_text_values(false);
  in.expect_section_end();
}

void parse_entities(MshCursor& in, MshContent& content) {
  std::uint64_t counts[4] = {};
  counts[0] = in.read_count("number of points", 5, 36);
  counts[1] = in.read_count("number of curves", 9, 68);
  counts[2] = in.read_count("number of surfaces", 9, 68);
  counts[3] = in.read_count("number of volumes", 9, 68);
  for (int dim = 0; dim < 4; ++dim)
    for (std::uint64_t i = 0; i < counts[dim]; ++i) read_one_entity(in, content, dim);
  in.expect_section_end();
}

void parse_nodes(MshCursor& in, MshContent& content) {
  const std::size_t at = in.value_start();
  const std::uint64_t blocks = in.read_count("number of node blocks", 4, 20);
  const std::uint64_t declared = in.read_size("number of nodes");
  in.read_size("minimum node tag");
  in.read_size("maximum node tag");
  std::uint64_t total = 0;
  for (std::uint64_t b = 0; b < blocks; ++b) read_node_block(in, content, total);
  check_total(in, at, declared, total, "nodes");
  in.expect_section_end();
}

void parse_elements(MshCursor& in, MshContent& content) {
  const std::size_t at = in.value_start();
  const std::uint64_t blocks = in.read_count("number of element blocks", 4, 20);
  const std::uint64_t declared = in.read_size("number of elements");
  in.read_size("minimum element tag");
  in.read_size("maximum element tag");
  std::uint64_t total = 0;
  for (std::uint64_t b = 0; b < blocks; ++b) read_element_block(in, content, total);
  check_total(in, at, declared, total, "elements");
  in.expect_section_end();
}

}  // namespace conserve::mesh::detail
