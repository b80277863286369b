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

using Terms = std::vector<std::pair<int, double>>;

}  // namespace

template <int D>
Elimination<D>::Elimination(int num_nodes, const std::vector<Constraint<D>>& constraints)
    : constraints_(constraints), num_nodes_(num_nodes) {
  build(nullptr);
}

template <int D>
Elimination<D>::Elimination(const Positions<D>& X, const Eigen::VectorXd& u_n, const Eigen::VectorXd& u,
                            const std::vector<Constraint<D>>& constraints, const std::vector<ContactPair<D>>& pairs)
    : constraints_(constraints),
      pairs_(&pairs),
      X_(X),
      u_n_(u_n),
      num_nodes_(static_cast<int>(X.cols())),
      switches_(constraints.size(), 0) {
  build(&u);
}

template <int D>
Positions<D> Elimination<D>::positions(const Eigen::VectorXd& u) const {
  return X_ + u.reshaped(D, num_nodes_);
}

namespace {

/// First-order data of one frictionless constraint at positions x (end of
/// step) and x_n (start): see Elimination::Local and the derivation in
/// docs/theory.md. c = (d_s − N d_m)·n with d = x − x_n is the normal
/// constraint (48); the update keeps c = 0 by moving the slave along n.
template <int D, class Local>
Local frictionless_local(const Constraint<D>& k, const Positions<D>& x, const Positions<D>& x_n) {
  FacetNodes<D> xm, xm_n;
  for (int a = 0; a < D; ++a) xm.col(a) = x.col(k.master[a]), xm_n.col(a) = x_n.col(k.master[a]);
  const Vec<D> ys = 0.5 * (x.col(k.slave) + x_n.col(k.slave));
  const FacetNodes<D> ym = 0.5 * (xm + xm_n);
  const Projection<D> p = project<D>(ys, ym);
  const auto Jxi = xi_gradient<D>(ys, ym);
  const auto Jn = normal_gradient<D>(ym);
  const Vec<D> N = facet_shape<D>(p.xi);
  const FacetNodes<D> dm = xm - xm_n;
  const Vec<D> h = (x.col(k.slave) - x_n.col(k.slave)) - dm * N;
  Xi<D> a;  // Σ_a (d_m,a·n) ∇N_a, ∇N_0 = −1, ∇N_j = e_{j−1}
  for (int j = 0; j < D - 1; ++j) a(j) = (dm.col(j + 1) - dm.col(0)).dot(p.normal);
  const Eigen::Matrix<double, 1, D> dc_s = p.normal.transpose() - 0.5 * a.transpose() * Jxi.template leftCols<D>();
  Eigen::Matrix<double, D, Local::W> S0 = Eigen::Matrix<double, D, Local::W>::Zero();
  Eigen::Matrix<double, 1, Local::W> dc_m = Eigen::Matrix<double, 1, Local::W>::Zero();
  for (int b = 0; b < D; ++b) {
    S0.template block<D, D>(0, b * D) = N(b) * Mat<D>::Identity();
    dc_m.template segment<D>(b * D) = -N(b) * p.normal.transpose() -
                                      0.5 * a.transpose() * Jxi.template block<D - 1, D>(0, D * (b + 1)) +
                                      0.5 * h.transpose() * Jn.template block<D, D>(0, D * (b + 1));
  }
  S0.template rightCols<D - 1>() = p.tangents;
  Local l;
  l.S = S0 - p.normal * (dc_s * S0 + dc_m) / dc_s.dot(p.normal);
  Eigen::Matrix<double, D - 1, Local::W> dxi_m = Eigen::Matrix<double, D - 1, Local::W>::Zero();
  dxi_m.template leftCols<D * D>() = Jxi.template rightCols<D * D>();
  l.dxi = 0.5 * (Jxi.template leftCols<D>() * l.S + dxi_m);
  return l;
}

}  // namespace

template <int D>
void Elimination<D>::build(const Eigen::VectorXd* u) {
  const int n = num_nodes_ * D;
  RowBuilder<D> builder(num_nodes_, constraints_);
  is_slave_.assign(num_nodes_, 0);
  is_stick_.assign(num_nodes_, 0);
  slave_row_of_.assign(n, -1);
  slave_rows_.clear();
  locals_.clear();
  for (const Constraint<D>& k : constraints_) {
    is_slave_[k.slave] = 1;
    is_stick_[k.slave] = k.kind == Kind::stick;
  }
  std::vector<Eigen::Triplet<double>> t, d;
  for (std::size_t c = 0; c < constraints_.size(); ++c) {
    const Constraint<D>& k = constraints_[c];
    const auto& rows = builder.rows(static_cast<int>(c));
    for (int i = 0; i < D; ++i) {
      slave_row_of_[k.slave * D + i] = static_cast<int>(slave_rows_.size());
      slave_rows_.emplace_back(k.slave * D + i, Terms(rows[i].begin(), rows[i].end()));
      for (const auto& [q, coeff] : rows[i]) t.emplace_back(k.slave * D + i, q, coeff);
    }
    for (int j = (k.kind == Kind::frictionless ? D - 1 : 0); j < D; ++j)
      d.emplace_back(k.slave * D + j, k.slave * D + j, 1.0);
  }
  for (int node = 0; node < num_nodes_; ++node)
    if (!is_slave_[node])
      for (int i = 0; i < D; ++i) t.emplace_back(node * D + i, node * D + i, 1.0);
  T_.resize(n, n);
  T_.setFromTriplets(t.begin(), t.end());
  dummy_.resize(n, n);
  dummy_.setFromTriplets(d.begin(), d.end());
  T_prime_ = T_;
  if (!u || !pairs_) return;
  const Positions<D> x = positions(*u), x_n = positions(u_n_);
  for (std::size_t c = 0; c < constraints_.size(); ++c) {
    if (constraints_[c].kind != Kind::frictionless) continue;
    locals_.push_back(frictionless_local<D, Local>(constraints_[c], x, x_n));
    locals_.back().constraint = static_cast<int>(c);
  }
  // T′: the frictionless slaves' rows become S mapped to the reduced unknowns.
  std::vector<Eigen::Triplet<double>> tp;
  std::vector<char> replaced(n, 0);
  for (const Local& l : locals_) {
    const Constraint<D>& k = constraints_[l.constraint];
    for (int kappa = 0; kappa < Local::W; ++kappa)
      for (const auto& [q, coeff] : local_terms(k, kappa))
        for (int i = 0; i < D; ++i) tp.emplace_back(k.slave * D + i, q, l.S(i, kappa) * coeff);
    for (int i = 0; i < D; ++i) replaced[k.slave * D + i] = 1;
  }
  for (const auto& tr : t)
    if (!replaced[tr.row()]) tp.push_back(tr);
  T_prime_.setFromTriplets(tp.begin(), tp.end());
}

template <int D>
std::vector<std::pair<int, double>> Elimination<D>::local_terms(const Constraint<D>& k, int kappa) const {
  if (kappa >= D * D) return {{k.slave * D + kappa - D * D, 1.0}};  // slip slot
  const int node = k.master[kappa / D], i = kappa % D;
  if (!is_slave_[node]) return {{node * D + i, 1.0}};
  return slave_rows_[slave_row_of_[node * D + i]].second;  // a chained master: its own row of T
}

template <int D>
void Elimination<D>::reduce_residual(const Eigen::VectorXd& g, Eigen::VectorXd& r) const {
  r = T_.transpose() * g;  // (41), (56)
}

// V = (δT)ᵀ g: master rows get g_s δN_b (δN_b = ∇N_b·δξ_{n+½}), slip rows
// get g_s·δτ_j with δτ_j = ½(δx_{m,j} − δx_{m,0}) (mid-point tangents).
template <int D>
void Elimination<D>::reduce_tangent(const SparseMatrix& K, const Eigen::VectorXd& g, SparseMatrix& K_r) const {
  std::vector<Eigen::Triplet<double>> v;
  for (int k = 0; k < dummy_.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(dummy_, k); it; ++it) {
      const int s = it.row() / D;  // (44), (59): β = tr(K_ss)/D
      double trace = 0.0;
      for (int i = 0; i < D; ++i) trace += K.coeff(s * D + i, s * D + i);
      v.emplace_back(it.row(), it.col(), trace / D);
    }
  for (const Local& l : locals_) {
    const Constraint<D>& k = constraints_[l.constraint];
    const Vec<D> gs = g.template segment<D>(k.slave * D);
    Eigen::Matrix<double, Local::W, Local::W> V = Eigen::Matrix<double, Local::W, Local::W>::Zero();
    for (int b = 0; b < D; ++b) {
      Xi<D> gradN = b == 0 ? Xi<D>(-Xi<D>::Ones()) : Xi<D>(Xi<D>::Unit(b - 1));
      V.template block<D, Local::W>(b * D, 0) = gs * (gradN.transpose() * l.dxi);
    }
    for (int j = 0; j < D - 1; ++j) {
      V.template block<1, D>(D * D + j, D * (j + 1)) += 0.5 * gs.transpose();
      V.template block<1, D>(D * D + j, 0) -= 0.5 * gs.transpose();
    }
    for (int rho = 0; rho < Local::W; ++rho)
      for (int kappa = 0; kappa < Local::W; ++kappa) {
        if (V(rho, kappa) == 0.0) continue;
        for (const auto& [q1, c1] : local_terms(k, rho))
          for (const auto& [q2, c2] : local_terms(k, kappa)) v.emplace_back(q1, q2, c1 * V(rho, kappa) * c2);
      }
  }
  SparseMatrix extra(K.rows(), K.cols());
  extra.setFromTriplets(v.begin(), v.end());
  K_r = SparseMatrix(T_.transpose() * K * T_prime_) + extra;  // (43), (58)
}

template <int D>
void Elimination<D>::expand(const Eigen::VectorXd& q, Eigen::VectorXd& du) const {
  du = T_ * q;
}

// (60)–(64), steps 2 and 3: the mid-point closest-point projection (moving
// to a neighbouring facet when it has left its own), then the removal of
// the normal violation so that (48) holds exactly.
template <int D>
void Elimination<D>::project_frictionless(Eigen::VectorXd& u) {
  if (!pairs_) return;
  const Positions<D> x_n = positions(u_n_);
  for (int sweep = 0; sweep < 2; ++sweep) {  // a second sweep settles chains
    for (Constraint<D>& k : constraints_) {
      if (k.kind != Kind::frictionless) continue;
      const Positions<D> x = positions(u), x_mid = 0.5 * (x + x_n);
      const ContactSurface& master = (*pairs_)[k.pair].master;
      Match<D> m{k.facet, project<D>(x_mid.col(k.slave), facet_nodes<D>(master, k.facet, x_mid))};
      // Facet switching (§7), at most kMaxSwitches times per solve: a slave
      // near a facet edge could otherwise hop between two facets from one
      // Newton iteration to the next and stall it. After that the facet is
      // kept and the projection extrapolated, which conservation allows.
      int& switches = switches_[&k - constraints_.data()];
      if (switches < kMaxSwitches) {
        m = follow<D>(x_mid.col(k.slave), m, master, x_mid);
        if (m.facet != k.facet) ++switches;
      }
      k.facet = m.facet;
      for (int a = 0; a < D; ++a) k.master[a] = master.facets(a, m.facet);
      k.xi = m.projection.xi;
      k.normal = m.projection.normal;
      k.tangents = m.projection.tangents;
      Vec<D> d = x.col(k.slave) - x_n.col(k.slave);
      const Vec<D> N = facet_shape<D>(k.xi);
      for (int a = 0; a < D; ++a) d -= N(a) * (x.col(k.master[a]) - x_n.col(k.master[a]));
      u.template segment<D>(k.slave * D) -= d.dot(k.normal) * k.normal;
    }
  }
}

template <int D>
void Elimination<D>::update(const Eigen::VectorXd& q, Eigen::VectorXd& u) {
  u += T_ * q;  // step 1 (49), (60)
  project_frictionless(u);
  build(&u);
}

template <int D>
void Elimination<D>::enforce(Eigen::VectorXd& u) {
  if (u_n_.size() != u.size()) throw Error("Elimination::enforce needs the step's start (geometry constructor)");
  for (const auto& [row, terms] : slave_rows_) {  // (45): a stick slave follows its master point
    if (!is_stick_[row / D]) continue;
    double du = 0.0;
    for (const auto& [q, coeff] : terms)
      if (!is_slave_[q / D]) du += coeff * (u[q] - u_n_[q]);
    u[row] = u_n_[row] + du;
  }
  project_frictionless(u);
  build(&u);
}

template class Elimination<2>;
template class Elimination<3>;

}  // namespace conserve::contact
