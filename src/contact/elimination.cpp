#include "contact/elimination.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <map>

#include <unsupported/Eigen/AutoDiff>

#include "contact/zero_work.hpp"
#include "core/error.hpp"

namespace conserve::contact {
namespace {

/// A row of a map: reduced-unknown index → coefficient.
using Row = std::map<int, double>;

/// Composes every slave dof's row of a map from the constraints' local
/// coefficients by substitution (chains), refusing cycles.
template <int D>
class RowBuilder {
 public:
  using Coefficients = typename Elimination<D>::Coefficients;
  RowBuilder(int num_nodes, const std::vector<Constraint<D>>& constraints, std::vector<const Coefficients*> local)
      : constraints_(constraints),
        local_(std::move(local)),
        of_node_(num_nodes, -1),
        state_(constraints.size(), 0),
        rows_(constraints.size()) {
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
    const Coefficients& l = *local_[c];
    std::array<Row, D> out;
    for (std::size_t a = 0; a < l.nodes.size(); ++a) add_node(out, l.nodes[a], l.master.middleCols(a * D, D));
    if (k.kind == Kind::frictionless)  // (49): slip unknowns in the slave's first D−1 slots
      for (int j = 0; j < D - 1; ++j)
        for (int i = 0; i < D; ++i) out[i][k.slave * D + j] += l.slip(i, j);
    rows_[c] = std::move(out);
    state_[c] = 2;
    order_.push_back(c);
    return rows_[c];
  }

  /// Constraints in the order their rows were completed: every constraint
  /// after those of its chained master nodes.
  [[nodiscard]] const std::vector<int>& order() const { return order_; }

 private:
  /// Adds C δx_node (C: D × D) to the rows.
  void add_node(std::array<Row, D>& out, int node, const Eigen::MatrixXd& C) {
    if (of_node_[node] < 0) {
      for (int i = 0; i < D; ++i)
        for (int k = 0; k < D; ++k)
          if (C(i, k) != 0.0) out[i][node * D + k] += C(i, k);
      return;
    }
    const std::array<Row, D>& sub = rows(of_node_[node]);
    for (int i = 0; i < D; ++i)
      for (int k = 0; k < D; ++k)
        if (C(i, k) != 0.0)
          for (const auto& [q, c] : sub[k]) out[i][q] += C(i, k) * c;
  }

  const std::vector<Constraint<D>>& constraints_;
  std::vector<const Coefficients*> local_;
  std::vector<int> of_node_;
  std::vector<char> state_;  ///< 0 new, 1 being expanded, 2 done
  std::vector<std::array<Row, D>> rows_;
  std::vector<int> order_;
};

/// N(ξ) ⊗ 1 over a facet's nodes: D × D².
template <int D>
Eigen::MatrixXd shape_block(const Xi<D>& xi) {
  const Vec<D> N = facet_shape<D>(xi);
  Eigen::MatrixXd C = Eigen::MatrixXd::Zero(D, D * D);
  for (int b = 0; b < D; ++b) C.middleCols(b * D, D) = N(b) * Mat<D>::Identity();
  return C;
}

template <int N>
using AD = Eigen::AutoDiffScalar<Eigen::Matrix<double, N, 1>>;

/// Seeds x as the AD variables of the end positions: entry k of the
/// flattened matrix has derivative e_k. The same seeding serves for the
/// displacements dx = x − x_n, whose derivatives are those of x.
template <int N, int R, int C>
Eigen::Matrix<AD<N>, R, C> variables(const Eigen::Matrix<double, R, C>& x) {
  Eigen::Matrix<AD<N>, R, C> y;
  for (int k = 0; k < R * C; ++k) y(k) = AD<N>(x(k), N, k);
  return y;
}

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

template <int D>
typename Elimination<D>::Kernel Elimination<D>::kernel_input(const Constraint<D>& k, const Eigen::VectorXd& u) const {
  Kernel in;
  auto put = [&](int column, int node) {
    in.x.col(column) = X_.col(node) + u.template segment<D>(node * D);
    in.dx.col(column) = u.template segment<D>(node * D) - u_n_.template segment<D>(node * D);
  };
  put(0, k.slave);
  for (int b = 0; b < D; ++b) put(b + 1, k.master[b]);
  in.xm_n = in.x.template rightCols<D>() - in.dx.template rightCols<D>();
  if (k.kind == Kind::stick)
    in.offset = (X_.col(k.slave) + u_n_.template segment<D>(k.slave * D)) -
                zero_work::stick_position<D, double>(in.xm_n, k.xi, k.gap);
  return in;
}

template <int D>
typename Elimination<D>::Local Elimination<D>::local(const Constraint<D>& k, const Eigen::VectorXd& u) const {
  Local l;
  const Kernel in = kernel_input(k, u);
  l.test.nodes.assign(k.master.begin(), k.master.end());
  l.trial.nodes = l.test.nodes;
  const auto xm = in.x.template rightCols<D>();
  if (k.kind == Kind::stick) {
    l.trial.master = zero_work::stick_jacobian<D, double>(xm, k.xi, k.gap);
    l.test.master = zero_work::stick_test<D, double>(xm, in.dx.template rightCols<D>(), in.xm_n, in.offset, k.xi, k.gap);
    return l;
  }
  const Projection<D> p = project<D>(in.x.col(0), xm);
  l.trial.master = shape_block<D>(p.xi);
  l.trial.slip = p.tangents;
  const auto t = zero_work::frictionless_test<D, double>(in.x, in.dx);
  l.test.master = t.master;
  l.test.slip = t.slip;
  return l;
}

template <int D>
void Elimination<D>::build(const Eigen::VectorXd* u) {
  const int n = num_nodes_ * D;
  std::vector<Local> locals;
  locals.reserve(constraints_.size());
  for (const Constraint<D>& k : constraints_) {
    if (u && pairs_) {
      locals.push_back(local(k, *u));
      continue;
    }
    Local l;  // no geometry: the slave on its facet at ξ, the paper's maps
    l.trial.nodes.assign(k.master.begin(), k.master.end());
    l.trial.master = shape_block<D>(k.xi);
    l.trial.slip = k.tangents;
    l.test = l.trial;
    locals.push_back(std::move(l));
  }
  if (u) u_ = *u;
  std::vector<const Coefficients*> trial, test;
  for (const Local& l : locals) trial.push_back(&l.trial), test.push_back(&l.test);
  test_.clear();
  for (const Local& l : locals) test_.push_back(l.test);
  RowBuilder<D> trial_builder(num_nodes_, constraints_, trial), test_builder(num_nodes_, constraints_, test);
  is_slave_.assign(num_nodes_, 0);
  slave_row_of_.assign(n, -1);
  trial_rows_.clear();
  test_rows_.clear();
  std::vector<Eigen::Triplet<double>> t, w, d;
  for (std::size_t c = 0; c < constraints_.size(); ++c) {
    const Constraint<D>& k = constraints_[c];
    is_slave_[k.slave] = 1;
    const auto& trial_rows = trial_builder.rows(static_cast<int>(c));
    const auto& test_rows = test_builder.rows(static_cast<int>(c));
    for (int i = 0; i < D; ++i) {
      slave_row_of_[k.slave * D + i] = static_cast<int>(trial_rows_.size());
      trial_rows_.emplace_back(k.slave * D + i, Terms(trial_rows[i].begin(), trial_rows[i].end()));
      test_rows_.emplace_back(k.slave * D + i, Terms(test_rows[i].begin(), test_rows[i].end()));
      for (const auto& [q, coeff] : trial_rows[i]) t.emplace_back(k.slave * D + i, q, coeff);
      for (const auto& [q, coeff] : test_rows[i]) w.emplace_back(k.slave * D + i, q, coeff);
    }
    for (int j = (k.kind == Kind::frictionless ? D - 1 : 0); j < D; ++j)
      d.emplace_back(k.slave * D + j, k.slave * D + j, 1.0);
  }
  order_ = test_builder.order();
  for (int node = 0; node < num_nodes_; ++node)
    if (!is_slave_[node])
      for (int i = 0; i < D; ++i) {
        t.emplace_back(node * D + i, node * D + i, 1.0);
        w.emplace_back(node * D + i, node * D + i, 1.0);
      }
  T_.resize(n, n);
  T_.setFromTriplets(t.begin(), t.end());
  W_.resize(n, n);
  W_.setFromTriplets(w.begin(), w.end());
  dummy_.resize(n, n);
  dummy_.setFromTriplets(d.begin(), d.end());
}

template <int D>
typename Elimination<D>::Terms Elimination<D>::terms(const Rows& rows, int node, int i) const {
  if (!is_slave_[node]) return {{node * D + i, 1.0}};
  return rows[slave_row_of_[node * D + i]].second;
}

template <int D>
void Elimination<D>::reduce_residual(const Eigen::VectorXd& g, Eigen::VectorXd& r) const {
  r = W_.transpose() * g;  // (41), (56)
}

// V = (δW)ᵀ g: the derivative of the constraint's test coefficients
// contracted with the slave's residual, by automatic differentiation of
// the zero-work kernels with respect to the end positions of the
// constraint's nodes, mapped to reduced unknowns through T (inputs) and
// W (outputs).
template <int D>
void Elimination<D>::add_variation(const Constraint<D>& k, const Vec<D>& g_s, const Eigen::VectorXd& u,
                                   std::vector<Eigen::Triplet<double>>& v) const {
  const Kernel in = kernel_input(k, u);
  if (k.kind == Kind::stick) {
    constexpr int N = D * D;
    const zero_work::Facet<D, double> xm = in.x.template rightCols<D>(), dxm = in.dx.template rightCols<D>();
    const auto A = zero_work::stick_test<D, AD<N>>(variables<N>(xm), variables<N>(dxm), in.xm_n, in.offset, k.xi,
                                                   k.gap);
    const Eigen::Matrix<AD<N>, N, 1> rho = A.transpose() * g_s.template cast<AD<N>>();
    for (int o = 0; o < N; ++o)
      for (const auto& [q1, c1] : terms(test_rows_, k.master[o / D], o % D))
        for (int i = 0; i < N; ++i) {
          const double dr = rho(o).derivatives()(i);
          if (dr == 0.0) continue;
          for (const auto& [q2, c2] : terms(trial_rows_, k.master[i / D], i % D)) v.emplace_back(q1, q2, c1 * dr * c2);
        }
    return;
  }
  constexpr int N = D * (D + 1);
  const auto t = zero_work::frictionless_test<D, AD<N>>(variables<N>(in.x), variables<N>(in.dx));
  const Eigen::Matrix<AD<N>, D, 1> gs = g_s.template cast<AD<N>>();
  auto node_of = [&](int i) { return i < D ? k.slave : k.master[i / D - 1]; };
  for (int o = 0; o < D * D + D - 1; ++o) {
    const AD<N> rho = o < D * D ? t.master.col(o).dot(gs) : t.slip.col(o - D * D).dot(gs);
    const Terms out = o < D * D ? terms(test_rows_, k.master[o / D], o % D) : Terms{{k.slave * D + o - D * D, 1.0}};
    for (const auto& [q1, c1] : out)
      for (int i = 0; i < N; ++i) {
        const double dr = rho.derivatives()(i);
        if (dr == 0.0) continue;
        for (const auto& [q2, c2] : terms(trial_rows_, node_of(i), i % D)) v.emplace_back(q1, q2, c1 * dr * c2);
      }
  }
}

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
  if (pairs_ && u_.size() == g.size()) {
    // The residual each slave passes on to its masters' rows: its own plus
    // what chained slaves passed on to it (a chain's slave is a master node
    // of another constraint), accumulated from the outer end of the chains.
    Eigen::VectorXd passed = g;
    for (auto c = order_.rbegin(); c != order_.rend(); ++c) {
      const Constraint<D>& k = constraints_[*c];
      const Coefficients& l = test_[*c];
      const Vec<D> gs = passed.template segment<D>(k.slave * D);
      for (std::size_t a = 0; a < l.nodes.size(); ++a)
        if (is_slave_[l.nodes[a]])
          passed.template segment<D>(l.nodes[a] * D) += l.master.middleCols(a * D, D).transpose() * gs;
    }
    for (const Constraint<D>& k : constraints_) add_variation(k, passed.template segment<D>(k.slave * D), u_, v);
  }
  SparseMatrix extra(K.rows(), K.cols());
  extra.setFromTriplets(v.begin(), v.end());
  K_r = SparseMatrix(W_.transpose() * K * T_) + extra;  // (43), (58)
}

template <int D>
void Elimination<D>::expand(const Eigen::VectorXd& q, Eigen::VectorXd& du) const {
  du = T_ * q;
}

// The frictionless slave back to its held gap γ on its facet, the facet
// the slave's end position projects on, which is also the facet its force
// acts on: then a·Δx, the work the zero-work correction has to absorb, is
// of third order in the step except on the step a slave crosses an edge
// (contact/zero_work.hpp). The facet may be switched at most kMaxSwitches
// times per solve, by walking to the facet the point projects on or, at a
// concave edge, to a neighbour the slave projects inside with a gap
// smaller by more than round-off (so that it ends behind neither facet).
// The cap keeps Newton's iterates from hopping between facets: a slave on
// a vertex of a surface whose concavity changes from iterate to iterate
// (conforming meshes) has no fixed point otherwise. After the cap the
// projection is extrapolated, which is safe at a convex edge (the extended
// plane lies outside the neighbour); at a concave one the slave may end
// behind the neighbour by the surface's kink (docs/theory.md, "Limits";
// history.csv's max_penetration shows it).
template <int D>
void Elimination<D>::place_frictionless(Constraint<D>& k, Positions<D>& x, Positions<D>& x_mid, int& switches) const {
  const ContactSurface& master = (*pairs_)[k.pair].master;
  const double tol = (*pairs_)[k.pair].search.inside_tolerance;
  // A neighbour must be lower by more than round-off: on a flat surface
  // (or at a vertex the slave sits on) all facets give the same gap, and a
  // choice made by round-off would hop between iterations.
  const double lower = (*pairs_)[k.pair].search.penetration_tolerance;
  Vec<D> xs = x.col(k.slave);
  int facet = k.facet;
  for (int pass = 0; pass < 4; ++pass) {
    Match<D> best{facet, project<D>(xs, facet_nodes<D>(master, facet, x))};
    if (switches < kMaxSwitches) {
      best = follow<D>(xs, best, master, x, tol);
      for (int side = 0; side < D; ++side) {
        const int next = master.facet_neighbours(side, best.facet);
        if (next < 0) continue;
        const Projection<D> p = project<D>(xs, facet_nodes<D>(master, next, x));
        if (p.inside(tol) && p.gap < best.projection.gap - lower) best = Match<D>{next, p};
      }
    }
    xs -= (best.projection.gap - k.gap) * best.projection.normal;
    if (best.facet == facet) break;
    facet = best.facet;
    ++switches;
  }
  x.col(k.slave) = xs;
  x_mid.col(k.slave) = 0.5 * (xs + (X_.col(k.slave) + u_n_.template segment<D>(k.slave * D)));
  const Projection<D> mid = project<D>(x_mid.col(k.slave), facet_nodes<D>(master, facet, x_mid));  // (60)–(64), 2
  k.facet = facet;
  for (int a = 0; a < D; ++a) k.master[a] = master.facets(a, facet);
  k.xi = mid.xi;
  k.normal = mid.normal;
  k.tangents = mid.tangents;
}

template <int D>
void Elimination<D>::enforce(Eigen::VectorXd& u) {
  if (!pairs_) throw Error("Elimination::enforce needs the step's geometry (the geometry constructor)");
  Positions<D> x = positions(u), x_mid = 0.5 * (x + positions(u_n_));
  for (int sweep = 0; sweep < 2; ++sweep) {  // a second sweep settles chains
    for (std::size_t c = 0; c < constraints_.size(); ++c) {
      Constraint<D>& k = constraints_[c];
      if (k.kind == Kind::stick) {  // (45): the slave at its point of the facet's frame
        zero_work::Facet<D, double> xm;
        for (int b = 0; b < D; ++b) xm.col(b) = x.col(k.master[b]);
        x.col(k.slave) = zero_work::stick_position<D, double>(xm, k.xi, k.gap);
        x_mid.col(k.slave) = 0.5 * (x.col(k.slave) + X_.col(k.slave) + u_n_.template segment<D>(k.slave * D));
      } else {
        place_frictionless(k, x, x_mid, switches_[c]);
      }
    }
  }
  for (const Constraint<D>& k : constraints_)
    u.template segment<D>(k.slave * D) = x.col(k.slave) - X_.col(k.slave);
  build(&u);
}

template <int D>
void Elimination<D>::update(const Eigen::VectorXd& q, Eigen::VectorXd& u) {
  u += T_ * q;  // (49), (60)
  enforce(u);
}

template class Elimination<2>;
template class Elimination<3>;

}  // namespace conserve::contact
