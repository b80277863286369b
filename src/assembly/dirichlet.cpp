#include "assembly/dirichlet.hpp"

#include <algorithm>

namespace conserve::assembly {

DirichletMask::DirichletMask(const SparseMatrix& A, const std::vector<int>& dofs, std::pair<int, int> owned)
    : dofs_(dofs),
      fixed_(static_cast<std::size_t>(A.cols()), 0),
      owned_(owned) {
  for (int d : dofs) fixed_[static_cast<std::size_t>(d)] = 1;
  const std::vector<char>& fixed = fixed_;
  for (int col = 0; col < A.cols(); ++col)
    for (int p = A.outerIndexPtr()[col]; p < A.outerIndexPtr()[col + 1]; ++p) {
      const int row = A.innerIndexPtr()[p];
      if (fixed[row] && row == col && row >= owned.first && row < owned.second)
        diagonal_positions_.push_back(p);
      else if (fixed[row] || fixed[col])
        zero_positions_.push_back(p);
    }
}

void DirichletMask::apply(SparseMatrix& K, double diagonal) const {
  double* v = K.valuePtr();
  for (int p : zero_positions_) v[p] = 0.0;
  for (int p : diagonal_positions_) v[p] = diagonal;
}

void DirichletMask::apply(Eigen::VectorXd& r) const {
  for (int d : dofs_) r[d] = 0.0;
}

}  // namespace conserve::assembly
