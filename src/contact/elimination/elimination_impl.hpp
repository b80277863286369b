// The definitions of Elimination<D>, included by elimination_2d.cpp and
// elimination_3d.cpp only: each instantiates one dimension, so the two
// halves of its automatic-differentiation code compile side by side.
#pragma once

#include "contact/elimination/elimination.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <optional>

#include <unsupported/Eigen/AutoDiff>

#include "contact/elimination/zero_work.hpp"
#include "core/error.hpp"

namespace conserve::contact {
namespace {

/// Composes every slave's rows of a map, in node blocks, from the
/// constraints' local coefficients by substitution (chains), refusing
/// cycles. Structural: every node the coefficients name is kept, with its
/// block even when that is zero, so that the rows' nodes (and the reduced
/// tangent's pattern) depend on the constraints' nodes only.
template <int D>
class RowBuilder {
 public:
  using Coefficients = typename Elimination<D>::Coefficients;
  /// `slaves`: per group, its slave node (distinct); `local`: per group,
  /// its coefficients.
  RowBuilder(int num_nodes, const std::vector<int>& slaves, std::vector<const Coefficients*> local)
      : slaves_(slaves), local_(std::move(local)), of_node_(num_nodes, -1), state_(slaves.size(), 0), rows_(slaves.size()) {
    for (std::size_t c = 0; c < slaves.size(); ++c) of_node_[slaves[c]] = static_cast<int>(c);
  }

  /// The D rows of group c's slave.
  const BlockRow<D>& rows(int c) {
    if (state_[c] == 2) return rows_[c];
    if (state_[c] == 1)
      throw SolverError(fmt::format(
          "contact constraints form a cycle through slave node {} (each slave's master is another's slave); "
          "choose the contact pairs so that no body is both slave and master of the same nodes",
          slaves_[c]));
    state_[c] = 1;
    const Coefficients& l = *local_[c];
    std::map<int, Mat<D>> out;
    for (std::size_t a = 0; a < l.nodes.size(); ++a) add_node(out, l.nodes[a], l.master.middleCols(a * D, D));
    // (49): slip unknowns in the slave's first slots (zero for stick)
    block(out, slaves_[c]).template leftCols<D - 1>() += l.slip;
    BlockRow<D>& row = rows_[c];
    for (const auto& [node, b] : out) {
      row.nodes.push_back(node);
      row.blocks.push_back(b);
    }
    state_[c] = 2;
    order_.push_back(c);
    return row;
  }

  /// Groups in the order their rows were completed: every group after
  /// those of its chained master nodes.
  [[nodiscard]] const std::vector<int>& order() const { return order_; }

 private:
  static Mat<D>& block(std::map<int, Mat<D>>& out, int node) {
    return out.try_emplace(node, Mat<D>::Zero()).first->second;
  }

  /// Adds C δx_node (C: D × D) to the rows.
  void add_node(std::map<int, Mat<D>>& out, int node, const Mat<D>& C) {
    if (of_node_[node] < 0) {
      block(out, node) += C;
      return;
    }
    const BlockRow<D>& sub = rows(of_node_[node]);
    for (std::size_t b = 0; b < sub.nodes.size(); ++b) block(out, sub.nodes[b]) += C * sub.blocks[b];
  }

  const std::vector<int>& slaves_;
  std::vector<const Coefficients*> local_;
  std::vector<int> of_node_;
  std::vector<char> state_;  ///< 0 new, 1 being expanded, 2 done
  std::vector<BlockRow<D>> rows_;
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
Elimination<D>::Elimination(int num_nodes, std::vector<Constraint<D>>& constraints)
    : constraints_(&constraints), num_nodes_(num_nodes), reduction_(std::make_shared<TangentReduction<D>>()) {
  build(nullptr);
}

template <int D>
Elimination<D>::Elimination(const Positions<D>& X, const Eigen::VectorXd& u_n, const Eigen::VectorXd& u,
                            std::vector<Constraint<D>>& constraints, const std::vector<ContactPair<D>>& pairs,
                            std::shared_ptr<TangentReduction<D>> reduction)
    : constraints_(&constraints),
      pairs_(&pairs),
      X_(X),
      u_n_(u_n),
      num_nodes_(static_cast<int>(X.cols())),
      reduction_(reduction ? std::move(reduction) : std::make_shared<TangentReduction<D>>()),
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
  const auto t = zero_work::frictionless_test<D, double>(in.x, in.dx, !k.push, k.friction, k.slip_scale);
  l.test.master = t.master;
  l.test.slip = t.slip;
  l.cosine = t.cosine;
  return l;
}

// A slave node holds one constraint, or two frictionless ones: of
// different pairs whose facets are not parallel, or of one pair on two
// facets (a crease pair) (the active set's rules, ActiveSet::can_hold,
// ActiveSet::crease); anything else is refused.
template <int D>
void Elimination<D>::make_groups() {
  groups_.clear();
  slave_of_.assign(num_nodes_, -1);
  for (std::size_t c = 0; c < constraints_->size(); ++c) {
    const Constraint<D>& k = (*constraints_)[c];
    int& g = slave_of_[k.slave];
    if (g < 0) {
      g = static_cast<int>(groups_.size());
      groups_.push_back(Group{k.slave, 1, {static_cast<int>(c), -1}});
      continue;
    }
    Group& group = groups_[g];
    const Constraint<D>& first = (*constraints_)[group.constraint[0]];
    if (group.count == 2 || k.kind != Kind::frictionless || first.kind != Kind::frictionless ||
        (k.pair == first.pair && k.facet == first.facet))
      throw SolverError(fmt::format(
          "node {} is the slave of {} active contact constraints (at most two, frictionless, on two facets)", k.slave,
          group.count + 1));
    group.constraint[1] = static_cast<int>(c);
    group.count = 2;
  }
}

template <int D>
typename Elimination<D>::PairKernel Elimination<D>::pair_input(const Group& g, const Eigen::VectorXd& u) const {
  PairKernel in;
  auto put = [&](int column, int node) {
    in.x.col(column) = X_.col(node) + u.template segment<D>(node * D);
    in.dx.col(column) = u.template segment<D>(node * D) - u_n_.template segment<D>(node * D);
  };
  put(0, g.slave);
  for (int k = 0; k < 2; ++k)
    for (int b = 0; b < D; ++b) put(1 + k * D + b, (*constraints_)[g.constraint[k]].master[b]);
  return in;
}

// The trial map of a slave holding two gaps: to first order, gap k moves
// by n_kᵀ(Δx_s − N_k Δx_mk) (exact for a flat facet, whatever the gap,
// since x_s − x(ξ_k) ∥ n_k ⊥ δn_k), so Δx_s = C [n_1ᵀ N_1 Δx_m1; n_2ᵀ N_2
// Δx_m2] + a Δξ with C = [n_1 n_2] G⁻¹ holds both, a = n_1 × n_2 / |…| the
// free slip (3D).
template <int D>
typename Elimination<D>::Local Elimination<D>::local_pair(const Group& g, const Eigen::VectorXd* u) const {
  std::array<Vec<D>, 2> normal;
  std::array<Vec<D>, 2> shape;
  std::optional<PairKernel> in;
  if (u) in = pair_input(g, *u);
  for (int k = 0; k < 2; ++k) {
    const Constraint<D>& c = (*constraints_)[g.constraint[k]];
    if (in) {
      const Projection<D> p = project<D>(in->x.col(0), in->x.template middleCols<D>(1 + k * D));
      normal[k] = p.normal;
      shape[k] = facet_shape<D>(p.xi);
    } else {
      normal[k] = c.normal;
      shape[k] = facet_shape<D>(c.xi);
    }
  }
  Eigen::Matrix<double, D, 2> n;
  n << normal[0], normal[1];
  const Eigen::Matrix<double, D, 2> C = n * (n.transpose() * n).inverse();
  Local l;
  for (int k = 0; k < 2; ++k) {
    const Constraint<D>& c = (*constraints_)[g.constraint[k]];
    l.trial.nodes.insert(l.trial.nodes.end(), c.master.begin(), c.master.end());
  }
  l.trial.master.resize(D, 2 * D * D);
  for (int k = 0; k < 2; ++k)
    for (int b = 0; b < D; ++b)
      l.trial.master.middleCols((k * D + b) * D, D) = shape[k](b) * C.col(k) * normal[k].transpose();
  if constexpr (D == 3) l.trial.slip.col(0) = normal[0].cross(normal[1]).normalized();
  l.test.nodes = l.trial.nodes;
  if (!in) {
    l.test.master = l.trial.master;
    l.test.slip = l.trial.slip;
    return l;
  }
  const auto t = zero_work::pair_frictionless_test<D, double>(in->x, in->dx);
  l.test.master = t.master;
  l.test.slip.col(0) = t.slip;
  return l;
}

template <int D>
void Elimination<D>::build(const Eigen::VectorXd* u) {
  make_groups();
  std::vector<Local> locals;
  locals.reserve(groups_.size());
  const bool geometry = u && pairs_;
  for (const Group& g : groups_) {
    if (g.count == 2) {
      locals.push_back(local_pair(g, geometry ? u : nullptr));
      continue;
    }
    const Constraint<D>& k = (*constraints_)[g.constraint[0]];
    if (geometry) {
      locals.push_back(local(k, *u));
      continue;
    }
    Local l;  // no geometry: the slave on its facet at ξ, the paper's maps
    l.trial.nodes.assign(k.master.begin(), k.master.end());
    l.trial.master = shape_block<D>(k.xi);
    if (k.kind == Kind::frictionless) l.trial.slip = k.tangents;
    l.test = l.trial;
    locals.push_back(std::move(l));
  }
  if (u) u_ = *u;
  std::vector<const Coefficients*> trial, test;
  for (const Local& l : locals) trial.push_back(&l.trial), test.push_back(&l.test);
  test_.clear();
  trial_.clear();
  cosine_.clear();
  for (const Local& l : locals) test_.push_back(l.test), trial_.push_back(l.trial), cosine_.push_back(l.cosine);
  const std::size_t count = groups_.size();
  slaves_.resize(count);
  for (std::size_t g = 0; g < count; ++g) slaves_[g] = groups_[g].slave;
  RowBuilder<D> trial_builder(num_nodes_, slaves_, trial), test_builder(num_nodes_, slaves_, test);
  trial_rows_.resize(count);
  test_rows_.resize(count);
  for (std::size_t g = 0; g < count; ++g) {
    trial_rows_[g] = trial_builder.rows(static_cast<int>(g));
    test_rows_[g] = test_builder.rows(static_cast<int>(g));
  }
  order_ = test_builder.order();
}

template <int D>
SparseMatrix Elimination<D>::assemble(const std::vector<BlockRow<D>>& rows) const {
  const int n = num_nodes_ * D;
  std::vector<Eigen::Triplet<double>> t;
  for (int node = 0; node < num_nodes_; ++node)
    if (slave_of_[node] < 0)
      for (int i = 0; i < D; ++i) t.emplace_back(node * D + i, node * D + i, 1.0);
  for (std::size_t c = 0; c < rows.size(); ++c)
    for (std::size_t b = 0; b < rows[c].nodes.size(); ++b)
      for (int i = 0; i < D; ++i)
        for (int k = 0; k < D; ++k)
          if (rows[c].blocks[b](i, k) != 0.0)
            t.emplace_back(slaves_[c] * D + i, rows[c].nodes[b] * D + k, rows[c].blocks[b](i, k));
  SparseMatrix out(n, n);
  out.setFromTriplets(t.begin(), t.end());
  return out;
}

template <int D>
void Elimination<D>::reduce_residual(const Eigen::VectorXd& g, Eigen::VectorXd& r) const {
  std::vector<Vec<D>> g_s(slaves_.size());  // (41), (56): r = g + Σ_s W_sᵀ g_s − g_s
  for (std::size_t c = 0; c < slaves_.size(); ++c) g_s[c] = g.template segment<D>(slaves_[c] * D);
  r = g;
  for (const int s : slaves_) r.template segment<D>(s * D).setZero();
  for (std::size_t c = 0; c < slaves_.size(); ++c)
    for (std::size_t b = 0; b < test_rows_[c].nodes.size(); ++b)
      r.template segment<D>(test_rows_[c].nodes[b] * D) += test_rows_[c].blocks[b].transpose() * g_s[c];
}

template <int D>
void Elimination<D>::add_variation_block(int c, int out, bool slip, int in, const Mat<D>& G, SparseMatrix& K_r) const {
  if ((G.array() == 0.0).all()) return;
  static const Mat<D> identity = Mat<D>::Identity();
  const int co = slip ? -1 : slave_of_[out], ci = slave_of_[in];
  const int* w_nodes = co < 0 ? &out : test_rows_[co].nodes.data();
  const Mat<D>* w_blocks = co < 0 ? &identity : test_rows_[co].blocks.data();
  const std::size_t w_size = co < 0 ? 1 : test_rows_[co].nodes.size();
  const int* t_nodes = ci < 0 ? &in : trial_rows_[ci].nodes.data();
  const Mat<D>* t_blocks = ci < 0 ? &identity : trial_rows_[ci].blocks.data();
  const std::size_t t_size = ci < 0 ? 1 : trial_rows_[ci].nodes.size();
  for (std::size_t i = 0; i < w_size; ++i) {
    const Mat<D> WG = w_blocks[i].transpose() * G;
    for (std::size_t j = 0; j < t_size; ++j) reduction_->add(c, w_nodes[i], t_nodes[j], WG * t_blocks[j], K_r);
  }
}

// V = (δW)ᵀ g: the derivative of the constraint's test coefficients
// contracted with the slave's residual, by automatic differentiation of
// the zero-work kernels with respect to the end positions of the
// constraint's nodes, mapped to reduced unknowns through T (inputs) and
// W (outputs), node block by node block.
template <int D>
void Elimination<D>::add_variation(int c, const Vec<D>& g_s, SparseMatrix& K_r) const {
  if (groups_[c].count == 2) {
    add_pair_variation(c, g_s, K_r);
    return;
  }
  const Constraint<D>& k = (*constraints_)[groups_[c].constraint[0]];
  const Kernel in = kernel_input(k, u_);
  if (k.kind == Kind::stick) {
    constexpr int N = D * D;  // inputs and outputs: the facet's nodes
    const zero_work::Facet<D, double> xm = in.x.template rightCols<D>(), dxm = in.dx.template rightCols<D>();
    const auto A = zero_work::stick_test<D, AD<N>>(variables<N>(xm), variables<N>(dxm), in.xm_n, in.offset, k.xi,
                                                   k.gap);
    const Eigen::Matrix<AD<N>, N, 1> rho = A.transpose() * g_s.template cast<AD<N>>();
    Eigen::Matrix<double, N, N> G;
    for (int o = 0; o < N; ++o) G.row(o) = rho(o).derivatives().transpose();
    for (int a = 0; a < D; ++a)
      for (int b = 0; b < D; ++b)
        add_variation_block(c, k.master[a], false, k.master[b], G.template block<D, D>(a * D, b * D), K_r);
    return;
  }
  constexpr int N = D * (D + 1);  // inputs: the slave, then the facet's nodes
  const auto t = zero_work::frictionless_test<D, AD<N>>(variables<N>(in.x), variables<N>(in.dx), !k.push, k.friction,
                                                        k.slip_scale);
  const Eigen::Matrix<AD<N>, D, 1> gs = g_s.template cast<AD<N>>();
  Eigen::Matrix<double, N, N> G = Eigen::Matrix<double, N, N>::Zero();  // outputs: the slips (row D−1 zero), the facet
  for (int j = 0; j < D - 1; ++j) G.row(j) = t.slip.col(j).dot(gs).derivatives().transpose();
  for (int o = 0; o < D * D; ++o) G.row(D + o) = t.master.col(o).dot(gs).derivatives().transpose();
  auto node = [&](int a) { return a == 0 ? k.slave : k.master[a - 1]; };
  for (int a = 0; a <= D; ++a)
    for (int b = 0; b <= D; ++b)
      add_variation_block(c, node(a), a == 0, node(b), G.template block<D, D>(a * D, b * D), K_r);
}

// The same for a slave holding two constraints: inputs and outputs the
// slave, facet 1's nodes and facet 2's.
template <int D>
void Elimination<D>::add_pair_variation(int c, const Vec<D>& g_s, SparseMatrix& K_r) const {
  const Group& g = groups_[c];
  const PairKernel in = pair_input(g, u_);
  constexpr int N = D * (2 * D + 1);
  const auto t = zero_work::pair_frictionless_test<D, AD<N>>(variables<N>(in.x), variables<N>(in.dx));
  const Eigen::Matrix<AD<N>, D, 1> gs = g_s.template cast<AD<N>>();
  Eigen::Matrix<double, N, N> G = Eigen::Matrix<double, N, N>::Zero();  // outputs: the slip (rows 1…D−1 zero), the facets
  if constexpr (D == 3) G.row(0) = t.slip.dot(gs).derivatives().transpose();
  for (int o = 0; o < 2 * D * D; ++o) G.row(D + o) = t.master.col(o).dot(gs).derivatives().transpose();
  auto node = [&](int a) {
    return a == 0 ? g.slave : (*constraints_)[g.constraint[(a - 1) / D]].master[(a - 1) % D];
  };
  for (int a = 0; a <= 2 * D; ++a)
    for (int b = 0; b <= 2 * D; ++b)
      add_variation_block(c, node(a), a == 0, node(b), G.template block<D, D>(a * D, b * D), K_r);
}

template <int D>
Eigen::MatrixXd Elimination<D>::force_variation(std::size_t c, const Vec<D>& f) const {
  constexpr int N = D * (D + 1);  // inputs and outputs: the slave, then the facet's nodes
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(N, N);
  if (groups_[c].count == 2) return G;
  const Constraint<D>& k = (*constraints_)[groups_[c].constraint[0]];
  const Kernel in = kernel_input(k, u_);
  if (k.kind == Kind::stick) {
    constexpr int M = D * D;
    const zero_work::Facet<D, double> xm = in.x.template rightCols<D>(), dxm = in.dx.template rightCols<D>();
    const auto A = zero_work::stick_test<D, AD<M>>(variables<M>(xm), variables<M>(dxm), in.xm_n, in.offset, k.xi,
                                                   k.gap);
    const Eigen::Matrix<AD<M>, M, 1> out = -(A.transpose() * f.template cast<AD<M>>());
    for (int o = 0; o < M; ++o) G.block(D + o, D, 1, M) = out(o).derivatives().transpose();
    return G;
  }
  const auto t = zero_work::frictionless_test<D, AD<N>>(variables<N>(in.x), variables<N>(in.dx), !k.push, k.friction,
                                                        k.slip_scale);
  Eigen::Matrix<AD<N>, D, 1> nu;
  if constexpr (D == 2)
    nu << -t.slip(1, 0), t.slip(0, 0);
  else
    nu = t.slip.col(0).cross(t.slip.col(1));
  nu /= sqrt(nu.squaredNorm());
  Vec<D> value;
  for (int i = 0; i < D; ++i) value(i) = nu(i).value();
  const Eigen::Matrix<AD<N>, D, 1> force = nu * AD<N>(f.dot(value));
  for (int i = 0; i < D; ++i) G.row(i) = force(i).derivatives().transpose();
  for (int o = 0; o < D * D; ++o) G.row(D + o) = (-t.master.col(o).dot(force)).derivatives().transpose();
  return G;
}

template <int D>
bool Elimination<D>::reduce_tangent(const SparseMatrix& K, const Eigen::VectorXd& g, SparseMatrix& K_r) const {
  const bool new_pattern = reduction_->reduce(K, slave_rows(), K_r);  // Wᵀ K T (43), (58)
  // (44), (59): β = tr(K_ss)/D on the dummy slots.
  // A frictionless slave has D − (its constraints) slips; stick none.
  for (std::size_t c = 0; c < groups_.size(); ++c) {
    const int s = slaves_[c];
    double trace = 0.0;
    for (int i = 0; i < D; ++i) trace += K.coeff(s * D + i, s * D + i);
    Mat<D> beta = Mat<D>::Zero();
    const Group& group = groups_[c];
    const bool stick = (*constraints_)[group.constraint[0]].kind == Kind::stick;
    for (int j = stick ? 0 : D - group.count; j < D; ++j) beta(j, j) = trace / D;
    reduction_->add(static_cast<int>(c), s, s, beta, K_r);
  }
  if (!pairs_ || u_.size() != g.size()) return new_pattern;
  // The residual each slave passes on to its masters' rows: its own plus
  // what chained slaves passed on to it (a chain's slave is a master node
  // of another constraint), accumulated from the outer end of the chains.
  Eigen::VectorXd passed = g;
  for (auto c = order_.rbegin(); c != order_.rend(); ++c) {
    const Coefficients& l = test_[*c];
    const Vec<D> gs = passed.template segment<D>(slaves_[*c] * D);
    for (std::size_t a = 0; a < l.nodes.size(); ++a)
      if (slave_of_[l.nodes[a]] >= 0)
        passed.template segment<D>(l.nodes[a] * D) += l.master.middleCols(a * D, D).transpose() * gs;
  }
  for (std::size_t c = 0; c < groups_.size(); ++c)
    add_variation(static_cast<int>(c), passed.template segment<D>(slaves_[c] * D), K_r);
  return new_pattern;
}

template <int D>
void Elimination<D>::expand(const Eigen::VectorXd& q, Eigen::VectorXd& du) const {
  std::vector<Vec<D>> du_s(slaves_.size(), Vec<D>::Zero());  // Δu_s = Σ_b T_sb q_b
  for (std::size_t c = 0; c < slaves_.size(); ++c)
    for (std::size_t b = 0; b < trial_rows_[c].nodes.size(); ++b)
      du_s[c] += trial_rows_[c].blocks[b] * q.template segment<D>(trial_rows_[c].nodes[b] * D);
  du = q;
  for (std::size_t c = 0; c < slaves_.size(); ++c) du.template segment<D>(slaves_[c] * D) = du_s[c];
}

// The frictionless slave back to its held gap γ on its facet, the facet
// the slave's end position projects on, which is also the facet its force
// acts on: then a·Δx, the work the zero-work correction has to absorb, is
// of third order in the step except on the step a slave crosses an edge
// (contact/elimination/zero_work.hpp). The facet may be switched at most kMaxSwitches
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
Match<D> Elimination<D>::settle(const Constraint<D>& k, const Vec<D>& xs, int facet, const Positions<D>& x,
                                int switches) const {
  const ContactSurface& master = (*pairs_)[k.pair].master;
  const double tol = (*pairs_)[k.pair].search.inside_tolerance;
  // A neighbour must be lower by more than round-off: on a flat surface
  // (or at a vertex the slave sits on) all facets give the same gap, and a
  // choice made by round-off would hop between iterations.
  const double lower = (*pairs_)[k.pair].search.penetration_tolerance;
  Match<D> best{facet, project<D>(xs, facet_nodes<D>(master, facet, x))};
  if (switches >= kMaxSwitches) return best;
  // Never onto a facet that faces the way the slave does (find_master).
  const ContactSurface& slave = (*pairs_)[k.pair].slave;
  const Vec<D> facing = node_normal<D>(slave, static_cast<std::size_t>(slave.local_node(k.slave)), x);
  best = follow<D>(xs, best, master, x, tol, &facing);
  for (int side = 0; side < D; ++side) {
    const int next = master.facet_neighbours(side, best.facet);
    if (next < 0) continue;
    const Projection<D> p = project<D>(xs, facet_nodes<D>(master, next, x));
    if (p.inside(tol) && p.gap < best.projection.gap - lower && !(p.normal.dot(facing) > 0.0)) best = Match<D>{next, p};
  }
  return best;
}

template <int D>
void Elimination<D>::set_mid_point(Constraint<D>& k, int facet, const Positions<D>& x_mid) const {
  const ContactSurface& master = (*pairs_)[k.pair].master;
  const Projection<D> mid = project<D>(x_mid.col(k.slave), facet_nodes<D>(master, facet, x_mid));  // (60)–(64), 2
  k.facet = facet;
  for (int a = 0; a < D; ++a) k.master[a] = master.facets(a, facet);
  k.xi = mid.xi;
  k.normal = mid.normal;
  k.tangents = mid.tangents;
}

template <int D>
void Elimination<D>::place_frictionless(Constraint<D>& k, Positions<D>& x, Positions<D>& x_mid, int& switches) const {
  Vec<D> xs = x.col(k.slave);
  int facet = k.facet;
  const Vec<D> xs_n = X_.col(k.slave) + u_n_.template segment<D>(k.slave * D);
  if (k.rate) {  // (60)–(64): the slave along n_{n+½} until (48) holds
    const Match<D> best = settle(k, xs, facet, x, switches);
    if (best.facet != facet) ++switches;
    x_mid.col(k.slave) = 0.5 * (xs + xs_n);
    set_mid_point(k, best.facet, x_mid);
    Vec<D> relative = xs - xs_n;
    const Vec<D> N = facet_shape<D>(k.xi);
    for (int b = 0; b < D; ++b)
      relative -= N(b) * (x.col(k.master[b]) - X_.col(k.master[b]) - u_n_.template segment<D>(k.master[b] * D));
    xs -= relative.dot(k.normal) * k.normal;  // flat facet: ξ_{n+½} and n_{n+½} unchanged
    x.col(k.slave) = xs;
    x_mid.col(k.slave) = 0.5 * (xs + xs_n);
    set_mid_point(k, best.facet, x_mid);
    return;
  }
  for (int pass = 0; pass < 4; ++pass) {
    const Match<D> best = settle(k, xs, facet, x, switches);
    xs -= (best.projection.gap - k.gap) * best.projection.normal;
    if (best.facet == facet) break;
    facet = best.facet;
    ++switches;
  }
  x.col(k.slave) = xs;
  x_mid.col(k.slave) = 0.5 * (xs + xs_n);
  set_mid_point(k, facet, x_mid);
}

// Both gaps at once: the slave moves by −C e, e the two gaps' errors and
// C = [n_1 n_2] G⁻¹, the least move that holds both (exact for flat
// facets); the facets are settled as for one constraint, except that the
// two of a crease pair (one master surface) never meet on one facet or on
// two within kCreaseSine of coplanar, where G is singular: such a
// constraint keeps its facet, its plane extended.
template <int D>
void Elimination<D>::place_pair(const Group& g, Positions<D>& x, Positions<D>& x_mid) {
  std::array<Constraint<D>*, 2> k{&(*constraints_)[g.constraint[0]], &(*constraints_)[g.constraint[1]]};
  Vec<D> xs = x.col(g.slave);
  std::array<int, 2> facet{k[0]->facet, k[1]->facet};
  const bool crease = k[0]->pair == k[1]->pair;
  const ContactSurface& master = (*pairs_)[k[0]->pair].master;
  for (int pass = 0; pass < 4; ++pass) {
    Eigen::Matrix<double, D, 2> n;
    Eigen::Vector2d e;
    bool same = true;
    std::array<int, 2> next{};
    for (int j = 0; j < 2; ++j) {
      Match<D> best = settle(*k[j], xs, facet[j], x, switches_[g.constraint[j]]);
      if (crease && best.facet != facet[j]) {
        const int other = j == 0 ? facet[1] : next[0];
        const Vec<D> m = facet_normal<D>(facet_nodes<D>(master, other, x));
        const double cosine = best.projection.normal.dot(m);
        if (best.facet == other || 1.0 - cosine * cosine < kCreaseSine * kCreaseSine)
          best = Match<D>{facet[j], project<D>(xs, facet_nodes<D>(master, facet[j], x))};
      }
      n.col(j) = best.projection.normal;
      e(j) = best.projection.gap - k[j]->gap;
      next[j] = best.facet;
      same = same && best.facet == facet[j];
    }
    xs -= n * (n.transpose() * n).ldlt().solve(e);
    if (same) break;
    for (int j = 0; j < 2; ++j)
      if (next[j] != facet[j]) facet[j] = next[j], ++switches_[g.constraint[j]];
  }
  x.col(g.slave) = xs;
  x_mid.col(g.slave) = 0.5 * (xs + (X_.col(g.slave) + u_n_.template segment<D>(g.slave * D)));
  for (int j = 0; j < 2; ++j) set_mid_point(*k[j], facet[j], x_mid);
}

template <int D>
void Elimination<D>::enforce(Eigen::VectorXd& u) {
  if (!pairs_) throw Error("Elimination::enforce needs the step's geometry (the geometry constructor)");
  Positions<D> x = positions(u), x_mid = 0.5 * (x + positions(u_n_));
  for (int sweep = 0; sweep < 2; ++sweep) {  // a second sweep settles chains
    for (const Group& g : groups_) {
      if (g.count == 2) {
        place_pair(g, x, x_mid);
        continue;
      }
      const int c = g.constraint[0];
      Constraint<D>& k = (*constraints_)[c];
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
  for (const Constraint<D>& k : *constraints_)
    u.template segment<D>(k.slave * D) = x.col(k.slave) - X_.col(k.slave);
  build(&u);
  if (!switch_to_rate()) return;
  for (const Group& g : groups_) {
    Constraint<D>& k = (*constraints_)[g.constraint[0]];
    if (g.count == 1 && k.rate) place_frictionless(k, x, x_mid, switches_[g.constraint[0]]);
  }
  for (const Constraint<D>& k : *constraints_)
    u.template segment<D>(k.slave * D) = x.col(k.slave) - X_.col(k.slave);
  build(&u);
}

// A held gap asks for a zero-work force direction ā that differs from the
// paper's a by a multiple of the constraint's non-rigid motion w (F2);
// when a·Δx is not small against |w| (a slave held where it hardly moves
// while its facet changes at an edge, or pushed out with little other
// motion), ā turns tangential and Newton cannot balance it. Such a
// constraint takes the paper's (48) for the rest of the step: then
// a·Δx = 0 and ā = a, the force is normal, and E, L, J are conserved as
// in the paper (docs/theory.md, "When the held gap gives way to (48)").
template <int D>
bool Elimination<D>::switch_to_rate() {
  bool any = false;
  for (std::size_t g = 0; g < groups_.size(); ++g) {
    if (groups_[g].count != 1) continue;
    Constraint<D>& k = (*constraints_)[groups_[g].constraint[0]];
    if (k.kind == Kind::frictionless && !k.rate && cosine_[g] < kRateCosine) k.rate = any = true;
  }
  return any;
}

template <int D>
void Elimination<D>::save(std::optional<Saved>& saved) const {
  if (!saved) {
    saved.emplace(Saved{*this, *constraints_});
    return;
  }
  saved->maps = *this;  // assignments reuse the storage of the last save
  saved->constraints = *constraints_;
}

template <int D>
void Elimination<D>::restore(const Saved& saved) {
  if (saved.constraints.size() != constraints_->size())
    throw Error("Elimination::restore: the saved constraints are another active set");
  std::vector<Constraint<D>>* constraints = constraints_;
  *this = saved.maps;
  constraints_ = constraints;
  *constraints_ = saved.constraints;
}

template <int D>
void Elimination<D>::update(const Eigen::VectorXd& q, Eigen::VectorXd& u) {
  std::vector<Vec<D>> u_s(slaves_.size());  // (49), (60): u += T q, T the identity but on the slaves
  for (std::size_t c = 0; c < slaves_.size(); ++c) {
    Vec<D> du = Vec<D>::Zero();
    for (std::size_t b = 0; b < trial_rows_[c].nodes.size(); ++b)
      du += trial_rows_[c].blocks[b] * q.template segment<D>(trial_rows_[c].nodes[b] * D);
    u_s[c] = u.template segment<D>(slaves_[c] * D) + du;
  }
  u += q;
  for (std::size_t c = 0; c < slaves_.size(); ++c) u.template segment<D>(slaves_[c] * D) = u_s[c];
  enforce(u);
}

}  // namespace conserve::contact
