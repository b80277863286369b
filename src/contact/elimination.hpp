#pragma once
/// Direct elimination of the active slaves' unknowns (ALGORITHM.md §4–§6,
/// paper (35), (41), (43)–(45), (49), (56)–(64)). The Newton increment is
/// Δu = T q, where q has the same size as u; a slave's slots in q hold its
/// slip increments (frictionless: Δξ[, Δη]) and dummies with zero right-hand
/// side, so the number of equations never changes. The reduced system is
///   r = Tᵀ g (41)/(56),   K_r = Tᵀ K T′ + V + β (43)/(58),
/// with β = tr(K_ss)/D on the dummy diagonal (44)/(59). For frictionless
/// slaves N and τ are re-evaluated at the mid-point closest-point projection
/// after every update (60)–(64), which also removes the normal violation;
/// T′ (the first-order effect of that correction) and V (the variation of
/// N and τ, the paper's A, Ā) make the tangent consistent. A slave whose
/// master node is itself a slave (a chain) is expanded by substitution; a
/// cycle is refused with a clear error.
#include <vector>

#include "contact/constraint.hpp"

namespace conserve::contact {

template <int D>
class Elimination {
 public:
  /// Constraints taken as they are (no geometry, no slave updates): for
  /// tests of the map, and for stick.
  Elimination(int num_nodes, const std::vector<Constraint<D>>& constraints);

  /// The elimination of one step from u_n, with the geometry needed to
  /// update frictionless slaves (`pairs` must outlive it). `u` is the
  /// current iterate; it is not modified (call enforce()).
  Elimination(const Positions<D>& X, const Eigen::VectorXd& u_n, const Eigen::VectorXd& u,
              const std::vector<Constraint<D>>& constraints, const std::vector<ContactPair<D>>& pairs);

  [[nodiscard]] bool empty() const { return constraints_.empty(); }
  [[nodiscard]] const std::vector<Constraint<D>>& constraints() const { return constraints_; }
  /// The map from reduced unknowns to full increments, ndof × ndof.
  [[nodiscard]] const SparseMatrix& map() const { return T_; }

  /// r = Tᵀ g (the dummy slots come out zero).
  void reduce_residual(const Eigen::VectorXd& g, Eigen::VectorXd& r) const;
  /// K_r = Tᵀ K T′ + V(g) + β on the dummy slots; g is the full residual at
  /// the same iterate.
  void reduce_tangent(const SparseMatrix& K, const Eigen::VectorXd& g, SparseMatrix& K_r) const;
  /// Δu = T q (step 1 of (60)–(64)).
  void expand(const Eigen::VectorXd& q, Eigen::VectorXd& du) const;
  /// Applies the reduced increment: u += T q, then (frictionless) the
  /// mid-point projection and the normal correction, and re-evaluates T.
  void update(const Eigen::VectorXd& q, Eigen::VectorXd& u);
  /// Puts a predictor on the constraints: stick slaves follow their master
  /// point (45); frictionless slaves are projected and corrected (62)–(64).
  void enforce(Eigen::VectorXd& u);

 private:
  /// Per frictionless constraint, with local unknowns w = (δx_m (D nodes ×
  /// D), δξ (D−1)): S maps w to the slave's first-order motion including
  /// the normal correction (its rows of T′); dxi maps w to the change of the
  /// mid-point projection ξ_{n+½}.
  struct Local {
    static constexpr int W = D * D + D - 1;
    int constraint = -1;
    Eigen::Matrix<double, D, W> S;
    Eigen::Matrix<double, D - 1, W> dxi;
  };
  void build(const Eigen::VectorXd* u);
  /// Reduced unknowns (with coefficients) behind local unknown κ of a
  /// frictionless constraint: a master node's dof (through its own row of T
  /// if it is itself a slave) or a slip slot.
  [[nodiscard]] std::vector<std::pair<int, double>> local_terms(const Constraint<D>& k, int kappa) const;
  void project_frictionless(Eigen::VectorXd& u);
  [[nodiscard]] Positions<D> positions(const Eigen::VectorXd& u) const;

  std::vector<Constraint<D>> constraints_;
  const std::vector<ContactPair<D>>* pairs_ = nullptr;
  Positions<D> X_;
  Eigen::VectorXd u_n_;
  int num_nodes_ = 0;
  std::vector<char> is_slave_;    ///< per node
  std::vector<char> is_stick_;    ///< per node: slave of a stick constraint
  std::vector<int> slave_row_of_; ///< per dof: index into slave_rows_, or −1
  /// Each slave dof's row of T: (row, [(reduced unknown, coefficient)]).
  std::vector<std::pair<int, std::vector<std::pair<int, double>>>> slave_rows_;
  SparseMatrix T_, T_prime_, dummy_;
  std::vector<Local> locals_;
  static constexpr int kMaxSwitches = 2;
  std::vector<int> switches_;  ///< facet switches per constraint in this solve
};

}  // namespace conserve::contact
