#pragma once
/// Prescribed degrees of freedom in the Newton system: their rows and
/// columns are replaced by a scaled identity and their residual by zero, so
/// the increment on them comes out exactly zero and the number of equations
/// (and the sparsity pattern) stays the same.
#include <limits>
#include <utility>
#include <vector>

#include "assembly/block_pattern.hpp"

namespace conserve::assembly {

class DirichletMask {
 public:
  DirichletMask() = default;
  /// `pattern_matrix` fixes the layout the mask will be applied to; the
  /// diagonal is put on the rows [owned.first, owned.second) alone (a
  /// rank's: another rank's part of a row it shares is zeroed only).
  DirichletMask(const SparseMatrix& pattern_matrix, const std::vector<int>& dofs,
                std::pair<int, int> owned = {0, std::numeric_limits<int>::max()});

  /// Zeroes the prescribed rows and columns of K and puts `diagonal` on
  /// their diagonal (choose it of the order of K's diagonal).
  void apply(SparseMatrix& K, double diagonal) const;
  /// Zeroes the prescribed entries of a residual.
  void apply(Eigen::VectorXd& r) const;
  [[nodiscard]] const std::vector<int>& dofs() const { return dofs_; }
  /// Whether dof d is prescribed.
  [[nodiscard]] bool masked(int d) const { return fixed_[static_cast<std::size_t>(d)] != 0; }
  /// The rows that get the diagonal.
  [[nodiscard]] std::pair<int, int> owned() const { return owned_; }

 private:
  std::vector<int> dofs_;
  std::vector<char> fixed_;  ///< per dof: prescribed
  std::pair<int, int> owned_{0, std::numeric_limits<int>::max()};
  std::vector<int> zero_positions_;
  std::vector<int> diagonal_positions_;
};

}  // namespace conserve::assembly
