#pragma once
/// The sparsity pattern of node-block matrices (every node couples D dofs
/// with every node it shares a cell with), built once, with the positions
/// each cell writes to, so that assembly is a direct store into the values.
/// On a rank of a distributed run it holds the rows of the rank's nodes
/// only (all columns), from the cells with a corner among them: memory
/// falls with the number of ranks.
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "core/types.hpp"

namespace conserve::assembly {

template <int D>
class BlockPattern {
 public:
  /// `cells`: nodes × n_cells node numbers; `extra` couples further node
  /// pairs (both ways), e.g. for constraints. Only the rows of the nodes
  /// [first, end) are kept (end < 0: all nodes).
  BlockPattern(int num_nodes, const Eigen::MatrixXi& cells, const std::vector<std::pair<int, int>>& extra = {},
               int first = 0, int end = -1);

  /// A compressed matrix with this pattern and zero values.
  [[nodiscard]] SparseMatrix make_matrix() const;

  /// Index into the values of the entry (row dof A·D+i, column dof B·D+k),
  /// where A = cells(a, cell), B = cells(b, cell); A must be a kept row.
  [[nodiscard]] int position(int cell, int a, int b, int i, int k) const {
    const int local = local_cell_[static_cast<std::size_t>(cell)];
    const int B = cells_(b, local);
    return outer_[B * D + k] + rank_[(local * nodes_ + b) * nodes_ + a] * D + i;
  }

  /// Adds a cell's matrix Ke (row a·D+i, column b·D+k for local nodes a, b)
  /// into `values`, the values of a matrix with this pattern: the same
  /// entries as position(), with the block starts found once per cell.
  /// Only the block rows a whose bit is set in `rows` (all by default):
  /// those of the nodes a thread owns (assembly/partition.hpp), which must
  /// be kept rows. N: the cells' nodes.
  template <int N>
  void add_cell_matrix(int cell, const Eigen::Matrix<double, D * N, D * N>& Ke, double* values,
                       std::uint16_t rows = 0xffff) const {
    const int local = local_cell_[static_cast<std::size_t>(cell)];
    for (int b = 0; b < N; ++b) {
      const int B = cells_(b, local);
      const int* rank = &rank_[static_cast<std::size_t>(local * N + b) * N];
      const int column = outer_[static_cast<std::size_t>(B) * D];
      const int height = D * (offsets_[B + 1] - offsets_[B]);  // the columns of node B are equally long
      for (int k = 0; k < D; ++k) {
        const double* ke = Ke.data() + (b * D + k) * Ke.rows();
        double* out = values + column + k * height;
        for (int a = 0; a < N; ++a) {
          if (!(rows >> a & 1u)) continue;
          for (int i = 0; i < D; ++i) out[rank[a] * D + i] += ke[a * D + i];
        }
      }
    }
  }

  /// values += c (N ⊗ I_D) for a nodes × nodes matrix N whose entries the
  /// pattern holds (the mass matrix M_AB).
  void add_identity_blocks(double c, const SparseMatrix& N, double* values) const;

  /// Index of entry (row dof r, column dof c), or −1 if not in the pattern.
  [[nodiscard]] int find(int row, int col) const;

  [[nodiscard]] int num_dofs() const { return static_cast<int>(outer_.size()) - 1; }
  [[nodiscard]] std::size_t non_zeros() const { return static_cast<std::size_t>(outer_.back()); }
  /// Whether the cell has a corner among the kept rows.
  [[nodiscard]] bool kept_cell(int cell) const { return local_cell_[static_cast<std::size_t>(cell)] >= 0; }
  /// The cell's index among the kept cells (ascending with the cells), −1 if not kept.
  [[nodiscard]] int local_cell(int cell) const { return local_cell_[static_cast<std::size_t>(cell)]; }
  [[nodiscard]] int kept_cells() const { return static_cast<int>(cells_.cols()); }
  /// The kept cells, ascending.
  [[nodiscard]] std::vector<int> kept_cell_ids() const;
  /// From now on cells are numbered as the kept ones (the model kept only
  /// those: model::keep_cells with kept_cell_ids()).
  void renumber_to_kept();
  /// The kept rows' nodes [first_row(), end_row()).
  [[nodiscard]] int first_row() const { return first_; }
  [[nodiscard]] int end_row() const { return end_; }
  /// The couplings of the kept rows: node B's neighbours among them
  /// (ascending; B itself if kept) are node_neighbours()[node_offsets()[B]
  /// .. node_offsets()[B+1]).
  [[nodiscard]] const std::vector<int>& node_offsets() const { return offsets_; }
  [[nodiscard]] const std::vector<int>& node_neighbours() const { return neighbours_; }

 private:
  // The row indices are not kept: column B·D+k holds the D rows of each of
  // B's kept neighbours in turn, so make_matrix() and find() derive them.
  int first_ = 0, end_ = 0;
  int nodes_ = D + 1;            ///< per cell
  std::vector<int> local_cell_;  ///< per cell: its index among the kept cells, −1 if it has no kept corner
  Eigen::MatrixXi cells_;        ///< the kept cells
  std::vector<int> outer_;       ///< column starts (CSC)
  std::vector<int> offsets_;     ///< node B's kept neighbours are neighbours_[offsets_[B] .. offsets_[B+1])
  std::vector<int> neighbours_;  ///< sorted, each kept node among its own
  std::vector<int> rank_;        ///< per kept cell, per (b, a): rank of A among B's kept neighbours (−1: A not kept)
};

}  // namespace conserve::assembly
