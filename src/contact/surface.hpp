#pragma once
/// Contact surfaces: outward-oriented boundary facets of one body, in the
/// model's global node numbers, with node→facet and facet→facet adjacency.
#include <string>
#include <vector>

#include "model/model.hpp"

namespace conserve::contact {

struct ContactSurface {
  std::string name;  ///< "body:group", for messages
  int body = -1;     ///< index into Model::bodies
  /// D × n_facets global node numbers, outward oriented (mesh::boundary_facets convention).
  Eigen::MatrixXi facets;
  /// Sorted unique global node numbers of the facets.
  std::vector<int> nodes;
  /// node_facets[i]: facets (columns of `facets`) that contain nodes[i].
  std::vector<std::vector<int>> node_facets;
  /// facet_neighbours(k, f): the facet sharing with f the edge (3D) or vertex
  /// (2D) opposite f's local node k, or −1 on the surface's border.
  Eigen::MatrixXi facet_neighbours;
  /// Every degree of freedom of the surface's nodes is held: prescribed, or
  /// a free rigid body's (a rigid surface).
  bool rigid = false;

  [[nodiscard]] int num_facets() const { return static_cast<int>(facets.cols()); }
  /// Index of a global node in `nodes`, or −1.
  [[nodiscard]] int local_node(int global) const;
};

/// The surface of body `body` made of its facet group `group`; "boundary"
/// means all boundary facets of the body (computed from its cells when the
/// mesh has no such group). Throws InputError naming the body and group if
/// the group does not exist, is empty, or has facets that are not on the
/// body's boundary. `rigid` is set from the model's prescribed dofs.
template <int D>
ContactSurface make_surface(const model::Model<D>& model, int body, const std::string& group);

/// The longest edge of each facet of `surface` at positions x (D × the
/// model's nodes) [m]: the mesh size the search, the gap tolerances and
/// the coarse-slave warning measure a surface by.
template <int D>
std::vector<double> facet_sizes(const ContactSurface& surface, const Eigen::Matrix<double, D, Eigen::Dynamic>& x);

/// The median of facet_sizes [m] (0 for a surface without facets): which
/// of two surfaces is the finer.
template <int D>
double median_facet_size(const ContactSurface& surface, const Eigen::Matrix<double, D, Eigen::Dynamic>& x);

/// Adjacency from facets alone (used by make_surface; exposed for tests and
/// for surfaces that are not part of a model): sets `nodes`, `node_facets`
/// and `facet_neighbours` from `facets` (dim rows). A side shared by more
/// than two facets (non-manifold) gets no neighbour (−1).
void build_adjacency(ContactSurface& surface, int dim);

}  // namespace conserve::contact
