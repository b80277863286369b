#pragma once
/// Contact surfaces: outward-oriented boundary facets of one body, in the
/// model's global node numbers, with node→facet and facet→facet adjacency.
#include <algorithm>
#include <array>
#include <initializer_list>
#include <string>
#include <vector>

#include "model/model.hpp"

namespace conserve::contact {

/// Most nodes of a master facet: a 3-node line (2D), a 6-node triangle (3D).
template <int D>
inline constexpr int kMaxFacetNodes = D * (D + 1) / 2;

/// The global node numbers of one master facet: its D vertices (linear)
/// or vertices then edge middles (quadratic, Gmsh's order). Iterates over
/// the facet's own nodes only.
template <int D>
class FacetIndex {
 public:
  FacetIndex() = default;
  /// Column f of a surface's facets (D or kMaxFacetNodes rows).
  FacetIndex(const Eigen::MatrixXi& facets, int f) : size_(static_cast<int>(facets.rows())) {
    for (int a = 0; a < size_; ++a) node_[static_cast<std::size_t>(a)] = facets(a, f);
  }
  /// The given nodes (at most kMaxFacetNodes).
  FacetIndex(std::initializer_list<int> nodes) : size_(static_cast<int>(nodes.size())) {
    std::copy(nodes.begin(), nodes.end(), node_.begin());
  }
  FacetIndex(const std::array<int, D>& nodes) : size_(D) { std::copy(nodes.begin(), nodes.end(), node_.begin()); }
  /// n nodes, numbered 0 until set (a record being read).
  void resize(int n) { size_ = n; }
  [[nodiscard]] int size() const { return size_; }
  int operator[](int a) const { return node_[static_cast<std::size_t>(a)]; }
  int& operator[](int a) { return node_[static_cast<std::size_t>(a)]; }
  [[nodiscard]] const int* begin() const { return node_.data(); }
  [[nodiscard]] const int* end() const { return node_.data() + size_; }
  int* begin() { return node_.data(); }
  int* end() { return node_.data() + size_; }
  friend bool operator==(const FacetIndex& a, const FacetIndex& b) {
    return a.size_ == b.size_ && std::equal(a.begin(), a.end(), b.begin());
  }

 private:
  std::array<int, kMaxFacetNodes<D>> node_{};
  int size_ = D;
};

/// A facet's shape values N_b(ξ), one per node (no heap).
template <int D>
using FacetWeights = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxFacetNodes<D>, 1>;

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
