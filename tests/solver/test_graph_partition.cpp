// The nodes' parts for several ranks (solver/graph_partition.hpp), on
// graphs whose good cuts are known.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "solver/graph_partition.hpp"

namespace {

using conserve::solver::edge_cut;
using conserve::solver::partition_graph;

/// The node graph of an nx × ny × nz grid (each node its own neighbour,
/// and its 6 face neighbours), numbered x fastest.
struct Graph {
  std::vector<int> offsets{0}, neighbours;
};

Graph grid(int nx, int ny, int nz) {
  Graph g;
  const auto id = [&](int i, int j, int k) { return i + nx * (j + ny * k); };
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        std::vector<int> n = {id(i, j, k)};
        if (i > 0) n.push_back(id(i - 1, j, k));
        if (i + 1 < nx) n.push_back(id(i + 1, j, k));
        if (j > 0) n.push_back(id(i, j - 1, k));
        if (j + 1 < ny) n.push_back(id(i, j + 1, k));
        if (k > 0) n.push_back(id(i, j, k - 1));
        if (k + 1 < nz) n.push_back(id(i, j, k + 1));
        std::sort(n.begin(), n.end());
        g.neighbours.insert(g.neighbours.end(), n.begin(), n.end());
        g.offsets.push_back(static_cast<int>(g.neighbours.size()));
      }
  return g;
}

TEST(GraphPartition, TwoSeparateBodiesAreCutNowhere) {
  // Two 6 × 6 × 6 grids, the second numbered after the first.
  const Graph one = grid(6, 6, 6);
  Graph two = one;
  const int n = static_cast<int>(one.offsets.size()) - 1;
  for (std::size_t B = 1; B < one.offsets.size(); ++B) two.offsets.push_back(one.offsets[B] + one.offsets.back());
  for (const int v : one.neighbours) two.neighbours.push_back(v + n);
  const auto p = partition_graph(two.offsets, two.neighbours, 2);
  EXPECT_EQ(p.cut, 0);
  EXPECT_EQ(edge_cut(two.offsets, two.neighbours, p.part), 0);
  EXPECT_EQ(std::count(p.part.begin(), p.part.end(), 0), n);
}

TEST(GraphPartition, ThinSlabsLoseToPtScotchOnABlock) {
  // A 24 × 24 × 24 block in 8 parts: contiguous ranges of the x-fastest
  // order are slabs of 3 layers, 7 × 576 edges cut; PT-Scotch's cut is
  // well below (eight 12³ cubes would cut 3 × 576). Each part holds about
  // an eighth of the work.
  const Graph g = grid(24, 24, 24);
  const auto p = partition_graph(g.offsets, g.neighbours, 8);
  EXPECT_TRUE(p.scotch);
  EXPECT_LT(p.cut, 7 * 576);
  EXPECT_EQ(p.cut, edge_cut(g.offsets, g.neighbours, p.part));
  std::vector<long> work(8, 0);
  for (std::size_t B = 0; B + 1 < g.offsets.size(); ++B) work[p.part[B]] += g.offsets[B + 1] - g.offsets[B];
  const long total = g.offsets.back();
  for (const long w : work) EXPECT_NEAR(static_cast<double>(w), total / 8.0, 0.1 * total / 8.0);
}

TEST(GraphPartition, ThickSlabsAreKeptWhenTheyCutLeast) {
  // A long 40 × 4 × 4 bar in 2 parts: the middle slab cuts 16 edges, no
  // partition cuts fewer; contiguous ranges are kept unless beaten.
  const Graph g = grid(4, 4, 40);
  const auto p = partition_graph(g.offsets, g.neighbours, 2);
  EXPECT_EQ(p.cut, 16);
}

}  // namespace
