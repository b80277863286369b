// The nodes' split over ranks (simulation/rank_numbering.hpp): a body that
// ranks share is numbered part by part of a graph partition, with the
// ranks' shares of the work and fewer ghost nodes than contiguous ranges
// of its band; the split of `ranges` is assembly::partition_nodes's.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <vector>

#include "assembly/partition.hpp"
#include "mesh/generators.hpp"
#include "mesh/topology.hpp"
#include "simulation/rank_numbering.hpp"
#include "solver/ordering.hpp"

namespace conserve::simulation {
namespace {

/// A generated box in reverse Cuthill–McKee order, as setup numbers it.
mesh::Mesh box(double lx, double size) {
  mesh::Mesh m = mesh::generate_mesh("box", {{"lx", lx}, {"ly", 1.0}, {"lz", 1.0}, {"size", size}});
  std::vector<int> offsets, neighbours;
  mesh::node_graph(m, offsets, neighbours);
  return mesh::renumbered(m, solver::reverse_cuthill_mckee(offsets, neighbours));
}

/// The meshes one after the other, as the model holds them.
mesh::Mesh joined(const std::vector<mesh::Mesh>& meshes) {
  mesh::Mesh all;
  long nodes = 0, cells = 0;
  for (const auto& m : meshes) nodes += m.points.cols(), cells += m.cells.cols();
  all.points.resize(3, nodes);
  all.cells.resize(4, cells);
  int n = 0, c = 0;
  for (const auto& m : meshes) {
    all.points.middleCols(n, m.points.cols()) = m.points;
    all.cells.middleCols(c, m.cells.cols()) = m.cells.array() + n;
    n += static_cast<int>(m.points.cols());
    c += static_cast<int>(m.cells.cols());
  }
  return all;
}

struct Shares {
  std::vector<long> corners, ghosts;
};

/// Per rank: the corners of the cells at its nodes, and its ghost nodes
/// (other ranks' corners of the cells with a corner among its nodes).
Shares shares(const mesh::Mesh& m, const std::vector<int>& rank_nodes) {
  const int ranks = static_cast<int>(rank_nodes.size()) - 1;
  std::vector<int> rank_of(static_cast<std::size_t>(m.points.cols()));
  for (int r = 0; r < ranks; ++r) std::fill(rank_of.begin() + rank_nodes[r], rank_of.begin() + rank_nodes[r + 1], r);
  Shares s{std::vector<long>(ranks, 0), std::vector<long>(ranks, 0)};
  std::vector<std::vector<int>> ghosts(static_cast<std::size_t>(ranks));
  for (Eigen::Index c = 0; c < m.cells.cols(); ++c)
    for (int a = 0; a < 4; ++a) {
      const int r = rank_of[m.cells(a, c)];
      ++s.corners[r];
      for (int b = 0; b < 4; ++b)
        if (rank_of[m.cells(b, c)] != r) ghosts[r].push_back(m.cells(b, c));
    }
  for (int r = 0; r < ranks; ++r) {
    std::sort(ghosts[r].begin(), ghosts[r].end());
    s.ghosts[r] = std::unique(ghosts[r].begin(), ghosts[r].end()) - ghosts[r].begin();
  }
  return s;
}

TEST(RankNumbering, ABodyRanksShareIsNumberedByGraphPartsWithFewerGhosts) {
  const mesh::Mesh original = box(2.0, 0.12);
  std::vector<mesh::Mesh> graph = {original}, ranges = {original};
  const int ranks = 4;
  const RankNumbering g = number_for_ranks(graph, {true}, ranks, true);
  const RankNumbering r = number_for_ranks(ranges, {true}, ranks, false);
  EXPECT_TRUE(g.by_parts);
  EXPECT_FALSE(r.by_parts);
  EXPECT_EQ(ranges[0].points, original.points);  // untouched
  // The same mesh, renumbered: its nodes as a set and its volume.
  ASSERT_EQ(graph[0].points.cols(), original.points.cols());
  EXPECT_NE(graph[0].points, original.points);
  EXPECT_NEAR(mesh::total_volume(graph[0]), mesh::total_volume(original), 1e-12 * mesh::total_volume(original));
  // contiguous ranges covering the nodes
  const std::vector<int> expected =
      assembly::partition_nodes(static_cast<int>(original.points.cols()), original.cells, ranks).first_node;
  EXPECT_EQ(r.rank_nodes, expected);
  ASSERT_EQ(g.rank_nodes.size(), 5u);
  EXPECT_EQ(g.rank_nodes.front(), 0);
  EXPECT_EQ(g.rank_nodes.back(), original.points.cols());
  EXPECT_TRUE(std::is_sorted(g.rank_nodes.begin(), g.rank_nodes.end()));
  const Shares sg = shares(graph[0], g.rank_nodes), sr = shares(ranges[0], r.rank_nodes);
  const double each = static_cast<double>(original.cells.size()) / ranks;
  for (int k = 0; k < ranks; ++k) EXPECT_NEAR(sg.corners[k], each, 0.05 * each) << "rank " << k;
  const long most_g = *std::max_element(sg.ghosts.begin(), sg.ghosts.end());
  const long most_r = *std::max_element(sr.ghosts.begin(), sr.ghosts.end());
  std::printf("[ measured ] %ld nodes on %d ranks: most ghost nodes of a rank %ld by graph parts, %ld by ranges\n",
              static_cast<long>(original.points.cols()), ranks, most_g, most_r);
  EXPECT_LT(most_g, most_r);
}

TEST(RankNumbering, PartsFollowTheRanksSharesOfTwoBodies) {
  // 3 ranks on two boxes of 2 : 1 volume: rank 1 holds a share of each,
  // and each body stays one range of the numbering.
  std::vector<mesh::Mesh> meshes = {box(2.0, 0.15), box(1.0, 0.15)};
  const std::vector<mesh::Mesh> before = meshes;
  const int ranks = 3;
  const RankNumbering n = number_for_ranks(meshes, {true, true}, ranks, true);
  EXPECT_TRUE(n.by_parts);
  const mesh::Mesh all = joined(meshes);
  const Shares s = shares(all, n.rank_nodes);
  const double each = static_cast<double>(all.cells.size()) / ranks;
  for (int k = 0; k < ranks; ++k) EXPECT_NEAR(s.corners[k], each, 0.05 * each) << "rank " << k;
  for (std::size_t b = 0; b < meshes.size(); ++b)
    EXPECT_NEAR(mesh::total_volume(meshes[b]), mesh::total_volume(before[b]), 1e-12 * mesh::total_volume(before[b]));
  // A body the program may not renumber (a file's) is cut in ranges.
  std::vector<mesh::Mesh> kept = before;
  const RankNumbering k = number_for_ranks(kept, {false, false}, ranks, true);
  EXPECT_FALSE(k.by_parts);
  EXPECT_EQ(k.rank_nodes,
            assembly::partition_nodes(static_cast<int>(joined(before).points.cols()), joined(before).cells, ranks)
                .first_node);
}

TEST(RankNumbering, BodiesOfOneRankEachAreNotRenumbered) {
  std::vector<mesh::Mesh> meshes = {box(1.0, 0.2), box(1.0, 0.2)};
  const std::vector<mesh::Mesh> before = meshes;
  const RankNumbering n = number_for_ranks(meshes, {true, true}, 2, true);
  EXPECT_FALSE(n.by_parts);
  EXPECT_EQ(meshes[0].points, before[0].points);
  EXPECT_EQ(meshes[1].points, before[1].points);
  EXPECT_EQ(n.rank_nodes, (std::vector<int>{0, static_cast<int>(before[0].points.cols()),
                                            static_cast<int>(before[0].points.cols() + before[1].points.cols())}));
}

}  // namespace
}  // namespace conserve::simulation
