#include "contact/elimination.hpp"

#include <fmt/format.h>

#include <map>

#include "core/error.hpp"

namespace conserve::contact {
namespace {

/// A row of T: reduced-unknown index → coefficient.
using Row = std::map<int, double>;

/// Expands every slave dof into reduced unknowns by substitution (chains),
/// refusing cycles.
template <int D>
class RowBuilder {
 public:
  RowBuilder(int num_nodes, const std::vector<Constraint<D>>& constraints)
      : constraints_(constraints), of_node_(num_nodes, -1), state_(constraints.size(), 0), rows_(constraints.size()) {
    for (std::size_t c = 0; c < constraints.size(); ++c) {
      int& owner = of_node_[constraints[c].slave];
      if (owner >= 0)
        throw SolverError(fmt::format("node {} is the slave of two active contact constraints", constraints[c].slave));
      owner = static_cast<int>(c);
    }
  }

  /// The D rows of constraint c's slave.
  const std::array<Row, D>& rows(int c) {
    if (state_[c] == 2) return rows_[c];
    if (state_[c] == 1)
      throw SolverError(fmt::format(
          "contact constraints form a cycle through slave node {} (each slave's master is another's slave); "
          "choose the contact pairs so that no body is both slave and master of the same nodes",
          constraints_[c].slave));
    state_[c] = 1;
    const Constraint<D>& k = constraints_[c];
    const Vec<D> N = facet_shape<D>(k.xi);
    std::array<Row, D> out;
    for (int a = 0; a < D; ++a) add_node(out, k.master[a], N(a));
    if (k.kind == Kind::frictionless)  // (49): slip unknowns in the slave's first D−1 slots
      for (int j = 0; j < D - 1; ++j)
        for (int i = 0; i < D; ++i) out[i][k.slave * D + j] += k.tangents(i, j);
    rows_[c] = std::move(out);
    state_[c] = 2;
    return rows_[c];
  }

 private:
  void add_node(std::array<Row, D>& out, int node, double coeff) {
    if (coeff == 0.0) return;
    if (of_node_[node] < 0) {
      for (int i = 0; i < D; ++i) out[i][node * D + i] += coeff;
      return;
    }
    const std::array<Row, D>& sub = rows(of_node_[node]);
    for (int i = 0; i < D; ++i)
      for (const auto& [q, c] : sub[i]) out[i][q] += coeff * c;
  }

  const std::vector<Constraint<D>>& constraints_;
  std::vector<int> of_node_;
  std::vector<char> state_;  ///< 0 new, 1 being expanded, 2 done
  std::vector<std::array<Row, D>> rows_;
};

}  // namespace

template <int D>
Elimination<D>::Elimination(int num_nodes, const std::vector<Constraint<D>>& constraints)
    : is_slave_(num_nodes, 0) {
  const int n = num_nodes * D;
  RowBuilder<D> builder(num_nodes, constraints);
  std::vector<Eigen::Triplet<double>> t, d;
  for (const Constraint<D>& k : constraints) is_slave_[k.slave] = 1;
  for (std::size_t c = 0; c < constraints.size(); ++c) {
    const Constraint<D>& k = constraints[c];
    slaves_.push_back(k.slave);
    const auto& rows = builder.rows(static_cast<int>(c));
    for (int i = 0; i < D; ++i) {
      slave_rows_.emplace_back(k.slave * D + i, std::vector<std::pair<int, double>>(rows[i].begin(), rows[i].end()));
      for (const auto& [q, coeff] : rows[i]) t.emplace_back(k.slave * D + i, q, coeff);
    }
    for (int j = (k.kind == Kind::frictionless ? D - 1 : 0); j < D; ++j)
      d.emplace_back(k.slave * D + j, k.slave * D + j, 1.0);
  }
  for (int node = 0; node < num_nodes; ++node)
    if (!is_slave_[node])
      for (int i = 0; i < D; ++i) t.emplace_back(node * D + i, node * D + i, 1.0);
  T_.resize(n, n);
  T_.setFromTriplets(t.begin(), t.end());
  dummy_.resize(n, n);
  dummy_.setFromTriplets(d.begin(), d.end());
}
template <int D>
void Elimination<D>::reduce_residual(const Eigen::VectorXd& g, Eigen::VectorXd& r) const {
  r = T_.transpose() * g;
}

template <int D>
void Elimination<D>::reduce_tangent(const SparseMatrix& K, SparseMatrix& K_r) const {
  SparseMatrix beta = dummy_;
  for (int k = 0; k < beta.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(beta, k); it; ++it) {
      const int s = it.row() / D;  // (44): β = tr(K_ss)/D
      double trace = 0.0;
      for (int i = 0; i < D; ++i) trace += K.coeff(s * D + i, s * D + i);
      it.valueRef() = trace / D;
    }
  K_r = SparseMatrix(T_.transpose() * K * T_) + beta;
}

template <int D>
void Elimination<D>::expand(const Eigen::VectorXd& q, Eigen::VectorXd& du) const {
  du = T_ * q;
}

// Only the node terms: slip terms (frictionless) are free by definition.
template <int D>
void Elimination<D>::enforce(const Eigen::VectorXd& u_n, Eigen::VectorXd& u_np1) const {
  for (const auto& [row, terms] : slave_rows_) {
    double du = 0.0;
    for (const auto& [q, coeff] : terms)
      if (!is_slave_[q / D]) du += coeff * (u_np1[q] - u_n[q]);
    u_np1[row] = u_n[row] + du;
  }
}

template class Elimination<2>;
template class Elimination<3>;

}  // namespace conserve::contact
