#pragma once
/// Topological helpers on simplex meshes, linear or quadratic (mesh.hpp).
#include <string>
#include <vector>

#include "mesh/mesh.hpp"

namespace conserve::mesh {

/// Boundary facets (faces used by exactly one cell), ordered so that their
/// normal (right-hand rule in 3D; (t_y, -t_x) for the segment tangent t in
/// 2D) points out of the cell. facet_nodes(dim, order) × n_facets: the
/// vertices first, then for a quadratic mesh the midside node of each edge
/// of the facet in its vertex order (line3: 0, 1, mid; tri6: 3 = (0,1),
/// 4 = (1,2), 5 = (2,0)), as Gmsh orders them.
Eigen::MatrixXi boundary_facets(const Mesh& mesh);

/// Gives each facet of `facets` that is also a facet of `boundary` (as
/// returned by boundary_facets, the same number of rows) that facet's
/// outward node order: facets are matched by their vertices and the whole
/// column (midside nodes included) is copied. Returns how many facets are
/// not on the boundary (left unchanged). Throws std::invalid_argument if
/// the row counts differ.
int orient_outward(Eigen::MatrixXi& facets, const Eigen::MatrixXi& boundary);

/// The sub-mesh made of the cells of group `group` (all cells if `group` is
/// empty), nodes renumbered (midside nodes too), facet groups restricted to
/// facets whose nodes all belong to it (dropped if empty). Throws InputError
/// if the group does not exist (message lists the groups there are).
Mesh extract(const Mesh& mesh, const std::string& group);

/// The neighbours of each node through the cells (every node of a cell is
/// a neighbour of every other, midside nodes included), as
/// offsets/neighbours (node v's are neighbours[offsets[v] … offsets[v+1]),
/// ascending).
void node_graph(const Mesh& mesh, std::vector<int>& offsets, std::vector<int>& neighbours);

/// The same mesh with node order[k] numbered k (order: a permutation of
/// the nodes) and its cells sorted by their lowest new node (ties in their
/// old order), groups following: with a band-narrowing order, a loop over
/// the cells then walks through the nodes' data instead of jumping.
/// Throws std::invalid_argument if `order` is not a permutation.
Mesh renumbered(const Mesh& mesh, const std::vector<int>& order);

/// Signed volume [m³] (3D) or signed area [m²] (2D) of cell `cell`'s vertex
/// simplex: the cell's own for a linear or straight-sided quadratic cell.
double vertex_volume(const Mesh& mesh, int cell);

/// Signed volume [m³] (3D) or signed area [m²] (2D) of cell `cell`: the
/// integral of the Jacobian determinant of its map from the reference
/// simplex, positive when the cell is positively oriented. Linear cells:
/// vertex_volume. Quadratic cells: det J is a polynomial of degree 2 (tri6)
/// or 3 (tet10), integrated by the 3-point rule of degree 2 / the 5-point
/// rule of degree 3, so the value is exact (to round-off) for curved cells
/// too.
double signed_volume(const Mesh& mesh, int cell);

/// How a cell's vertex simplex is oriented: positive, inverted (negative
/// vertex_volume) or degenerate (|vertex_volume| ≤ 1e-12 · (longest
/// edge)^dim). For a quadratic cell see also is_folded.
enum class CellOrientation { positive, inverted, degenerate };
CellOrientation cell_orientation(const Mesh& mesh, int cell);

/// The smallest determinant of the Jacobian ∂x/∂ξ of cell `cell`'s map
/// from the reference simplex (Gmsh's shape functions, mesh.hpp) at its
/// vertices and its centroid. Linear cells: the constant dim!·vertex_volume.
/// These dim+2 points are a necessary check, not a proof that det J > 0
/// everywhere in a curved cell.
double min_jacobian_determinant(const Mesh& mesh, int cell);

/// A quadratic cell whose map folds over where checked: its
/// min_jacobian_determinant ≤ 1e-12 · (longest vertex edge)^dim (a midside
/// node too far off its edge), even if its vertex simplex is positive.
/// Always false for a linear cell.
bool is_folded(const Mesh& mesh, int cell);

/// Reverses cell `cell`'s orientation: swaps its vertices 1 and 2 and, of
/// a quadratic cell, the midside nodes that follow them, tri6 3 ↔ 5 (edges
/// (0,1) ↔ (2,0)), tet10 4 ↔ 6 and 8 ↔ 9 ((0,1) ↔ (2,0), (3,2) ↔ (3,1)).
void flip_cell(Mesh& mesh, int cell);

/// Total volume [m³] (area [m²] in 2D): the sum of the signed volumes
/// (exact for curved quadratic cells too, see signed_volume).
double total_volume(const Mesh& mesh);

/// Throws InputError "NAME: cell K is inverted/degenerate (signed volume V)"
/// for the first cell whose vertex simplex is not positive, or "NAME: cell
/// K is folded (...)" for the first folded quadratic cell.
void check_orientation(const Mesh& mesh, const std::string& name);

}  // namespace conserve::mesh
