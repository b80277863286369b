#pragma once
/// Topological helpers on simplex meshes.
#include <string>
#include <vector>

#include "mesh/mesh.hpp"

namespace conserve::mesh {

/// Boundary facets (faces used by exactly one cell), ordered so that their
/// normal (right-hand rule in 3D; (t_y, -t_x) for the segment tangent t in
/// 2D) points out of the cell. dim × n_facets.
Eigen::MatrixXi boundary_facets(const Mesh& mesh);

/// Gives each facet of `facets` (dim × n) that is also a facet of
/// `boundary` (as returned by boundary_facets) that facet's outward node
/// order. Returns how many facets are not on the boundary (left unchanged).
int orient_outward(Eigen::MatrixXi& facets, const Eigen::MatrixXi& boundary);

/// The sub-mesh made of the cells of group `group` (all cells if `group` is
/// empty), nodes renumbered, facet groups restricted to facets whose nodes
/// all belong to it (dropped if empty). Throws InputError if the group does
/// not exist (message lists the groups there are).
Mesh extract(const Mesh& mesh, const std::string& group);

/// The neighbours of each node through the cells, as offsets/neighbours
/// (node v's are neighbours[offsets[v] … offsets[v+1]), ascending).
void node_graph(const Mesh& mesh, std::vector<int>& offsets, std::vector<int>& neighbours);

/// The same mesh with node order[k] numbered k (order: a permutation of
/// the nodes) and its cells sorted by their lowest new node (ties in their
/// old order), groups following: with a band-narrowing order, a loop over
/// the cells then walks through the nodes' data instead of jumping.
/// Throws std::invalid_argument if `order` is not a permutation.
Mesh renumbered(const Mesh& mesh, const std::vector<int>& order);

/// Signed volume [m³] (3D) or signed area [m²] (2D) of cell `cell`:
/// positive when the cell is positively oriented.
double signed_volume(const Mesh& mesh, int cell);

/// How a cell is oriented: positive, inverted (negative signed volume) or
/// degenerate (|signed volume| ≤ 1e-12 · (longest edge)^dim).
enum class CellOrientation { positive, inverted, degenerate };
CellOrientation cell_orientation(const Mesh& mesh, int cell);

/// Total volume [m³] (area [m²] in 2D): the sum of the signed volumes.
double total_volume(const Mesh& mesh);

/// Throws InputError "NAME: cell K is inverted/degenerate (signed volume V)"
/// for the first cell whose signed volume is not positive.
void check_orientation(const Mesh& mesh, const std::string& name);

}  // namespace conserve::mesh
