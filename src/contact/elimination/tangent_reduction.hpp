#pragma once
/// The product Wᵀ K T of the direct elimination's reduced tangent (43)/(58),
/// computed only where it differs from K. T and W are the identity except
/// on the slave nodes' rows, so
///   K_r = K on the rows and columns of the free nodes
///       + the slave rows of K mapped through W, its slave columns through T,
/// in D × D node blocks: K_r(M, N) += W_sMᵀ K(s, N), K(M, s) T_sN and
/// W_sMᵀ K(s, s′) T_s′N. The pattern of K_r (K's, closed to node blocks,
/// with the blocks these products reach and each slave's own block of V
/// and β) and the positions every product is added at are built once per
/// pattern of K and set of constraint nodes; a call then copies K's free
/// values in contiguous runs and adds the slave blocks: O(nnz) work, no
/// allocation, and the same pattern (explicit zeros kept) while the
/// constraints' nodes do not change, so a solver's symbolic analysis of
/// K_r is reused. On a rank of a distributed run K holds the rank's rows
/// (assembly/block_pattern.hpp): each product is then formed by the rank
/// that holds its row of K, and V and β by the rank that owns the slave,
/// so every term is added once, some into other ranks' rows, which the
/// linear system sums (solver/petsc_system.hpp).
#include <limits>
#include <vector>

#include "core/types.hpp"

namespace conserve::contact {

/// A slave node's D rows of a map in node blocks: the slave's dofs are
/// Σ_b blocks[b] times the reduced unknowns of node nodes[b] (T), or its
/// residual passes blocksᵀ g_s on to those unknowns (W). Structural: a
/// node stays listed when its block happens to be zero.
template <int D>
struct BlockRow {
  std::vector<int> nodes;      ///< ascending
  std::vector<Mat<D>> blocks;  ///< D × D: rows the slave's dofs, columns the node's unknowns
};

/// The slaves' rows of T and W, per eliminated slave node (the
/// elimination's view; a slave may hold one or two constraints).
template <int D>
struct SlaveRows {
  const std::vector<int>& slave_of;  ///< per node: its slave index, or −1
  const std::vector<int>& slaves;    ///< per slave index: its node
  const std::vector<BlockRow<D>>& trial;
  const std::vector<BlockRow<D>>& test;
};

template <int D>
class TangentReduction {
 public:
  /// K_r = Wᵀ K T (43)/(58), ndof × ndof; K square with ascending rows in
  /// each column, ndof a multiple of D. K_r keeps its storage when it holds
  /// this reduction's pattern, else it is given it: returns whether it was
  /// (then a layout computed for the old K_r is void). K and K_r must be
  /// distinct.
  bool reduce(const SparseMatrix& K, const SlaveRows<D>& rows, SparseMatrix& K_r);
  /// K_r(M, N) += X (D × D node block) where M is slave c's node or one of
  /// its test row's nodes and N its node or one of its trial row's nodes
  /// (the blocks of V and β); K_r from the last reduce(). Slave c must be
  /// this rank's (owns()).
  void add(int c, int M, int N, const Mat<D>& X, SparseMatrix& K_r) const;
  /// The same by slots: row_slot(c, M) and column_slot(c, N), looked up
  /// once for a row or column of V's blocks.
  void add_slot(int c, int i, int j, const Mat<D>& X, SparseMatrix& K_r) const;
  [[nodiscard]] int row_slot(int c, int M) const;
  [[nodiscard]] int column_slot(int c, int N) const;
  /// Pattern builds so far (for tests: reuse while the nodes are unchanged).
  [[nodiscard]] int builds() const { return builds_; }
  /// This rank's nodes [first, end) (model::Model::rank_nodes): the
  /// constraints whose slave it owns get V's and β's blocks here (all by
  /// default). Set before the first reduce().
  void set_owned(int first, int end) { owned_first_ = first, owned_end_ = end; }
  [[nodiscard]] bool owns(int node) const { return node >= owned_first_ && node < owned_end_; }

 private:
  struct Run {
    int src, dst, len;  ///< K's values [src, src+len) → K_r's [dst, dst+len)
  };
  struct Block {
    int row, col;  ///< nodes of a block of K with a slave row or column
  };
  /// What reaches a column node: a block of K (source ≥ 0, its index) or
  /// constraint c's V table (source −1 − c), at index j of its column
  /// expansion.
  struct Reach {
    int source, j;
  };

  [[nodiscard]] bool fits(const SparseMatrix& K) const;
  [[nodiscard]] bool same_nodes(const SlaveRows<D>& rows) const;
  void set_k(const SparseMatrix& K);
  void build(const SlaveRows<D>& rows);
  void make_slave_blocks(const SlaveRows<D>& rows, std::vector<int>& block_of, std::vector<char>& involved);
  void make_pattern(const std::vector<char>& involved, const std::vector<int>& block_of);
  void make_targets(const SlaveRows<D>& rows);
  void add_run(int src, int dst, int len);
  bool adopt_pattern(SparseMatrix& K_r);
  void add_at(int p0, int N, const Mat<D>& X, double* values) const;

  int nodes_ = 0;
  // K: its pattern, and per node column N the row nodes
  // k_nodes_[k_offsets_[N], k_offsets_[N+1]) and whether its D columns
  // hold these node blocks whole.
  std::vector<int> k_outer_, k_inner_;
  const int* k_inner_data_ = nullptr;  ///< K's index storage last seen with that pattern
  std::vector<int> k_offsets_, k_nodes_;
  std::vector<char> k_complete_;
  // The constraints' nodes the rest was built for (empty: none yet).
  std::vector<int> key_;
  // K_r: its node pattern (as K's), its pattern, and the storage last given it.
  std::vector<int> r_offsets_, r_nodes_, outer_, inner_;
  const int* kr_inner_data_ = nullptr;
  std::vector<Run> runs_;                    ///< K's free values into K_r
  std::vector<int> zeros_;                   ///< K_r's positions no run writes
  std::vector<std::pair<int, int>> gather_;  ///< (K position, index into buffer_)
  std::vector<Block> blocks_;                ///< buffer_ holds their values, D × D column-major each
  std::vector<int> targets_;                 ///< K_r position of each product's block, in reduce()'s order
  std::vector<int> target_offsets_;          ///< per block of blocks_: its first entry of targets_
  std::vector<int> reach_offsets_;           ///< per column node: its reaches in reach_
  std::vector<Reach> reach_;
  std::vector<std::vector<int>> slave_rows_, slave_cols_, slave_table_;  ///< per constraint: V's and β's blocks
  std::vector<double> buffer_;
  int builds_ = 0;
  int owned_first_ = 0, owned_end_ = std::numeric_limits<int>::max();
};

}  // namespace conserve::contact
