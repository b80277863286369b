#pragma once
/// The sparsity pattern of node-block matrices (every node couples D dofs
/// with every node it shares a cell with), built once, with the positions
/// each cell writes to, so that assembly is a direct store into the values.
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
  /// `cells`: (D+1) × n_cells node numbers; `extra` couples further node
  /// pairs (both ways), e.g. for constraints.
  BlockPattern(int num_nodes, const Eigen::MatrixXi& cells, const std::vector<std::pair<int, int>>& extra = {});

  /// A compressed matrix with this pattern and zero values.
  [[nodiscard]] SparseMatrix make_matrix() const;

  /// Index into the values of the entry (row dof A·D+i, column dof B·D+k),
  /// where A = cells(a, cell), B = cells(b, cell).
  [[nodiscard]] int position(int cell, int a, int b, int i, int k) const {
    const int B = cells_(b, cell);
    return outer_[B * D + k] + rank_[(cell * (D + 1) + b) * (D + 1) + a] * D + i;
  }

  /// Adds a cell's matrix Ke (row a·D+i, column b·D+k for local nodes a, b)
  /// into `values`, the values of a matrix with this pattern: the same
  /// entries as position(), with the block starts found once per cell.
  /// Only the block columns b whose bit is set in `columns` (all by
  /// default): those of the nodes a thread owns (assembly/partition.hpp).
  void add_cell_matrix(int cell, const Eigen::Matrix<double, D*(D + 1), D*(D + 1)>& Ke, double* values,
                       std::uint8_t columns = 0xff) const {
    for (int b = 0; b <= D; ++b) {
      if (!(columns >> b & 1u)) continue;
      const int B = cells_(b, cell);
      const int* rank = &rank_[static_cast<std::size_t>(cell * (D + 1) + b) * (D + 1)];
      const int column = outer_[static_cast<std::size_t>(B) * D];
      const int height = D * (offsets_[B + 1] - offsets_[B]);  // the columns of node B are equally long
      double* block[D + 1];
      for (int a = 0; a <= D; ++a) block[a] = values + (column + rank[a] * D);
      for (int k = 0; k < D; ++k) {
        const double* ke = Ke.data() + (b * D + k) * Ke.rows();
        for (int a = 0; a <= D; ++a)
          for (int i = 0; i < D; ++i) block[a][k * height + i] += ke[a * D + i];
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
  /// The node graph: node B's neighbours (itself among them, ascending)
  /// are node_neighbours()[node_offsets()[B] .. node_offsets()[B+1]).
  [[nodiscard]] const std::vector<int>& node_offsets() const { return offsets_; }
  [[nodiscard]] const std::vector<int>& node_neighbours() const { return neighbours_; }

 private:
  // The row indices are not kept: column B·D+k holds the D rows of each of
  // B's neighbours in turn, so make_matrix() and find() derive them.
  Eigen::MatrixXi cells_;
  std::vector<int> outer_;       ///< column starts (CSC)
  std::vector<int> offsets_;     ///< node B's neighbours are neighbours_[offsets_[B] .. offsets_[B+1])
  std::vector<int> neighbours_;  ///< sorted, each node among its own
  std::vector<int> rank_;        ///< per cell, per (b, a): rank of A among B's neighbours
};

}  // namespace conserve::assembly
