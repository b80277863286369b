#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <set>

#include "assembly/colouring.hpp"
#include "support/grid_mesh.hpp"

namespace conserve::assembly {
namespace {

/// Every cell once; chunks ascending within a colour; no node shared by two
/// chunks of one colour; the waits are the earlier chunks sharing a node.
void check_colouring(int num_nodes, const Eigen::MatrixXi& cells, const CellColouring& colouring) {
  std::vector<int> seen(cells.cols(), 0);
  for (int k = 0; k < colouring.num_colours(); ++k) {
    std::vector<int> owner(num_nodes, -1);  // chunk of this colour holding the node
    for (int j = colouring.start[k]; j < colouring.start[k + 1]; ++j) {
      const int chunk = colouring.chunks[j];
      if (j > colouring.start[k]) EXPECT_LT(colouring.chunks[j - 1], chunk);
      for (int c = colouring.first_cell(chunk); c < colouring.end_cell(chunk); ++c) {
        ++seen[c];
        for (int a = 0; a < cells.rows(); ++a) {
          int& o = owner[cells(a, c)];
          EXPECT_TRUE(o == -1 || o == chunk)
              << "colour " << k << ": node " << cells(a, c) << " in chunks " << o << " and " << chunk;
          o = chunk;
        }
      }
    }
  }
  EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), cells.cols());
  // Each chunk waits for exactly the earlier chunks that share a node with it.
  const int num_chunks = static_cast<int>(colouring.chunks.size());
  ASSERT_EQ(static_cast<int>(colouring.wait_start.size()), num_chunks + 1);
  std::vector<std::set<int>> at_node(num_nodes);  // indices j into colouring.chunks
  for (int j = 0; j < num_chunks; ++j)
    for (int c = colouring.first_cell(colouring.chunks[j]); c < colouring.end_cell(colouring.chunks[j]); ++c)
      for (int a = 0; a < cells.rows(); ++a) at_node[cells(a, c)].insert(j);
  std::vector<std::set<int>> expected(num_chunks);
  for (const auto& js : at_node)
    for (int j : js)
      for (int i : js)
        if (i < j) expected[j].insert(i);
  for (int j = 0; j < num_chunks; ++j) {
    const std::set<int> waits(colouring.waits_for.begin() + colouring.wait_start[j],
                              colouring.waits_for.begin() + colouring.wait_start[j + 1]);
    EXPECT_EQ(waits, expected[j]) << "chunk index " << j;
    EXPECT_EQ(waits.size(), static_cast<std::size_t>(colouring.wait_start[j + 1] - colouring.wait_start[j]));
  }
}

TEST(Colouring, ChunksOfAColourShareNoNode) {
  const mesh::Mesh box = test::box_mesh(12, 10, 9, 1.2, 1.0, 0.9);
  for (int chunk : {1, 7, 64, 100000})
    check_colouring(box.points.cols(), box.cells, colour_cells(box.points.cols(), box.cells, chunk));
  const mesh::Mesh rect = test::rectangle_mesh(30, 20, 1.5, 1.0);
  check_colouring(rect.points.cols(), rect.cells, colour_cells(rect.points.cols(), rect.cells));
}

TEST(Colouring, OrderedMeshGetsLargeChunksAndBalancedColours) {
  const mesh::Mesh box = test::box_mesh(12, 10, 9, 1.2, 1.0, 0.9);
  const CellColouring colouring = colour_cells(box.points.cols(), box.cells);
  check_colouring(box.points.cols(), box.cells, colouring);
  EXPECT_GT(colouring.chunk_size, 1);
  EXPECT_GE(colouring.chunks.size(), std::size_t{16} * colouring.num_colours());
}

TEST(Colouring, ShuffledMeshFallsBackToSmallChunks) {
  mesh::Mesh box = test::box_mesh(12, 10, 9, 1.2, 1.0, 0.9);
  std::vector<int> order(box.cells.cols());
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), std::mt19937(4));
  const Eigen::MatrixXi shuffled = box.cells(Eigen::all, order);
  const CellColouring colouring = colour_cells(box.points.cols(), shuffled);
  check_colouring(box.points.cols(), shuffled, colouring);
  EXPECT_TRUE(colouring.chunk_size == 1 || colouring.chunks.size() >= std::size_t{16} * colouring.num_colours());
}

TEST(Colouring, NoCells) {
  const CellColouring colouring = colour_cells(3, Eigen::MatrixXi(4, 0));
  EXPECT_EQ(colouring.num_colours(), 0);
  EXPECT_TRUE(colouring.chunks.empty());
}

}  // namespace
}  // namespace conserve::assembly
