#pragma once
/// Reader for Gmsh `.msh` version 4.1 files, ASCII and binary.
#include <filesystem>
#include <string>
#include <string_view>

#include "mesh/mesh.hpp"

namespace conserve::mesh {

/// Reads a mesh of dimension `dim` (2: 3-node triangles, plane z = 0;
/// 3: 4-node tetrahedra). Cells of dimension `dim` become Mesh::cells,
/// named physical groups of dimension `dim` become cell groups and named
/// physical groups of dimension `dim-1` (segments / triangles) facet groups.
/// Lower-dimensional elements outside named groups are ignored (a physical
/// group without a name in $PhysicalNames is named by its number, e.g. "3");
/// facets of facet groups that lie on the boundary are oriented outward, as
/// in boundary_facets(). Only nodes
/// used by cells are kept (renumbered 0..n-1 in file order).
/// Throws InputError "FILE:LINE: what is wrong" (line of the offending
/// entry; for binary files the byte offset) on malformed, truncated or
/// inconsistent input, unsupported cell types (e.g. quadratic tets, hexes),
/// 2D meshes with z != 0, and inverted or degenerate cells.
Mesh read_msh(const std::filesystem::path& file, int dim);

/// Same, from the bytes of a file; `name` is used in error messages.
Mesh parse_msh(std::string_view bytes, const std::string& name, int dim);

}  // namespace conserve::mesh
