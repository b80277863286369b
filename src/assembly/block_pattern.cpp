#include "assembly/block_pattern.hpp"

#include <algorithm>

namespace conserve::assembly {

template <int D>
BlockPattern<D>::BlockPattern(int num_nodes, const Eigen::MatrixXi& cells,
                              const std::vector<std::pair<int, int>>& extra)
    : cells_(cells), neighbours_(num_nodes) {
  for (int c = 0; c < cells.cols(); ++c)
    for (int a = 0; a <= D; ++a)
      for (int b = 0; b <= D; ++b) neighbours_[cells(b, c)].push_back(cells(a, c));
  for (const auto& [p, q] : extra) {
    neighbours_[p].push_back(q);
    neighbours_[q].push_back(p);
  }
  for (int n = 0; n < num_nodes; ++n) {
    auto& nb = neighbours_[n];
    nb.push_back(n);  // every node keeps its diagonal block, even if isolated
    std::sort(nb.begin(), nb.end());
    nb.erase(std::unique(nb.begin(), nb.end()), nb.end());
  }
  outer_.assign(num_nodes * D + 1, 0);
  for (int n = 0; n < num_nodes; ++n)
    for (int k = 0; k < D; ++k) outer_[n * D + k + 1] = outer_[n * D + k] + static_cast<int>(neighbours_[n].size()) * D;
  inner_.reserve(outer_.back());
  for (int n = 0; n < num_nodes; ++n)
    for (int k = 0; k < D; ++k)
      for (int m : neighbours_[n])
        for (int i = 0; i < D; ++i) inner_.push_back(m * D + i);
  rank_.resize(cells.cols() * (D + 1) * (D + 1));
  for (int c = 0; c < cells.cols(); ++c)
    for (int b = 0; b <= D; ++b) {
      const auto& nb = neighbours_[cells(b, c)];
      for (int a = 0; a <= D; ++a)
        rank_[(c * (D + 1) + b) * (D + 1) + a] =
            static_cast<int>(std::lower_bound(nb.begin(), nb.end(), cells(a, c)) - nb.begin());
    }
}

template <int D>
SparseMatrix BlockPattern<D>::make_matrix() const {
  const int n = num_dofs();
  SparseMatrix A(n, n);
  A.resizeNonZeros(static_cast<Eigen::Index>(inner_.size()));
  std::copy(outer_.begin(), outer_.end(), A.outerIndexPtr());
  std::copy(inner_.begin(), inner_.end(), A.innerIndexPtr());
  std::fill(A.valuePtr(), A.valuePtr() + inner_.size(), 0.0);
  return A;
}

template <int D>
int BlockPattern<D>::find(int row, int col) const {
  const auto first = inner_.begin() + outer_[col];
  const auto last = inner_.begin() + outer_[col + 1];
  const auto it = std::lower_bound(first, last, row);
  return (it != last && *it == row) ? static_cast<int>(it - inner_.begin()) : -1;
}

template class BlockPattern<2>;
template class BlockPattern<3>;

}  // namespace conserve::assembly
