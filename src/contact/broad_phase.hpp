#pragma once
/// Broad phase: a bounding-volume tree (axis-aligned boxes) over a set of
/// facets, rebuilt or refitted as the nodes move, returning the facets whose
/// box, enlarged by a search distance, contains a query point.
#include <vector>

#include "core/types.hpp"

namespace conserve::contact {

/// Positions of all nodes of a model, D × n_nodes (current or mid-point).
template <int D>
using Positions = Eigen::Matrix<double, D, Eigen::Dynamic>;

template <int D>
class FacetTree {
 public:
  /// Builds the tree over `facets` (D × n linear facets, or 3 × n / 6 × n
  /// quadratic ones; node numbers into `x`).
  void build(const Eigen::MatrixXi& facets, const Positions<D>& x);
  /// Updates the boxes for moved nodes, keeping the tree's topology (O(n)).
  /// Queries stay exact; only their speed depends on how much things moved.
  void refit(const Positions<D>& x);
  /// Appends to `out` (cleared first) every facet whose box enlarged by
  /// `radius` contains `point`, in increasing facet order.
  void query(const Vec<D>& point, double radius, std::vector<int>& out) const;
  [[nodiscard]] int num_facets() const;

 private:
  /// A tree node. Nodes are stored in depth-first order: an inner node's
  /// left child follows it, `right` is its right child. A leaf (count > 0)
  /// holds the facets order_[first, first + count).
  struct Node {
    int first = 0;
    int count = 0;
    int right = -1;
  };
  int build_node(int first, int count, const Positions<D>& centroids);
  Eigen::MatrixXi facets_;
  std::vector<Node> nodes_;
  std::vector<int> order_;                                ///< facet numbers, grouped by leaf
  std::vector<Eigen::AlignedBox<double, D>> boxes_;       ///< per tree node
  std::vector<Eigen::AlignedBox<double, D>> leaf_boxes_;  ///< per entry of order_: that facet's box
};

/// The oracle: the same answer by checking every facet.
template <int D>
void brute_force_query(const Eigen::MatrixXi& facets, const Positions<D>& x, const Vec<D>& point, double radius,
                       std::vector<int>& out);

}  // namespace conserve::contact
