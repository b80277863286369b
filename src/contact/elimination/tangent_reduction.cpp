#include "contact/elimination/tangent_reduction.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <iterator>

#include "core/error.hpp"

namespace conserve::contact {
namespace {

/// A node's reduced unknowns as seen from a row or column of K: through the
/// slave's row of the map, or the node itself.
struct Span {
  const int* nodes;
  int size;
};

template <int D>
Span expansion(const std::vector<BlockRow<D>>& map, int c, const int& node) {
  if (c < 0) return {&node, 1};
  return {map[c].nodes.data(), static_cast<int>(map[c].nodes.size())};
}

/// The row expansion of what reaches a column (TangentReduction::Reach):
/// a block's row node through W, or constraint c's V rows (source −1 − c).
template <int D, typename Block>
Span row_span(const SlaveRows<D>& rows, const std::vector<Block>& blocks,
              const std::vector<std::vector<int>>& table_rows, int source) {
  if (source < 0) {
    const std::vector<int>& r = table_rows[static_cast<std::size_t>(-1 - source)];
    return {r.data(), static_cast<int>(r.size())};
  }
  const Block& b = blocks[static_cast<std::size_t>(source)];
  return expansion(rows.test, rows.slave_of[b.row], b.row);
}

void sort_unique(std::vector<int>& v) {
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
}

/// Index of `node` in the ascending [begin, end) (which must hold it).
int index_of(const int* begin, const int* end, int node) {
  const int* it = std::lower_bound(begin, end, node);
  if (it == end || *it != node)
    throw Error(fmt::format("internal: node {} outside the reduced tangent's pattern", node));
  return static_cast<int>(it - begin);
}

}  // namespace

template <int D>
bool TangentReduction<D>::fits(const SparseMatrix& K) const {
  return K.rows() == K.cols() && K.cols() == static_cast<Eigen::Index>(nodes_) * D &&
         static_cast<Eigen::Index>(k_outer_.size()) == K.outerSize() + 1 &&
         static_cast<Eigen::Index>(k_inner_.size()) == K.nonZeros() &&
         std::equal(k_outer_.begin(), k_outer_.end(), K.outerIndexPtr()) &&
         (K.innerIndexPtr() == k_inner_data_ || std::equal(k_inner_.begin(), k_inner_.end(), K.innerIndexPtr()));
}

// The key: the number of nodes, then per constraint its slave, its trial
// row's nodes and its test row's nodes, each list after its length.
template <int D>
bool TangentReduction<D>::same_nodes(const SlaveRows<D>& rows) const {
  if (key_.empty() || key_[0] != static_cast<int>(rows.slave_of.size())) return false;
  std::size_t at = 1;
  auto match = [&](int value) { return at < key_.size() && key_[at++] == value; };
  for (std::size_t c = 0; c < rows.slaves.size(); ++c) {
    if (!match(rows.slaves[c])) return false;
    for (const BlockRow<D>* r : {&rows.trial[c], &rows.test[c]}) {
      if (!match(static_cast<int>(r->nodes.size()))) return false;
      for (const int node : r->nodes)
        if (!match(node)) return false;
    }
  }
  return at == key_.size();
}

/// K's pattern and its node pattern.
template <int D>
void TangentReduction<D>::set_k(const SparseMatrix& K) {
  nodes_ = static_cast<int>(K.cols() / D);
  k_outer_.assign(K.outerIndexPtr(), K.outerIndexPtr() + K.outerSize() + 1);
  k_inner_.assign(K.innerIndexPtr(), K.innerIndexPtr() + K.nonZeros());
  k_offsets_.assign(1, 0);
  k_nodes_.clear();
  k_complete_.assign(nodes_, 1);
  std::vector<int> column;
  for (int N = 0; N < nodes_; ++N) {
    const auto first = static_cast<std::ptrdiff_t>(k_nodes_.size());
    for (int k = 0; k < D; ++k) {
      const int c = N * D + k;
      column.clear();
      for (int p = k_outer_[c]; p < k_outer_[c + 1]; ++p)
        if (column.empty() || column.back() != k_inner_[p] / D) column.push_back(k_inner_[p] / D);
      if (k == 0) {
        k_nodes_.insert(k_nodes_.end(), column.begin(), column.end());
      } else if (!std::equal(column.begin(), column.end(), k_nodes_.begin() + first, k_nodes_.end())) {
        k_complete_[N] = 0;
        column.insert(column.end(), k_nodes_.begin() + first, k_nodes_.end());
        sort_unique(column);
        k_nodes_.resize(first);
        k_nodes_.insert(k_nodes_.end(), column.begin(), column.end());
      }
    }
    const auto count = static_cast<int>(k_nodes_.size() - first);
    for (int k = 0; k < D; ++k)
      if (k_outer_[N * D + k + 1] - k_outer_[N * D + k] != count * D) k_complete_[N] = 0;
    k_offsets_.push_back(static_cast<int>(k_nodes_.size()));
  }
  key_.clear();
}

template <int D>
void TangentReduction<D>::build(const SlaveRows<D>& rows) {
  key_.assign(1, static_cast<int>(rows.slave_of.size()));
  for (std::size_t c = 0; c < rows.slaves.size(); ++c) {
    key_.push_back(rows.slaves[c]);
    for (const BlockRow<D>* r : {&rows.trial[c], &rows.test[c]}) {
      key_.push_back(static_cast<int>(r->nodes.size()));
      key_.insert(key_.end(), r->nodes.begin(), r->nodes.end());
    }
  }
  std::vector<int> block_of;   // per entry of k_nodes_: its slave block, or −1
  std::vector<char> involved;  // per node column: holds slave blocks, or gains rows
  make_slave_blocks(rows, block_of, involved);
  make_pattern(involved, block_of);
  make_targets(rows);
  buffer_.assign(blocks_.size() * D * D, 0.0);
  kr_inner_data_ = nullptr;
  ++builds_;
}

/// K's blocks in a slave row or column, and K_r's node pattern: K's plus
/// the blocks their products reach and each slave's V and β blocks. What
/// reaches a column node J (reach_: a block of K whose column expansion
/// holds J, or a constraint's V table) brings its row expansion; each
/// column's new rows are the union of those, found with stamps (a dense
/// cycle's rows are long, and every block of the cycle brings nearly the
/// same ones).
template <int D>
void TangentReduction<D>::make_slave_blocks(const SlaveRows<D>& rows, std::vector<int>& block_of,
                                            std::vector<char>& involved) {
  blocks_.clear();
  block_of.assign(k_nodes_.size(), -1);
  involved.assign(nodes_, 0);
  for (int N = 0; N < nodes_; ++N)
    for (int q = k_offsets_[N]; q < k_offsets_[N + 1]; ++q) {
      const int M = k_nodes_[q], cm = rows.slave_of[M], cn = rows.slave_of[N];
      if (cm < 0 && cn < 0) continue;
      involved[N] = 1;
      block_of[q] = static_cast<int>(blocks_.size());
      blocks_.push_back({M, N});
    }
  const auto slaves = static_cast<int>(rows.slaves.size());
  slave_rows_.assign(slaves, {});
  slave_cols_.assign(slaves, {});
  for (int c = 0; c < slaves; ++c) {
    if (!owns(rows.slaves[c])) continue;  // V and β are the slave's rank's
    slave_rows_[c] = rows.test[c].nodes;
    slave_cols_[c] = rows.trial[c].nodes;
    slave_rows_[c].push_back(rows.slaves[c]);
    slave_cols_[c].push_back(rows.slaves[c]);
    sort_unique(slave_rows_[c]);
    sort_unique(slave_cols_[c]);
  }
  // reach_, grouped by column node.
  reach_offsets_.assign(static_cast<std::size_t>(nodes_) + 1, 0);
  for (const Block& b : blocks_) {
    const Span ns = expansion(rows.trial, rows.slave_of[b.col], b.col);
    for (int j = 0; j < ns.size; ++j) ++reach_offsets_[ns.nodes[j] + 1];
  }
  for (int c = 0; c < slaves; ++c)
    for (const int N : slave_cols_[c]) ++reach_offsets_[N + 1];
  for (int N = 0; N < nodes_; ++N) reach_offsets_[N + 1] += reach_offsets_[N];
  reach_.resize(reach_offsets_.back());
  std::vector<int> cursor(reach_offsets_.begin(), reach_offsets_.end() - 1);
  for (std::size_t b = 0; b < blocks_.size(); ++b) {
    const Span ns = expansion(rows.trial, rows.slave_of[blocks_[b].col], blocks_[b].col);
    for (int j = 0; j < ns.size; ++j) reach_[cursor[ns.nodes[j]]++] = {static_cast<int>(b), j};
  }
  for (int c = 0; c < slaves; ++c)
    for (std::size_t j = 0; j < slave_cols_[c].size(); ++j)
      reach_[cursor[slave_cols_[c][j]]++] = {-1 - c, static_cast<int>(j)};
  // Each column's rows: K's and the reaches' row expansions. A row span is
  // a constraint's test row (id c), a lone node (slaves + M) or a V table's
  // rows (slaves + nodes + c).
  std::vector<int> span_stamp(2 * static_cast<std::size_t>(slaves) + nodes_, -1), node_stamp(nodes_, -1);
  auto span_id = [&](int source) {
    if (source < 0) return slaves + nodes_ + (-1 - source);
    const int M = blocks_[source].row;
    return rows.slave_of[M] >= 0 ? rows.slave_of[M] : slaves + M;
  };
  std::vector<int> added;
  r_offsets_.assign(1, 0);
  r_nodes_.clear();
  r_nodes_.reserve(k_nodes_.size());
  for (int N = 0; N < nodes_; ++N) {
    added.clear();
    for (int r = reach_offsets_[N]; r < reach_offsets_[N + 1]; ++r) {
      const Span span = row_span(rows, blocks_, slave_rows_, reach_[r].source);
      const int id = span_id(reach_[r].source);
      if (span_stamp[id] == N) continue;
      span_stamp[id] = N;
      for (int i = 0; i < span.size; ++i)
        if (node_stamp[span.nodes[i]] != N) {
          node_stamp[span.nodes[i]] = N;
          added.push_back(span.nodes[i]);
        }
    }
    std::sort(added.begin(), added.end());
    std::set_union(k_nodes_.begin() + k_offsets_[N], k_nodes_.begin() + k_offsets_[N + 1], added.begin(), added.end(),
                   std::back_inserter(r_nodes_));
    r_offsets_.push_back(static_cast<int>(r_nodes_.size()));
    if (r_offsets_[N + 1] - r_offsets_[N] != k_offsets_[N + 1] - k_offsets_[N] || !k_complete_[N]) involved[N] = 1;
  }
}

template <int D>
void TangentReduction<D>::add_run(int src, int dst, int len) {
  if (!runs_.empty() && runs_.back().src + runs_.back().len == src && runs_.back().dst + runs_.back().len == dst)
    runs_.back().len += len;
  else
    runs_.push_back({src, dst, len});
}

/// K_r's compressed pattern (every node block dense, rows ascending), the
/// runs copying K's free values (a column untouched by the slaves is one
/// run), the positions left to zero, and the gathering of K's slave blocks.
template <int D>
void TangentReduction<D>::make_pattern(const std::vector<char>& involved, const std::vector<int>& block_of) {
  outer_.assign(1, 0);
  inner_.clear();
  inner_.reserve(r_nodes_.size() * D * D);
  for (int N = 0; N < nodes_; ++N)
    for (int k = 0; k < D; ++k) {
      for (int q = r_offsets_[N]; q < r_offsets_[N + 1]; ++q)
        for (int i = 0; i < D; ++i) inner_.push_back(r_nodes_[q] * D + i);
      outer_.push_back(static_cast<int>(inner_.size()));
    }
  runs_.clear();
  zeros_.clear();
  gather_.clear();
  std::vector<char> covered;
  for (int N = 0; N < nodes_; ++N)
    for (int k = 0; k < D; ++k) {
      const int c = N * D + k;
      if (!involved[N]) {  // K's column as it is
        add_run(k_outer_[c], outer_[c], k_outer_[c + 1] - k_outer_[c]);
        continue;
      }
      covered.assign(outer_[c + 1] - outer_[c], 0);
      int q = k_offsets_[N], qr = r_offsets_[N];
      for (int p = k_outer_[c]; p < k_outer_[c + 1]; ++p) {
        const int M = k_inner_[p] / D, i = k_inner_[p] % D;
        while (k_nodes_[q] < M) ++q;
        if (block_of[q] >= 0) {
          gather_.emplace_back(p, (block_of[q] * D + k) * D + i);
          continue;
        }
        while (r_nodes_[qr] < M) ++qr;
        const int at = (qr - r_offsets_[N]) * D + i;
        covered[at] = 1;
        add_run(p, outer_[c] + at, 1);
      }
      for (std::size_t at = 0; at < covered.size(); ++at)
        if (!covered[at]) zeros_.push_back(outer_[c] + static_cast<int>(at));
    }
}

/// The K_r position of every product's block in the order reduce() adds
/// them (block b's from target_offsets_[b], row i of its row expansion and
/// column j of its column expansion at i · (columns) + j), and each slave's
/// table for V and β: per column node, its rows' slots looked up once.
template <int D>
void TangentReduction<D>::make_targets(const SlaveRows<D>& rows) {
  target_offsets_.assign(blocks_.size() + 1, 0);
  for (std::size_t b = 0; b < blocks_.size(); ++b) {
    const Span ms = expansion(rows.test, rows.slave_of[blocks_[b].row], blocks_[b].row);
    const Span ns = expansion(rows.trial, rows.slave_of[blocks_[b].col], blocks_[b].col);
    target_offsets_[b + 1] = target_offsets_[b] + ms.size * ns.size;
  }
  targets_.assign(static_cast<std::size_t>(target_offsets_.back()), 0);
  slave_table_.assign(rows.slaves.size(), {});
  for (std::size_t c = 0; c < rows.slaves.size(); ++c)
    slave_table_[c].assign(slave_rows_[c].size() * slave_cols_[c].size(), 0);
  std::vector<int> slot(nodes_, -1);
  for (int N = 0; N < nodes_; ++N) {
    for (int q = r_offsets_[N]; q < r_offsets_[N + 1]; ++q) slot[r_nodes_[q]] = q - r_offsets_[N];
    const int base = outer_[N * D];
    for (int r = reach_offsets_[N]; r < reach_offsets_[N + 1]; ++r) {
      const Reach& reach = reach_[r];
      const Span ms = row_span(rows, blocks_, slave_rows_, reach.source);
      if (reach.source >= 0) {
        const Block& b = blocks_[reach.source];
        const int columns = expansion(rows.trial, rows.slave_of[b.col], b.col).size;
        int* out = targets_.data() + target_offsets_[reach.source] + reach.j;
        for (int i = 0; i < ms.size; ++i) out[i * columns] = base + slot[ms.nodes[i]] * D;
      } else {
        const auto c = static_cast<std::size_t>(-1 - reach.source);
        const std::size_t columns = slave_cols_[c].size();
        for (int i = 0; i < ms.size; ++i)
          slave_table_[c][i * columns + reach.j] = base + slot[ms.nodes[i]] * D;
      }
    }
    for (int q = r_offsets_[N]; q < r_offsets_[N + 1]; ++q) slot[r_nodes_[q]] = -1;
  }
}

template <int D>
bool TangentReduction<D>::adopt_pattern(SparseMatrix& K_r) {
  const Eigen::Index n = static_cast<Eigen::Index>(nodes_) * D;
  const bool ours = K_r.rows() == n && K_r.cols() == n && K_r.isCompressed() &&
                    K_r.nonZeros() == static_cast<Eigen::Index>(inner_.size()) &&
                    K_r.innerIndexPtr() == kr_inner_data_ &&
                    std::equal(outer_.begin(), outer_.end(), K_r.outerIndexPtr());
  if (ours) return false;
  K_r.resize(n, n);
  K_r.resizeNonZeros(static_cast<Eigen::Index>(inner_.size()));
  std::copy(outer_.begin(), outer_.end(), K_r.outerIndexPtr());
  std::copy(inner_.begin(), inner_.end(), K_r.innerIndexPtr());
  kr_inner_data_ = K_r.innerIndexPtr();
  return true;
}

template <int D>
void TangentReduction<D>::add_at(int p0, int N, const Mat<D>& X, double* values) const {
  const int c = N * D;
  const int column = outer_[c + 1] - outer_[c];  // node blocks: the D columns of N are alike
  Eigen::Map<Mat<D>, Eigen::Unaligned, Eigen::OuterStride<>>(values + p0, Eigen::OuterStride<>(column)) += X;
}

template <int D>
bool TangentReduction<D>::reduce(const SparseMatrix& K, const SlaveRows<D>& rows, SparseMatrix& K_r) {
  if (!K.isCompressed()) {
    SparseMatrix compressed = K;
    compressed.makeCompressed();
    return reduce(compressed, rows, K_r);
  }
  if (K.rows() != K.cols() || K.cols() != static_cast<Eigen::Index>(rows.slave_of.size()) * D)
    throw Error(fmt::format("reduced tangent: K is {} × {}, expected {} × {} (the model's dofs)", K.rows(), K.cols(),
                            rows.slave_of.size() * D, rows.slave_of.size() * D));
  if (!fits(K)) set_k(K);
  k_inner_data_ = K.innerIndexPtr();
  if (!same_nodes(rows)) build(rows);
  const bool adopted = adopt_pattern(K_r);
  double* v = K_r.valuePtr();
  const double* k = K.valuePtr();
  for (const int p : zeros_) v[p] = 0.0;
  for (const Run& r : runs_) std::copy_n(k + r.src, r.len, v + r.dst);
  for (const auto& [p, i] : gather_) buffer_[i] = k[p];
  // (43), (58): each of K's slave blocks through W (rows) and T (columns).
  const int* target = targets_.data();
  for (std::size_t b = 0; b < blocks_.size(); ++b) {
    const Eigen::Map<const Mat<D>> B(buffer_.data() + b * D * D);
    const int cm = rows.slave_of[blocks_[b].row], cn = rows.slave_of[blocks_[b].col];
    if (cn < 0) {
      const BlockRow<D>& w = rows.test[cm];
      for (std::size_t i = 0; i < w.nodes.size(); ++i)
        add_at(*target++, blocks_[b].col, w.blocks[i].transpose() * B, v);
    } else if (cm < 0) {
      const BlockRow<D>& t = rows.trial[cn];
      for (std::size_t j = 0; j < t.nodes.size(); ++j) add_at(*target++, t.nodes[j], B * t.blocks[j], v);
    } else {
      const BlockRow<D>& w = rows.test[cm];
      const BlockRow<D>& t = rows.trial[cn];
      for (std::size_t i = 0; i < w.nodes.size(); ++i) {
        const Mat<D> WB = w.blocks[i].transpose() * B;
        for (std::size_t j = 0; j < t.nodes.size(); ++j) add_at(*target++, t.nodes[j], WB * t.blocks[j], v);
      }
    }
  }
  return adopted;
}

template <int D>
void TangentReduction<D>::add(int c, int M, int N, const Mat<D>& X, SparseMatrix& K_r) const {
  add_slot(c, row_slot(c, M), column_slot(c, N), X, K_r);
}

template <int D>
int TangentReduction<D>::row_slot(int c, int M) const {
  const std::vector<int>& rows = slave_rows_[c];
  return index_of(rows.data(), rows.data() + rows.size(), M);
}

template <int D>
int TangentReduction<D>::column_slot(int c, int N) const {
  const std::vector<int>& cols = slave_cols_[c];
  return index_of(cols.data(), cols.data() + cols.size(), N);
}

template <int D>
void TangentReduction<D>::add_slot(int c, int i, int j, const Mat<D>& X, SparseMatrix& K_r) const {
  const std::vector<int>& cols = slave_cols_[c];
  add_at(slave_table_[c][i * cols.size() + j], cols[j], X, K_r.valuePtr());
}

template class TangentReduction<2>;
template class TangentReduction<3>;

}  // namespace conserve::contact
