#pragma once
/// The order in which cells are assembled, fixed once per model so that
/// every global entry receives its cells' contributions in the same order
/// whatever the number of threads. The cells are cut into chunks of
/// consecutive cells (which keeps the cache reuse of neighbouring cells
/// that a serial loop has), and the chunks coloured so that no two chunks
/// of one colour share a node. The order is colour by colour, chunk by
/// chunk, cell by cell; a chunk may run concurrently with any chunk it
/// shares no node with, so it only waits for the chunks of earlier colours
/// that share a node with it.
#include <Eigen/Core>
#include <algorithm>
#include <vector>

namespace conserve::assembly {

struct CellColouring {
  int chunk_size = 1;  ///< chunk q holds cells [q·chunk_size, (q+1)·chunk_size) ∩ cells
  int num_cells = 0;
  std::vector<int> start;   ///< colour k holds chunks[start[k] .. start[k+1])
  std::vector<int> chunks;  ///< every chunk once, by colour, ascending within a colour
  /// chunks[j] waits for chunks[waits_for[i]], i in [wait_start[j], wait_start[j+1]):
  /// the chunks of earlier colours that share a node with it (all before j).
  std::vector<int> wait_start;
  std::vector<int> waits_for;

  [[nodiscard]] int num_colours() const { return static_cast<int>(start.size()) - 1; }
  [[nodiscard]] int first_cell(int chunk) const { return chunk * chunk_size; }
  [[nodiscard]] int end_cell(int chunk) const { return std::min(num_cells, (chunk + 1) * chunk_size); }
};

/// Greedy colouring in chunk order: each chunk takes the lowest colour that
/// no earlier chunk sharing a node with it has. `cells`: (D+1) × n_cells
/// node numbers below `num_nodes`; `chunk_size` ≥ 1.
CellColouring colour_cells(int num_nodes, const Eigen::MatrixXi& cells, int chunk_size);

/// The colouring with the largest chunks (512 cells, halved until the
/// colours hold 16 chunks on average, or single cells): large chunks keep
/// the cache reuse, many chunks per colour leave work for several threads.
CellColouring colour_cells(int num_nodes, const Eigen::MatrixXi& cells);

}  // namespace conserve::assembly
