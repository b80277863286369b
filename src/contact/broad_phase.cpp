#include "contact/broad_phase.hpp"

#include "contact/curved_facet.hpp"

#include <algorithm>
#include <array>

namespace conserve::contact {

namespace {

/// Facets per leaf at most.
constexpr int kLeafSize = 4;

template <int D>
using Box = Eigen::AlignedBox<double, D>;

/// The axis-aligned box of facet f: of its nodes if linear, of its Bézier
/// control points if quadratic (CurvedFacet::box: a curved facet leaves
/// its nodes' box). The tree and the oracle both use this, so that their
/// answers are bit-for-bit the same.
template <int D>
Box<D> facet_box(const Eigen::MatrixXi& facets, const Positions<D>& x, int f) {
  if (facets.rows() != D) {
    typename CurvedFacet<D>::Nodes nodes;
    for (int i = 0; i < CurvedFacet<D>::kNodes; ++i) nodes.col(i) = x.col(facets(i, f));
    const auto [lo, hi] = CurvedFacet<D>::box(nodes);
    return Box<D>(lo, hi);
  }
  Box<D> box(x.col(facets(0, f)));
  for (int i = 1; i < D; ++i) box.extend(x.col(facets(i, f)));
  return box;
}

/// Whether the closed box enlarged by `radius` contains `p` (the one test
/// both the tree and the oracle apply to facets).
template <int D>
bool reaches(const Box<D>& box, const Vec<D>& p, double radius) {
  for (int i = 0; i < D; ++i)
    if (p(i) < box.min()(i) - radius || p(i) > box.max()(i) + radius) return false;
  return true;
}

}  // namespace

template <int D>
void FacetTree<D>::build(const Eigen::MatrixXi& facets, const Positions<D>& x) {
  facets_ = facets;
  const int n = static_cast<int>(facets.cols());
  Positions<D> centroids(D, n);
  for (int f = 0; f < n; ++f) {
    centroids.col(f).setZero();
    for (int i = 0; i < D; ++i) centroids.col(f) += x.col(facets(i, f));
    centroids.col(f) /= D;
  }
  order_.resize(static_cast<std::size_t>(n));
  for (int f = 0; f < n; ++f) order_[static_cast<std::size_t>(f)] = f;
  nodes_.clear();
  nodes_.reserve(static_cast<std::size_t>(2 * (n / kLeafSize + 1)));
  if (n > 0) build_node(0, n, centroids);
  refit(x);
}

/// Creates the node over order_[first, first + count) and, below it, its
/// subtree (median split along the longest axis of the centroids' box).
/// Returns the node's index.
template <int D>
int FacetTree<D>::build_node(int first, int count, const Positions<D>& centroids) {
  const int index = static_cast<int>(nodes_.size());
  nodes_.push_back({first, count, -1});
  if (count <= kLeafSize) return index;
  Box<D> spread;
  for (int j = first; j < first + count; ++j) spread.extend(centroids.col(order_[static_cast<std::size_t>(j)]));
  int axis = 0;
  spread.sizes().maxCoeff(&axis);
  const int half = count / 2;
  const auto begin = order_.begin() + first;
  std::nth_element(begin, begin + half, begin + count,
                   [&](int a, int b) { return centroids(axis, a) < centroids(axis, b); });
  nodes_[static_cast<std::size_t>(index)].count = 0;  // inner node
  build_node(first, half, centroids);
  const int right = build_node(first + half, count - half, centroids);
  nodes_[static_cast<std::size_t>(index)].right = right;
  return index;
}

template <int D>
void FacetTree<D>::refit(const Positions<D>& x) {
  leaf_boxes_.resize(order_.size());
  for (std::size_t j = 0; j < order_.size(); ++j) leaf_boxes_[j] = facet_box<D>(facets_, x, order_[j]);
  boxes_.resize(nodes_.size());
  // children follow their parent in nodes_, so one backward sweep suffices
  for (int i = static_cast<int>(nodes_.size()) - 1; i >= 0; --i) {
    const Node& node = nodes_[static_cast<std::size_t>(i)];
    Box<D>& box = boxes_[static_cast<std::size_t>(i)];
    if (node.count > 0) {
      box.setEmpty();
      for (int j = node.first; j < node.first + node.count; ++j) box.extend(leaf_boxes_[static_cast<std::size_t>(j)]);
    } else {
      box = boxes_[static_cast<std::size_t>(i + 1)].merged(boxes_[static_cast<std::size_t>(node.right)]);
    }
  }
}

template <int D>
void FacetTree<D>::query(const Vec<D>& point, double radius, std::vector<int>& out) const {
  out.clear();
  if (nodes_.empty()) return;
  // depth ≤ log2(n) + 1 for median splits: 128 entries is far more than enough
  std::array<int, 128> stack{};
  int top = 0;
  stack[static_cast<std::size_t>(top++)] = 0;
  while (top > 0) {
    const int i = stack[static_cast<std::size_t>(--top)];
    if (!reaches<D>(boxes_[static_cast<std::size_t>(i)], point, radius)) continue;
    const Node& node = nodes_[static_cast<std::size_t>(i)];
    if (node.count > 0) {
      for (int j = node.first; j < node.first + node.count; ++j)
        if (reaches<D>(leaf_boxes_[static_cast<std::size_t>(j)], point, radius))
          out.push_back(order_[static_cast<std::size_t>(j)]);
    } else {
      stack[static_cast<std::size_t>(top++)] = node.right;
      stack[static_cast<std::size_t>(top++)] = i + 1;
    }
  }
  std::sort(out.begin(), out.end());
}

template <int D>
int FacetTree<D>::num_facets() const {
  return static_cast<int>(facets_.cols());
}

template <int D>
void brute_force_query(const Eigen::MatrixXi& facets, const Positions<D>& x, const Vec<D>& point, double radius,
                       std::vector<int>& out) {
  out.clear();
  for (int f = 0; f < facets.cols(); ++f)
    if (reaches<D>(facet_box<D>(facets, x, f), point, radius)) out.push_back(f);
}

template class FacetTree<2>;
template class FacetTree<3>;
template void brute_force_query<2>(const Eigen::MatrixXi&, const Positions<2>&, const Vec<2>&, double,
                                   std::vector<int>&);
template void brute_force_query<3>(const Eigen::MatrixXi&, const Positions<3>&, const Vec<3>&, double,
                                   std::vector<int>&);

}  // namespace conserve::contact
