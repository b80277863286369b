#pragma once
/// Reader for STL files (ASCII or binary) through the Gmsh API: a triangle
/// surface, the bare surface of a rigid body.
#include <filesystem>

#include "mesh/mesh.hpp"
#include "mesh/msh_reader.hpp"

namespace conserve::mesh {

/// Reads the triangles of an STL file as a 3D bare surface
/// (surface_mesh.hpp): facet groups "surface" and "boundary" hold every
/// triangle in file order. Gmsh merges the file's repeated corners (its
/// STL reader, then gmsh::model::mesh::removeDuplicateNodes, both within
/// Geometry.Tolerance = 1e-8 of the bounding box's diagonal), so that
/// neighbouring triangles share nodes; the nodes are numbered in the order
/// the triangles first use them (as read_msh numbers a surface's). A
/// triangle's orientation is its corners' order (right-hand rule); the
/// normal stored in the file is ignored, as by Gmsh.
/// Throws InputError "FILE: what is wrong" if the file is neither an ASCII
/// STL (starting with "solid") nor a binary one of 84 + 50 × N bytes, if
/// Gmsh reads another number of triangles than the file holds, or if a
/// triangle is degenerate or the triangles are not consistently oriented
/// (orientation_clash), naming the triangles by their place in the file
/// (from 1) and the shared edge by its corners.
Mesh read_stl(const std::filesystem::path& file);

/// A .msh file (read_msh, with `bare`) or, for the extension .stl (any
/// case), an STL file (read_stl; InputError unless dim = 3 and `bare` =
/// accepted).
Mesh read_mesh_file(const std::filesystem::path& file, int dim, BareSurface bare);

}  // namespace conserve::mesh
