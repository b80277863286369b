#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <numeric>
#include <random>

#include "assembly/partition.hpp"
#include "support/grid_mesh.hpp"

namespace conserve::assembly {
namespace {

/// The ranges cover the nodes in order; each part visits, ascending, exactly
/// the cells with a corner in its range, and owns exactly those corners;
/// so every cell corner is owned by one part.
void check_partition(int num_nodes, const Eigen::MatrixXi& cells, const NodePartition& p, int parts) {
  ASSERT_EQ(p.num_parts(), parts);
  EXPECT_EQ(p.first_node.front(), 0);
  EXPECT_EQ(p.first_node.back(), num_nodes);
  EXPECT_TRUE(std::is_sorted(p.first_node.begin(), p.first_node.end()));
  ASSERT_EQ(static_cast<int>(p.visit_start.size()), parts + 1);
  ASSERT_EQ(p.visit_cell.size(), p.visit_owned.size());
  std::vector<int> owners(static_cast<std::size_t>(cells.size()), 0);  // per corner
  for (int k = 0; k < parts; ++k) {
    const auto in_range = [&](int node) { return p.first_node[k] <= node && node < p.first_node[k + 1]; };
    std::vector<int> expected;
    for (int c = 0; c < cells.cols(); ++c)
      for (int a = 0; a < cells.rows(); ++a)
        if (in_range(cells(a, c))) {
          expected.push_back(c);
          break;
        }
    const std::vector<int> visited(p.visit_cell.begin() + p.visit_start[k], p.visit_cell.begin() + p.visit_start[k + 1]);
    EXPECT_EQ(visited, expected) << "part " << k;
    for (int v = p.visit_start[k]; v < p.visit_start[k + 1]; ++v) {
      const int c = p.visit_cell[v];
      for (int a = 0; a < cells.rows(); ++a) {
        EXPECT_EQ((p.visit_owned[v] >> a & 1u) != 0, in_range(cells(a, c))) << "part " << k << " cell " << c;
        if (p.visit_owned[v] >> a & 1u) ++owners[static_cast<std::size_t>(c * cells.rows() + a)];
      }
    }
  }
  EXPECT_EQ(std::count(owners.begin(), owners.end(), 1), cells.size());
}

TEST(Partition, PartsOwnEveryCornerOnceAndVisitTheirCellsInOrder) {
  const mesh::Mesh box = test::box_mesh(12, 10, 9, 1.2, 1.0, 0.9);
  for (int parts : {1, 2, 3, 8}) check_partition(box.points.cols(), box.cells, partition_nodes(box.points.cols(), box.cells, parts), parts);
  const mesh::Mesh rect = test::rectangle_mesh(30, 20, 1.5, 1.0);
  for (int parts : {1, 2, 5}) check_partition(rect.points.cols(), rect.cells, partition_nodes(rect.points.cols(), rect.cells, parts), parts);
}

TEST(Partition, OnePartVisitsEveryCellOwningAllItsCorners) {
  const mesh::Mesh box = test::box_mesh(4, 3, 2, 1.0, 1.0, 1.0);
  const NodePartition p = partition_nodes(box.points.cols(), box.cells, 1);
  std::vector<int> all(box.cells.cols());
  std::iota(all.begin(), all.end(), 0);
  EXPECT_EQ(p.visit_cell, all);
  EXPECT_TRUE(std::all_of(p.visit_owned.begin(), p.visit_owned.end(), [](std::uint8_t o) { return o == 0xf; }));
}

/// Balanced by corners, and on a banded numbering the border cells (those
/// visited twice) are a thin layer; a shuffled numbering is still correct.
TEST(Partition, BalancedAndThinOnAnOrderedMesh) {
  const mesh::Mesh box = test::box_mesh(12, 10, 9, 1.2, 1.0, 0.9);
  const NodePartition p = partition_nodes(box.points.cols(), box.cells, 2);
  std::vector<long long> corners(2, 0);
  for (int k = 0; k < 2; ++k)
    for (int v = p.visit_start[k]; v < p.visit_start[k + 1]; ++v) corners[k] += std::popcount(p.visit_owned[v]);
  EXPECT_NEAR(static_cast<double>(corners[0]) / static_cast<double>(box.cells.size()), 0.5, 0.02);
  EXPECT_LT(p.num_visits(), 1.15 * static_cast<double>(box.cells.cols()));  // 9 layers of cells: one is duplicated

  mesh::Mesh shuffled = box;
  std::vector<int> order(box.points.cols());
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), std::mt19937(4));
  for (Eigen::Index i = 0; i < shuffled.cells.size(); ++i) shuffled.cells.data()[i] = order[shuffled.cells.data()[i]];
  check_partition(box.points.cols(), shuffled.cells, partition_nodes(box.points.cols(), shuffled.cells, 3), 3);
}

TEST(Partition, NoCellsAndBadArguments) {
  const NodePartition p = partition_nodes(5, Eigen::MatrixXi(4, 0), 2);
  EXPECT_EQ(p.num_parts(), 2);
  EXPECT_EQ(p.num_visits(), 0);
  EXPECT_EQ(p.first_node.back(), 5);
  EXPECT_THROW((void)partition_nodes(5, Eigen::MatrixXi(4, 0), 0), std::invalid_argument);
}

}  // namespace
}  // namespace conserve::assembly
