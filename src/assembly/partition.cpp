#include "assembly/partition.hpp"

#include <algorithm>
#include <stdexcept>

namespace conserve::assembly {

NodePartition partition_nodes(int num_nodes, const Eigen::MatrixXi& cells, int parts, int first, int end) {
  if (end < 0) end = num_nodes;
  if (first < 0 || first > end || end > num_nodes) throw std::invalid_argument("partition_nodes: bad node range");
  if (parts < 1) throw std::invalid_argument("partition_nodes: parts must be at least 1");
  if (cells.rows() > kMaxCorners) throw std::invalid_argument("partition_nodes: at most 16 nodes per cell");
  std::vector<long long> before(static_cast<std::size_t>(num_nodes) + 1, 0);  // corners at nodes < n
  for (Eigen::Index i = 0; i < cells.size(); ++i) ++before[static_cast<std::size_t>(cells.data()[i]) + 1];
  for (int n = 0; n < num_nodes; ++n) before[n + 1] += before[n];

  NodePartition p;
  p.first_node.resize(static_cast<std::size_t>(parts) + 1);
  for (int k = 0; k <= parts; ++k) {
    // The first node with at least k/parts of the range's corners before it.
    const long long target = before[first] + (before[end] - before[first]) * k / parts;
    p.first_node[k] =
        k == 0       ? first
        : k == parts ? end
                     : static_cast<int>(std::lower_bound(before.begin() + first, before.begin() + end + 1, target) -
                                        before.begin());
    if (k > 0) p.first_node[k] = std::max(p.first_node[k], p.first_node[k - 1]);
  }
  std::vector<int> part_of(num_nodes, -1);
  for (int k = 0; k < parts; ++k)
    std::fill(part_of.begin() + p.first_node[k], part_of.begin() + p.first_node[k + 1], k);

  // Count, then fill, the visits part by part in ascending cell order.
  const int corners_per_cell = static_cast<int>(cells.rows());
  std::vector<std::vector<std::pair<int, CornerMask>>> visits(parts);
  for (int c = 0; c < cells.cols(); ++c) {
    CornerMask owned[kMaxCorners] = {};
    int touched[kMaxCorners], num_touched = 0;
    for (int a = 0; a < corners_per_cell; ++a) {
      const int k = part_of[cells(a, c)];
      if (k < 0) continue;  // a node outside the range
      int t = 0;
      while (t < num_touched && touched[t] != k) ++t;
      if (t == num_touched) touched[num_touched++] = k;
      owned[t] |= static_cast<CornerMask>(1u << a);
    }
    for (int t = 0; t < num_touched; ++t) visits[touched[t]].emplace_back(c, owned[t]);
  }
  p.visit_start.assign(1, 0);
  for (const auto& v : visits) {
    for (const auto& [cell, owned] : v) p.visit_cell.push_back(cell), p.visit_owned.push_back(owned);
    p.visit_start.push_back(static_cast<int>(p.visit_cell.size()));
  }
  return p;
}

}  // namespace conserve::assembly
