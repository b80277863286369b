#include "assembly/block_pattern.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <limits>

#include "core/error.hpp"

namespace conserve::assembly {

template <int D>
BlockPattern<D>::BlockPattern(int num_nodes, const Eigen::MatrixXi& cells,
                              const std::vector<std::pair<int, int>>& extra, int first, int end)
    : first_(first), end_(end < 0 ? num_nodes : end), nodes_(static_cast<int>(cells.rows())) {
  const int N = nodes_;
  const auto kept = [&](int node) { return node >= first_ && node < end_; };
  // The kept cells: those with a corner among the kept rows.
  local_cell_.assign(static_cast<std::size_t>(cells.cols()), -1);
  int locals = 0;
  for (Eigen::Index c = 0; c < cells.cols(); ++c)
    for (int a = 0; a < N; ++a)
      if (kept(cells(a, c))) {
        local_cell_[static_cast<std::size_t>(c)] = locals++;
        break;
      }
  cells_.resize(N, locals);
  for (Eigen::Index c = 0; c < cells.cols(); ++c)
    if (const int l = local_cell_[static_cast<std::size_t>(c)]; l >= 0) cells_.col(l) = cells.col(c);
  // Each column node's kept neighbours with repeats (its cells' kept nodes,
  // the extra pairs' and itself if kept: every kept node keeps its
  // diagonal block, even if isolated), bucketed by counting, then sorted
  // and made unique in place.
  const auto nodes = static_cast<std::size_t>(num_nodes);
  std::vector<std::size_t> start(nodes + 1, 0);
  for (Eigen::Index c = 0; c < cells_.cols(); ++c) {
    int in = 0;
    for (int a = 0; a < N; ++a) in += kept(cells_(a, c)) ? 1 : 0;
    for (int b = 0; b < N; ++b) start[static_cast<std::size_t>(cells_(b, c)) + 1] += static_cast<std::size_t>(in);
  }
  for (const auto& [p, q] : extra) {
    if (kept(q)) ++start[static_cast<std::size_t>(p) + 1];
    if (kept(p)) ++start[static_cast<std::size_t>(q) + 1];
  }
  for (std::size_t n = 0; n < nodes; ++n) start[n + 1] += start[n] + (kept(static_cast<int>(n)) ? 1 : 0);
  std::vector<int> all(start[nodes]);
  std::vector<std::size_t> next(start.begin(), start.end() - 1);
  for (std::size_t n = 0; n < nodes; ++n)
    if (kept(static_cast<int>(n))) all[next[n]++] = static_cast<int>(n);
  for (Eigen::Index c = 0; c < cells_.cols(); ++c)
    for (int b = 0; b < N; ++b) {
      const auto B = static_cast<std::size_t>(cells_(b, c));
      for (int a = 0; a < N; ++a)
        if (kept(cells_(a, c))) all[next[B]++] = cells_(a, c);
    }
  for (const auto& [p, q] : extra) {
    if (kept(q)) all[next[static_cast<std::size_t>(p)]++] = q;
    if (kept(p)) all[next[static_cast<std::size_t>(q)]++] = p;
  }
  std::vector<int> count(nodes);
#pragma omp parallel for schedule(dynamic, 4096) if (nodes >= 65536)
  for (std::ptrdiff_t n = 0; n < static_cast<std::ptrdiff_t>(nodes); ++n) {
    const auto first_at = all.begin() + static_cast<std::ptrdiff_t>(start[n]);
    const auto last = all.begin() + static_cast<std::ptrdiff_t>(start[n + 1]);
    std::sort(first_at, last);
    count[n] = static_cast<int>(std::unique(first_at, last) - first_at);
  }
  // The entries this pattern holds are counted in 32 bits (Eigen's and
  // UMFPACK's indices, a 32-bit PETSc): a rank's share beyond that needs more ranks.
  long long entries = 0;
  for (std::size_t n = 0; n < nodes; ++n) entries += static_cast<long long>(count[n]) * D * D;
  if (entries > std::numeric_limits<int>::max())
    throw InputError(fmt::format("the tangent's rows of {} nodes hold {} entries, more than 2^31 - 1 (32-bit "
                                 "indices): run on more MPI ranks, each holding fewer nodes",
                                 end_ - first_, entries));
  offsets_.assign(nodes + 1, 0);
  for (std::size_t n = 0; n < nodes; ++n) offsets_[n + 1] = offsets_[n] + count[n];
  neighbours_.resize(static_cast<std::size_t>(offsets_[nodes]));
  for (std::size_t n = 0; n < nodes; ++n)
    std::copy_n(all.begin() + static_cast<std::ptrdiff_t>(start[n]), count[n], neighbours_.begin() + offsets_[n]);
  all = {};
  outer_.assign(nodes * D + 1, 0);
  for (std::size_t n = 0; n < nodes; ++n)
    for (int k = 0; k < D; ++k) outer_[n * D + k + 1] = outer_[n * D + k] + count[n] * D;
  rank_.resize(static_cast<std::size_t>(cells_.cols()) * N * N);
#pragma omp parallel for schedule(static) if (cells.cols() >= 65536)
  for (Eigen::Index c = 0; c < cells_.cols(); ++c)
    for (int b = 0; b < N; ++b) {
      const int B = cells_(b, c);
      const auto first_at = neighbours_.begin() + offsets_[B], last = neighbours_.begin() + offsets_[B + 1];
      for (int a = 0; a < N; ++a)
        rank_[static_cast<std::size_t>((c * N + b) * N + a)] =
            kept(cells_(a, c)) ? static_cast<int>(std::lower_bound(first_at, last, cells_(a, c)) - first_at) : -1;
    }
}

template <int D>
SparseMatrix BlockPattern<D>::make_matrix() const {
  const int n = num_dofs();
  SparseMatrix A(n, n);
  A.resizeNonZeros(static_cast<Eigen::Index>(non_zeros()));
  std::copy(outer_.begin(), outer_.end(), A.outerIndexPtr());
  int* inner = A.innerIndexPtr();
  for (int B = 0; B < n / D; ++B)
    for (int k = 0; k < D; ++k)
      for (int p = offsets_[B]; p < offsets_[B + 1]; ++p)
        for (int i = 0; i < D; ++i) *inner++ = neighbours_[static_cast<std::size_t>(p)] * D + i;
  std::fill(A.valuePtr(), A.valuePtr() + non_zeros(), 0.0);
  return A;
}

template <int D>
void BlockPattern<D>::add_identity_blocks(double c, const SparseMatrix& N, double* values) const {
  const int nodes = static_cast<int>(offsets_.size()) - 1;
#pragma omp parallel for schedule(static) if (nodes >= 65536)
  for (int B = 0; B < nodes; ++B) {
    // N's column B and B's neighbours are both in increasing node order.
    int rank = 0;
    for (SparseMatrix::InnerIterator it(N, B); it; ++it) {
      if (it.row() < first_ || it.row() >= end_) continue;  // a row this pattern does not keep
      while (neighbours_[static_cast<std::size_t>(offsets_[B] + rank)] != it.row()) ++rank;
      const double value = c * it.value();
      for (int k = 0; k < D; ++k) values[outer_[B * D + k] + rank * D + k] += value;
    }
  }
}

template <int D>
std::vector<int> BlockPattern<D>::kept_cell_ids() const {
  std::vector<int> ids;
  ids.reserve(static_cast<std::size_t>(cells_.cols()));
  for (std::size_t c = 0; c < local_cell_.size(); ++c)
    if (local_cell_[c] >= 0) ids.push_back(static_cast<int>(c));
  return ids;
}

template <int D>
void BlockPattern<D>::renumber_to_kept() {
  local_cell_.resize(static_cast<std::size_t>(cells_.cols()));
  for (std::size_t c = 0; c < local_cell_.size(); ++c) local_cell_[c] = static_cast<int>(c);
  local_cell_.shrink_to_fit();
}

template <int D>
int BlockPattern<D>::find(int row, int col) const {
  const int B = col / D, A = row / D;
  const auto first = neighbours_.begin() + offsets_[B], last = neighbours_.begin() + offsets_[B + 1];
  const auto it = std::lower_bound(first, last, A);
  return (it != last && *it == A) ? outer_[col] + static_cast<int>(it - first) * D + row % D : -1;
}

template class BlockPattern<2>;
template class BlockPattern<3>;

}  // namespace conserve::assembly
