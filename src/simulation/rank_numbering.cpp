#include "simulation/rank_numbering.hpp"

#include <algorithm>
#include <cstdint>
#include <numeric>

#include "mesh/topology.hpp"
#include "solver/graph_partition.hpp"

namespace conserve::simulation {

RankNumbering number_for_ranks(std::vector<mesh::Mesh>& meshes, const std::vector<bool>& renumber, int ranks,
                               bool graph) {
  const auto bodies = meshes.size();
  // Each body's corners and first node; rank r's work is the corners in
  // [total·r/N, total·(r+1)/N) of the bodies' sequence.
  std::vector<std::int64_t> corners_before(bodies + 1, 0);
  std::vector<int> first_node(bodies + 1, 0);
  for (std::size_t b = 0; b < bodies; ++b) {
    corners_before[b + 1] = corners_before[b] + static_cast<std::int64_t>(meshes[b].cells.size());
    first_node[b + 1] = first_node[b] + static_cast<int>(meshes[b].points.cols());
  }
  const std::int64_t total = corners_before[bodies];
  const auto target = [&](int r) { return total * r / ranks; };
  RankNumbering n;
  n.rank_nodes.assign(static_cast<std::size_t>(ranks) + 1, -1);
  n.rank_nodes[0] = 0;
  n.rank_nodes[static_cast<std::size_t>(ranks)] = first_node[bodies];
  for (std::size_t b = 0; b < bodies; ++b) {
    mesh::Mesh& m = meshes[b];
    const std::int64_t from = corners_before[b], to = corners_before[b + 1];
    // The ranks whose work this body holds a part of (r_first … r_last).
    int r_first = ranks, r_last = -1;
    for (int r = 0; r < ranks; ++r)
      if (std::min(to, target(r + 1)) > std::max(from, target(r))) r_first = std::min(r_first, r), r_last = r;
    if (r_last <= r_first) continue;  // within one rank's range
    std::vector<int> part(static_cast<std::size_t>(m.points.cols()), 0);
    std::vector<int> offsets, neighbours;
    mesh::node_graph(m, offsets, neighbours);
    if (graph && renumber[b]) {
      std::vector<double> shares;
      for (int r = r_first; r <= r_last; ++r)
        shares.push_back(static_cast<double>(std::min(to, target(r + 1)) - std::max(from, target(r))) /
                         static_cast<double>(to - from));
      part = solver::partition_graph(offsets, neighbours, shares).part;
      std::vector<int> order(part.size());
      std::iota(order.begin(), order.end(), 0);
      std::stable_sort(order.begin(), order.end(), [&](int a, int c) { return part[a] < part[c]; });
      std::vector<int> sorted_part(part.size());
      for (std::size_t k = 0; k < order.size(); ++k) sorted_part[k] = part[static_cast<std::size_t>(order[k])];
      m = mesh::renumbered(m, order);
      part = std::move(sorted_part);
      n.by_parts = true;
    } else {
      // Contiguous: the first node with at least the rank's share of the
      // body's corners before it (assembly::partition_nodes's rule).
      std::vector<std::int64_t> before(part.size() + 1, 0);
      for (Eigen::Index i = 0; i < m.cells.size(); ++i) ++before[static_cast<std::size_t>(m.cells.data()[i]) + 1];
      for (std::size_t B = 0; B < part.size(); ++B) before[B + 1] += before[B];
      for (int r = r_first + 1; r <= r_last; ++r) {
        const auto cut = std::lower_bound(before.begin(), before.end(), target(r) - from) - before.begin();
        std::fill(part.begin() + std::min<std::ptrdiff_t>(cut, static_cast<std::ptrdiff_t>(part.size())), part.end(),
                  r - r_first);
      }
    }
    for (int r = r_first + 1; r <= r_last; ++r)
      n.rank_nodes[static_cast<std::size_t>(r)] =
          first_node[b] + static_cast<int>(std::lower_bound(part.begin(), part.end(), r - r_first) - part.begin());
  }
  // A rank starting between bodies starts with the first body whose
  // corners before it reach its share (or at the end).
  for (int r = 1; r < ranks; ++r) {
    if (n.rank_nodes[static_cast<std::size_t>(r)] >= 0) continue;
    std::size_t b = 0;
    while (b < bodies && corners_before[b] < target(r)) ++b;
    n.rank_nodes[static_cast<std::size_t>(r)] = first_node[b];
  }
  for (int r = 1; r <= ranks; ++r)
    n.rank_nodes[static_cast<std::size_t>(r)] =
        std::max(n.rank_nodes[static_cast<std::size_t>(r)], n.rank_nodes[static_cast<std::size_t>(r) - 1]);
  return n;
}

}  // namespace conserve::simulation
