#pragma once
/// Direct elimination of the active slaves' unknowns (ALGORITHM.md §4,
/// paper (35), (41), (43)–(45)): the step increment is Δu = T q, where q has
/// the same size as u; a slave's slots in q are dummies with zero right-hand
/// side, so the number of equations never changes. The reduced system is
///   r = Tᵀ g,   K_r = Tᵀ K T + β on each slave's dummy diagonal,
/// with β = tr(K_ss)/D (44). A slave whose master node is itself a slave
/// (a chain) is expanded by substitution down to free nodes; a cycle is
/// refused with a clear error.
#include <vector>

#include "contact/constraint.hpp"

namespace conserve::contact {

template <int D>
class Elimination {
 public:
  /// Builds T for the constraints (empty: T = 1). Throws SolverError on a
  /// cycle of slaves and on a slave constrained twice.
  Elimination(int num_nodes, const std::vector<Constraint<D>>& constraints);

  [[nodiscard]] bool empty() const { return slaves_.empty(); }
  /// The map from reduced unknowns to full increments, ndof × ndof.
  [[nodiscard]] const SparseMatrix& map() const { return T_; }

  /// r = Tᵀ g (the slave slots come out zero).
  void reduce_residual(const Eigen::VectorXd& g, Eigen::VectorXd& r) const;
  /// K_r = Tᵀ K T + β 1 on the slave slots.
  void reduce_tangent(const SparseMatrix& K, SparseMatrix& K_r) const;
  /// Full increment Δu = T q.
  void expand(const Eigen::VectorXd& q, Eigen::VectorXd& du) const;
  /// Makes u_{n+1} satisfy the constraints given u_n: u_s = u_{s,n} + Σ c (u_p − u_{p,n}).
  void enforce(const Eigen::VectorXd& u_n, Eigen::VectorXd& u_np1) const;

 private:
  std::vector<int> slaves_;     ///< constrained nodes
  std::vector<char> is_slave_;  ///< per node
  /// Each slave dof's row of T: (row, [(reduced unknown, coefficient)]).
  std::vector<std::pair<int, std::vector<std::pair<int, double>>>> slave_rows_;
  SparseMatrix T_;
  SparseMatrix dummy_;  ///< 1 on the slave slots' diagonal, zero elsewhere
};

}  // namespace conserve::contact
