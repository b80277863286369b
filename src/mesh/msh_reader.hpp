#pragma once
/// Reader for Gmsh `.msh` version 4.1 files, ASCII and binary.
#include <filesystem>
#include <string>
#include <string_view>

#include "mesh/mesh.hpp"

namespace conserve::mesh {

/// Whether a file without cells of the mesh's dimension may be read as a
/// bare surface (surface_mesh.hpp), as a rigid body's mesh may be.
enum class BareSurface { rejected, accepted };

/// Reads a mesh of dimension `dim` (2: triangles, plane z = 0; 3:
/// tetrahedra), linear (Gmsh types 2 / 4, facets 1 / 2) or quadratic (types
/// 9 / 11, facets 8 / 9; every node kept, midside nodes too, in Gmsh's node
/// order, mesh.hpp). Cells of dimension `dim` become Mesh::cells, named
/// physical groups of dimension `dim` become cell groups and named physical
/// groups of dimension `dim-1` (segments / triangles of the cells' order)
/// facet groups. Lower-dimensional elements outside named groups are ignored
/// (a physical group without a name in $PhysicalNames is named by its
/// number, e.g. "3"); facets of facet groups that lie on the boundary are
/// oriented outward, as in boundary_facets(). Only nodes used by cells are
/// kept (renumbered 0..n-1 in file order).
///
/// With `bare` = accepted, a file with no such cells but with elements of
/// dimension `dim-1` (3-node triangles in 3D, 2-node lines in 2D) is a bare
/// surface: no cells, every such element a facet in its file order and
/// orientation (facet groups "surface" and "boundary" hold all of them,
/// unless the file names a group so; the physical groups of dimension
/// `dim-1` are facet groups as above), its nodes numbered in the order the
/// facets first use them (as an STL file's, stl_reader.hpp). Its facets
/// must be linear, consistently oriented (surface_mesh.hpp,
/// orientation_clash) and none degenerate.
///
/// Throws InputError "FILE:LINE: what is wrong" (line of the offending
/// entry; for binary files the byte offset) on malformed, truncated or
/// inconsistent input, unsupported cell types (e.g. cubic tets, hexes),
/// cells and facets of both orders in one file, 2D meshes with z != 0,
/// inverted or degenerate cells (their vertex simplex), quadratic cells
/// whose Jacobian determinant is not positive at their vertices and
/// centroid, and surfaces whose facets are quadratic, degenerate, not
/// simplices or not consistently oriented.
Mesh read_msh(const std::filesystem::path& file, int dim, BareSurface bare = BareSurface::rejected);

/// Same, from the bytes of a file; `name` is used in error messages.
Mesh parse_msh(std::string_view bytes, const std::string& name, int dim, BareSurface bare = BareSurface::rejected);

}  // namespace conserve::mesh
