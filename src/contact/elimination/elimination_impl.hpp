// The definitions of Elimination<D>, included by elimination_2d.cpp and
// elimination_3d.cpp only: each instantiates one dimension, so the two
// halves of its automatic-differentiation code compile side by side.
#pragma once

#include "contact/elimination/elimination.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <map>
#include <optional>
#include <unordered_map>

#include <unsupported/Eigen/AutoDiff>

#include "contact/elimination/activation.hpp"
#include "contact/elimination/zero_work.hpp"
#include "core/error.hpp"

namespace conserve::contact {
namespace {

/// The smallest pivot of a cycle's coupling (or of its placement's
/// Jacobian), relative to the largest, below which the cycle counts as
/// singular: its rows would amplify the motions by more than its inverse.
constexpr double kRedundantPivot = 1e-10;

/// A cycle whose coupling I − C_KK is singular (RowBuilder): its groups.
struct SingularCycle {
  std::vector<int> members;
};

/// Composes every slave's rows of a map, in node blocks, from the
/// constraints' local coefficients. A chain (a slave's master node is
/// another's slave) is composed by substitution; a cycle (two passes or
/// self-contact: slaves of each surface on the other's facets) is a
/// strongly connected component K of the groups' dependencies, solved
/// together: Δx_K = C_KK Δx_K + C_K,ext Δx_ext + slips, so the rows are
/// (I − C_KK)⁻¹ times the rest. A component whose I − C_KK is singular
/// (the slaves on each other's nodes: the same constraint twice) is
/// refused as redundant. Structural: every node the coefficients name is
/// kept, with its block even when that is zero, so that the rows' nodes
/// (and the reduced tangent's pattern) depend on the constraints' nodes
/// only.
template <int D>
class RowBuilder {
 public:
  using Coefficients = typename Elimination<D>::Coefficients;
  using Component = EliminationComponent;

  /// `slaves`: per group, its slave node (distinct); `local`: per group,
  /// its coefficients.
  RowBuilder(int num_nodes, const std::vector<int>& slaves, std::vector<const Coefficients*> local)
      : slaves_(slaves), local_(std::move(local)), of_node_(num_nodes, -1), rows_(slaves.size()) {
    for (std::size_t c = 0; c < slaves.size(); ++c) of_node_[slaves[c]] = static_cast<int>(c);
    index_.assign(slaves.size(), -1);
    low_.assign(slaves.size(), 0);
    on_stack_.assign(slaves.size(), 0);
    for (std::size_t c = 0; c < slaves.size(); ++c)
      if (index_[c] < 0) visit(static_cast<int>(c));
  }

  /// The D rows of group c's slave.
  const BlockRow<D>& rows(int c) const { return rows_[c]; }
  /// The components, each after those its members' master nodes belong to.
  [[nodiscard]] const std::vector<Component>& components() const { return components_; }

 private:
  static Mat<D>& block(std::map<int, Mat<D>>& out, int node) {
    return out.try_emplace(node, Mat<D>::Zero()).first->second;
  }

  // Tarjan's strongly connected components: a component is completed
  // after every component its members depend on.
  void visit(int c) {
    index_[c] = low_[c] = next_index_++;
    stack_.push_back(c);
    on_stack_[c] = 1;
    for (const int node : local_[c]->nodes) {
      const int d = of_node_[node];
      if (d < 0) continue;
      if (index_[d] < 0) {
        visit(d);
        low_[c] = std::min(low_[c], low_[d]);
      } else if (on_stack_[d]) {
        low_[c] = std::min(low_[c], index_[d]);
      }
    }
    if (low_[c] != index_[c]) return;
    Component k;
    for (int d = -1; d != c;) {
      d = stack_.back();
      stack_.pop_back();
      on_stack_[d] = 0;
      k.members.push_back(d);
    }
    std::reverse(k.members.begin(), k.members.end());
    compose(k);
    components_.push_back(std::move(k));
  }

  /// Rows of a component's members from their coefficients: nodes outside
  /// the component are free or completed slaves (substituted); members'
  /// own slips sit in their own node blocks.
  void compose(Component& k) {
    const auto m = static_cast<int>(k.members.size());
    std::map<int, int> member;  // slave node → position in the component
    for (int i = 0; i < m; ++i) member[slaves_[k.members[i]]] = i;
    std::vector<std::map<int, Mat<D>>> outside(static_cast<std::size_t>(m));
    Eigen::MatrixXd coupling = Eigen::MatrixXd::Identity(D * m, D * m);
    bool cycle = m > 1;
    for (int i = 0; i < m; ++i) {
      const int c = k.members[i];
      const Coefficients& l = *local_[c];
      auto& out = outside[i];
      for (std::size_t a = 0; a < l.nodes.size(); ++a) {
        const int node = l.nodes[a];
        const auto C = l.master.middleCols(a * D, D);
        if (const auto j = member.find(node); j != member.end()) {
          coupling.block(i * D, j->second * D, D, D) -= C;
          cycle = true;
          continue;
        }
        const int d = of_node_[node];
        if (d < 0) {
          block(out, node) += C;
          continue;
        }
        const BlockRow<D>& sub = rows_[d];
        for (std::size_t b = 0; b < sub.nodes.size(); ++b) block(out, sub.nodes[b]) += C * sub.blocks[b];
      }
      // (49): slip unknowns in the slave's first slots (zero for stick)
      block(out, slaves_[c]).template leftCols<D - 1>() += l.slip;
    }
    if (!cycle) {
      store(k.members[0], outside[0]);
      return;
    }
    // The right-hand side's columns: every node some member's rest names.
    std::map<int, int> column;
    for (const auto& out : outside)
      for (const auto& entry : out) column.try_emplace(entry.first, 0);
    int next = 0;
    for (auto& entry : column) entry.second = next++;
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(D * m, D * next);
    for (int i = 0; i < m; ++i)
      for (const auto& [node, b] : outside[i]) rhs.block(i * D, column[node] * D, D, D) = b;
    Eigen::FullPivLU<Eigen::MatrixXd> lu(coupling);
    // Round-off of the coefficients (O(1)) leaves a pivot of a singular
    // coupling near 1e-16; one of a genuine cycle is at least the part of
    // the slaves' weights outside it.
    lu.setThreshold(kRedundantPivot);
    if (lu.rank() < D * m) throw SingularCycle{k.members};
    const Eigen::MatrixXd solved = lu.solve(rhs);
    for (int i = 0; i < m; ++i) {
      std::map<int, Mat<D>> out;
      for (const auto& [node, j] : column) out[node] = solved.block(i * D, j * D, D, D);
      store(k.members[i], out);
    }
    k.coupling = std::move(coupling);
    const Eigen::VectorXd u = lu.matrixLU().diagonal().cwiseAbs();
    k.pivot = u.minCoeff() / u.maxCoeff();
  }

  void store(int c, const std::map<int, Mat<D>>& out) {
    BlockRow<D>& row = rows_[c];
    for (const auto& [node, b] : out) {
      row.nodes.push_back(node);
      row.blocks.push_back(b);
    }
  }

  const std::vector<int>& slaves_;
  std::vector<const Coefficients*> local_;
  std::vector<int> of_node_;
  std::vector<int> index_, low_;
  std::vector<char> on_stack_;
  std::vector<int> stack_;
  int next_index_ = 0;
  std::vector<BlockRow<D>> rows_;
  std::vector<Component> components_;
};

/// N ⊗ 1 over a facet's nodes (N their shape values): D × D·|N|.
template <int D>
Eigen::MatrixXd shape_block(const FacetWeights<D>& N) {
  Eigen::MatrixXd C = Eigen::MatrixXd::Zero(D, D * N.size());
  for (Eigen::Index b = 0; b < N.size(); ++b) C.middleCols(b * D, D) = N(b) * Mat<D>::Identity();
  return C;
}

template <int N>
using AD = Eigen::AutoDiffScalar<Eigen::Matrix<double, N, 1>>;

/// The unit direction a frictionless slave's slips miss (their span's
/// normal): the one direction its coefficients on the facet's nodes act
/// in. Projecting them on it (ν νᵀ C) keeps the constraint's motions (the
/// slips take the rest) and couples slaves that are each other's master
/// nodes by their normal motion only: the tangential parts would let a
/// cycle of slaves whose facets' nodes are all its own slide together,
/// and its rows would be singular.
template <int D, class S>
Eigen::Matrix<S, D, 1> missed_direction(const Eigen::Matrix<S, D, D - 1>& slip) {
  Eigen::Matrix<S, D, 1> nu;
  if constexpr (D == 2)
    nu << -slip(1, 0), slip(0, 0);
  else
    nu = slip.col(0).cross(slip.col(1));
  return nu / sqrt(nu.squaredNorm());
}

/// Seeds x as the AD variables of the end positions: entry k of the
/// flattened matrix has derivative e_k. The same seeding serves for the
/// displacements dx = x − x_n, whose derivatives are those of x.
template <int N, int R, int C>
Eigen::Matrix<AD<N>, R, C> variables(const Eigen::Matrix<double, R, C>& x) {
  Eigen::Matrix<AD<N>, R, C> y;
  for (int k = 0; k < R * C; ++k) y(k) = AD<N>(x(k), N, k);
  return y;
}

/// A driven slave's constraint held by node b of its facet (kernel column
/// 1 + b): the force directions the zero-work kernel gives its nodes, c_s =
/// ν (the slave) and c_j = −T_jᵀ ν (facet node j), the columns of `c` in
/// kernel order; and the directions `slip` b's residual is kept in, an
/// orthonormal basis of the plane normal to c_b (from the kernel's slips,
/// so that they vary smoothly with the positions).
template <int D, class S>
void driven_forces(const zero_work::TestColumns<D, S>& t, int b, Eigen::Matrix<S, D, D + 1>& c,
                   Eigen::Matrix<S, D, D - 1>& slip) {
  const Eigen::Matrix<S, D, 1> nu = missed_direction<D, S>(t.slip);
  c.col(0) = nu;
  for (int j = 0; j < D; ++j) c.col(1 + j) = -(t.master.middleCols(j * D, D).transpose() * nu);
  const Eigen::Matrix<S, D, 1> f = c.col(1 + b) / sqrt(c.col(1 + b).squaredNorm());
  for (int k = 0; k < D - 1; ++k) {
    Eigen::Matrix<S, D, 1> v = t.slip.col(k) - f * f.dot(t.slip.col(k));
    for (int i = 0; i < k; ++i) v -= slip.col(i) * slip.col(i).dot(v);
    slip.col(k) = v / sqrt(v.squaredNorm());
  }
}

/// How far beyond its border (isoparametric) a slave stays on its curved
/// facet (Elimination::settle).
constexpr double kCurvedBorder = 1e-3;

/// The smallest weight, relative to the largest of its facet's nodes, of
/// the node that holds a driven slave's constraint: below it the
/// constraint repeats the one of the node it is at, and is left out.
constexpr double kHolderWeight = 1e-2;

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
template <int NF>
typename Elimination<D>::template KernelOf<NF> Elimination<D>::kernel_input(const Constraint<D>& k,
                                                                           const Eigen::VectorXd& u) const {
  if (k.master.size() != NF)
    throw Error(fmt::format("slave {}'s facet has {} nodes, not {}", k.slave, k.master.size(), NF));
  KernelOf<NF> in;
  auto put = [&](int column, int node) {
    in.x.col(column) = X_.col(node) + u.template segment<D>(node * D);
    in.dx.col(column) = u.template segment<D>(node * D) - u_n_.template segment<D>(node * D);
  };
  put(0, k.slave);
  for (int b = 0; b < NF; ++b) put(b + 1, k.master[b]);
  in.xm_n = in.x.template rightCols<NF>() - in.dx.template rightCols<NF>();
  if constexpr (NF == D)
    if (k.kind == Kind::stick)
      in.offset = (X_.col(k.slave) + u_n_.template segment<D>(k.slave * D)) -
                  zero_work::stick_position<D, double>(in.xm_n, k.xi, k.gap);
  return in;
}

// On a facet of NF nodes, linear or curved: T = (N_b n nᵀ, τ) at the end
// positions (the gap's variation n·(δx_s − Σ N_b δx_b) holds on either),
// W from ā (zero_work::frictionless_test, its mid-point projection on the
// curved facet for NF > D).
template <int D>
template <int NF>
typename Elimination<D>::Local Elimination<D>::local_frictionless(const Constraint<D>& k,
                                                                  const Eigen::VectorXd& u) const {
  Local l;
  const KernelOf<NF> in = kernel_input<NF>(k, u);
  l.test.nodes.assign(k.master.begin(), k.master.end());
  l.trial.nodes = l.test.nodes;
  Projection<D> p;
  if constexpr (NF == D)
    p = project<D>(in.x.col(0), in.x.template rightCols<D>());
  else
    p = project_curved<D>(in.x.col(0), in.x.template rightCols<NF>()).projection;
  l.trial.master = p.normal * (p.normal.transpose() * shape_block<D>(facet_weights<D>(NF, p.xi)));
  l.trial.slip = p.tangents;
  const auto t = zero_work::frictionless_test<D, double, NF>(in.x, in.dx, !k.push, k.friction, k.slip_scale);
  const Vec<D> nu = missed_direction<D, double>(t.slip);
  l.test.master = nu * (nu.transpose() * t.master);
  l.test.slip = t.slip;
  l.cosine = t.cosine;
  return l;
}

template <int D>
typename Elimination<D>::Local Elimination<D>::local(const Constraint<D>& k, const Eigen::VectorXd& u) const {
  if (k.master.size() != D) {
    if (k.kind != Kind::frictionless || k.eliminated >= 0)
      throw Error(fmt::format("slave {}: only frictionless contact on a quadratic facet", k.slave));
    return local_frictionless<kMaxFacetNodes<D>>(k, u);
  }
  if (k.kind == Kind::frictionless && k.eliminated < 0) return local_frictionless<D>(k, u);
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
  // A driven slave's, held by facet node b: the same force pair, its
  // remainder passed on from b's residual along c_b, W_bx = −ĉ c_xᵀ/|c_b|.
  const auto t = zero_work::frictionless_test<D, double>(in.x, in.dx, !k.push, k.friction, k.slip_scale);
  const int b = facet_index(k, k.eliminated);
  l.trial = driven_trial(k, positions(u));
  Eigen::Matrix<double, D, D + 1> c;
  driven_forces<D, double>(t, b, c, l.test.slip);
  const double size = c.col(1 + b).norm();
  const Vec<D> f = c.col(1 + b) / size;
  l.test.nodes = l.trial.nodes;
  l.test.master.resize(D, D * D);
  for (int a = 0, col = 0; a <= D; ++a)
    if (a != 1 + b) l.test.master.middleCols(D * col++, D) = -f * c.col(a).transpose() / size;
  l.cosine = t.cosine;
  return l;
}

// A slave node holds one constraint, or two frictionless ones: of
// different pairs whose facets are not parallel, or of one pair on two
// facets (a crease pair) (the active set's rules, ActiveSet::can_hold,
// ActiveSet::crease); anything else is refused. A second pass's
// constraint that repeats another (its slave and that one's on each
// other's nodes, repeats()) is left out of the maps from this iterate to
// the solve's end (Constraint::repeat): the two say one thing, and the
// first pass's holds it (the active set releases it once the solve ends,
// ActiveSet::update).
template <int D>
void Elimination<D>::suspend_repeats(const Eigen::VectorXd* u) {
  suspended_.assign(constraints_->size(), 0);
  if (!pairs_ || !u) return;
  if (std::none_of(constraints_->begin(), constraints_->end(),
                   [&](const Constraint<D>& k) { return (*pairs_)[k.pair].yields(); }))
    return;  // one pass: nothing may give way
  const Positions<D> x = positions(*u);
  std::unordered_multimap<int, std::size_t> by_slave;
  for (std::size_t c = 0; c < constraints_->size(); ++c) {
    by_slave.emplace((*constraints_)[c].slave, c);
    suspended_[c] = (*constraints_)[c].repeat;
  }
  for (std::size_t c = 0; c < constraints_->size(); ++c) {
    Constraint<D>& k = (*constraints_)[c];
    if (!(*pairs_)[k.pair].yields() || suspended_[c]) continue;
    for (const int m : k.master)
      for (auto [it, end] = by_slave.equal_range(m); it != end; ++it) {
        const Constraint<D>& other = (*constraints_)[it->second];
        if (!suspended_[it->second] && gives_way(k, other, *pairs_) && repeats(k, other, x))
          suspended_[c] = 1, k.repeat = true;
      }
  }
}

// A driven slave (ContactPair::slave_driven) has no unknowns; its
// constraint is held by the node of its facet with the largest weight at
// the slave's projection among those that hold nothing else and have no
// prescribed dof (ties: the lower node), chosen after every other group.
template <int D>
int Elimination<D>::holder(const Constraint<D>& k, const Xi<D>& xi, int group) const {
  const std::vector<int>& fixed = (*pairs_)[k.pair].fixed;
  const Vec<D> N = facet_shape<D>(xi);
  int best = -1;
  for (int a = 0; a < D; ++a) {
    const int m = k.master[a];
    if ((slave_of_[m] >= 0 && slave_of_[m] != group) || std::binary_search(fixed.begin(), fixed.end(), m)) continue;
    if (best < 0 || N(a) > N(best) || (N(a) == N(best) && m < k.master[best])) best = a;
  }
  if (best < 0 || !(N(best) >= kHolderWeight * N.maxCoeff())) return -1;
  return k.master[best];
}

template <int D>
int Elimination<D>::facet_index(const Constraint<D>& k, int node) {
  for (int a = 0; a < k.master.size(); ++a)
    if (k.master[a] == node) return a;
  throw Error(fmt::format("node {} is not on the facet of slave {}'s constraint", node, k.slave));
}

// The trial map of a driven slave's constraint held by node b: b moves
// along n so that the gap n·(x_s − Σ N_j x_j) stays (to first order, exact
// for a flat facet), δx_b = n nᵀ(δx_s − Σ_{j≠b} N_j δx_j)/N_b + τ δξ; its
// nodes the slave, then the facet's other nodes in order.
template <int D>
typename Elimination<D>::Coefficients Elimination<D>::driven_trial(const Constraint<D>& k,
                                                                   const Positions<D>& x) const {
  const int b = facet_index(k, k.eliminated);
  Vec<D> n = k.normal;
  Vec<D> N = facet_shape<D>(k.xi);
  Tangents<D> tangents = k.tangents;
  if (pairs_) {
    const Projection<D> p = project<D>(x.col(k.slave), facet_nodes<D>((*pairs_)[k.pair].master, k.facet, x));
    n = p.normal;
    N = facet_shape<D>(p.xi);
    tangents = p.tangents;
  }
  Coefficients l;
  l.nodes.push_back(k.slave);
  l.master.resize(D, D * D);
  const Mat<D> nn = n * n.transpose() / N(b);
  l.master.leftCols(D) = nn;
  for (int a = 0; a < D; ++a)
    if (a != b) {
      l.master.middleCols(D * static_cast<Eigen::Index>(l.nodes.size()), D) = -N(a) * nn;
      l.nodes.push_back(k.master[a]);
    }
  l.slip = tangents;
  return l;
}

template <int D>
void Elimination<D>::make_groups(const Eigen::VectorXd* u) {
  groups_.clear();
  slave_of_.assign(num_nodes_, -1);
  std::vector<std::size_t> driven;
  for (std::size_t c = 0; c < constraints_->size(); ++c) {
    if (suspended_[c]) continue;
    Constraint<D>& k = (*constraints_)[c];
    if (pairs_ && (*pairs_)[k.pair].slave_driven()) {
      driven.push_back(c);
      continue;
    }
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
  std::optional<Positions<D>> x;
  if (u && !driven.empty()) x = positions(*u);
  for (const std::size_t c : driven) {
    Constraint<D>& k = (*constraints_)[c];
    const Xi<D> xi =
        x ? project<D>(x->col(k.slave), facet_nodes<D>((*pairs_)[k.pair].master, k.facet, *x)).xi : k.xi;
    k.eliminated = holder(k, xi, -1);
    if (k.eliminated < 0) {
      suspended_[c] = 1;
      continue;
    }
    slave_of_[k.eliminated] = static_cast<int>(groups_.size());
    groups_.push_back(Group{k.eliminated, 1, {static_cast<int>(c), -1}});
  }
}

template <int D>
template <int NF>
typename Elimination<D>::template PairKernelOf<NF> Elimination<D>::pair_input(const Group& g,
                                                                              const Eigen::VectorXd& u) const {
  PairKernelOf<NF> in;
  auto put = [&](int column, int node) {
    in.x.col(column) = X_.col(node) + u.template segment<D>(node * D);
    in.dx.col(column) = u.template segment<D>(node * D) - u_n_.template segment<D>(node * D);
  };
  put(0, g.slave);
  for (int k = 0; k < 2; ++k) {
    const Constraint<D>& c = (*constraints_)[g.constraint[k]];
    if (c.master.size() != NF)
      throw Error(fmt::format("slave {}'s facet has {} nodes, not {}", g.slave, c.master.size(), NF));
    for (int b = 0; b < NF; ++b) put(1 + k * NF + b, c.master[b]);
  }
  return in;
}

// The trial map of a slave holding two gaps: to first order, gap k moves
// by n_kᵀ(Δx_s − N_k Δx_mk) (exact for a linear or curved facet, whatever
// the gap, since x_s − x(ξ_k) ∥ n_k ⊥ x_ξ(ξ_k)), so Δx_s = C [n_1ᵀ N_1
// Δx_m1; n_2ᵀ N_2 Δx_m2] + a Δξ with C = [n_1 n_2] G⁻¹ holds both,
// a = n_1 × n_2 / |…| the free slip (3D).
template <int D>
typename Elimination<D>::Local Elimination<D>::local_pair(const Group& g, const Eigen::VectorXd* u) const {
  if ((*constraints_)[g.constraint[0]].master.size() == D) return local_pair_of<D>(g, u);
  return local_pair_of<kMaxFacetNodes<D>>(g, u);
}

template <int D>
template <int NF>
typename Elimination<D>::Local Elimination<D>::local_pair_of(const Group& g, const Eigen::VectorXd* u) const {
  std::array<Vec<D>, 2> normal;
  std::array<Eigen::Matrix<double, NF, 1>, 2> shape;
  std::optional<PairKernelOf<NF>> in;
  if (u) in = pair_input<NF>(g, *u);
  for (int k = 0; k < 2; ++k) {
    const Constraint<D>& c = (*constraints_)[g.constraint[k]];
    if (in) {
      Projection<D> p;
      if constexpr (NF == D)
        p = project<D>(in->x.col(0), in->x.template middleCols<D>(1 + k * D));
      else
        p = project_curved<D>(in->x.col(0), in->x.template middleCols<NF>(1 + k * NF)).projection;
      normal[k] = p.normal;
      shape[k] = facet_weights<D>(NF, p.xi);
    } else {
      normal[k] = c.normal;
      shape[k] = facet_weights<D>(NF, c.xi);
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
  l.trial.master.resize(D, 2 * NF * D);
  for (int k = 0; k < 2; ++k)
    for (int b = 0; b < NF; ++b)
      l.trial.master.middleCols((k * NF + b) * D, D) = shape[k](b) * C.col(k) * normal[k].transpose();
  if constexpr (D == 3) l.trial.slip.col(0) = normal[0].cross(normal[1]).normalized();
  l.test.nodes = l.trial.nodes;
  if (!in) {
    l.test.master = l.trial.master;
    l.test.slip = l.trial.slip;
    return l;
  }
  const auto t = zero_work::pair_frictionless_test<D, double, NF>(in->x, in->dx);
  l.test.master = t.master;
  l.test.slip.col(0) = t.slip;
  return l;
}

// A cycle that is singular at this iterate (slaves of both passes on each
// other's nodes, beyond the pairs repeats() finds) leaves its second
// pass's constraints out of the maps, as repeats do; one of the first
// pass alone is refused.
template <int D>
void Elimination<D>::build(const Eigen::VectorXd* u) {
  suspend_repeats(u);
  for (;;) {
    try {
      compose(u);
      return;
    } catch (const SingularCycle& cycle) {
      // The second pass's constraints go; else self-contact's of the
      // largest slave, one at a time.
      int chosen = -1;
      for (const int g : cycle.members)
        for (int j = 0; j < groups_[g].count; ++j) {
          const int c = groups_[g].constraint[j];
          if (!pairs_ || !(*pairs_)[(*constraints_)[c].pair].yields()) continue;
          if (chosen < 0 || gives_way((*constraints_)[c], (*constraints_)[chosen], *pairs_)) chosen = c;
        }
      for (const int g : cycle.members)
        for (int j = 0; j < groups_[g].count; ++j) {
          const int c = groups_[g].constraint[j];
          if (pairs_ && (*pairs_)[(*constraints_)[c].pair].second_pass) suspended_[c] = 1;
        }
      if (chosen >= 0) suspended_[chosen] = 1;
      if (chosen < 0)
        throw SolverError(fmt::format(
            "redundant contact constraints through slave node {}: slaves held on each other's nodes repeat one "
            "constraint",
            groups_[cycle.members.front()].slave));
    }
  }
}

template <int D>
void Elimination<D>::compose(const Eigen::VectorXd* u) {
  make_groups(u);
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
    if (k.eliminated >= 0) {
      l.trial = driven_trial(k, Positions<D>());
      l.test = l.trial;
      locals.push_back(std::move(l));
      continue;
    }
    l.trial.nodes.assign(k.master.begin(), k.master.end());
    l.trial.master = shape_block<D>(facet_weights<D>(k.master.size(), k.xi));
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
  components_ = test_builder.components();
  trial_pivot_.assign(count, 1.0);
  for (const EliminationComponent& k : trial_builder.components())
    for (const int g : k.members) trial_pivot_[static_cast<std::size_t>(g)] = k.pivot;
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
  std::vector<int> columns(t_size);  // slots in c's V table, looked up once
  for (std::size_t j = 0; j < t_size; ++j) columns[j] = reduction_->column_slot(c, t_nodes[j]);
  for (std::size_t i = 0; i < w_size; ++i) {
    const Mat<D> WG = w_blocks[i].transpose() * G;
    const int row = reduction_->row_slot(c, w_nodes[i]);
    for (std::size_t j = 0; j < t_size; ++j) reduction_->add_slot(c, row, columns[j], WG * t_blocks[j], K_r);
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
  if (k.kind == Kind::frictionless && k.eliminated < 0) {
    if (k.master.size() == D)
      add_frictionless_variation<D>(c, k, g_s, K_r);
    else
      add_frictionless_variation<kMaxFacetNodes<D>>(c, k, g_s, K_r);
    return;
  }
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
  auto node = [&](int a) { return a == 0 ? k.slave : k.master[a - 1]; };
  // A driven slave's, held by facet node b: outputs λ c_x at the other nodes, with
  // λ = −ĉ·g_b/|c_b|, and b's slips.
  const int b = facet_index(k, k.eliminated);
  Eigen::Matrix<AD<N>, D, D + 1> cf;
  Eigen::Matrix<AD<N>, D, D - 1> slip;
  driven_forces<D, AD<N>>(t, b, cf, slip);
  const AD<N> lambda = -cf.col(1 + b).dot(gs) / cf.col(1 + b).squaredNorm();
  Eigen::Matrix<double, N, N> G = Eigen::Matrix<double, N, N>::Zero();
  for (int a = 0; a <= D; ++a) {
    if (a == 1 + b) {
      for (int j = 0; j < D - 1; ++j) G.row(a * D + j) = slip.col(j).dot(gs).derivatives().transpose();
      continue;
    }
    for (int i = 0; i < D; ++i) G.row(a * D + i) = (lambda * cf(i, a)).derivatives().transpose();
  }
  for (int a = 0; a <= D; ++a)
    for (int e = 0; e <= D; ++e)
      add_variation_block(c, node(a), a == 1 + b, node(e), G.template block<D, D>(a * D, e * D), K_r);
}

template <int D>
template <int NF>
void Elimination<D>::add_frictionless_variation(int c, const Constraint<D>& k, const Vec<D>& g_s,
                                                SparseMatrix& K_r) const {
  const KernelOf<NF> in = kernel_input<NF>(k, u_);
  constexpr int N = D * (NF + 1);  // inputs: the slave, then the facet's nodes
  const auto t = zero_work::frictionless_test<D, AD<N>, NF>(variables<N>(in.x), variables<N>(in.dx), !k.push,
                                                            k.friction, k.slip_scale);
  const Eigen::Matrix<AD<N>, D, 1> gs = g_s.template cast<AD<N>>();
  auto node = [&](int a) { return a == 0 ? k.slave : k.master[a - 1]; };
  Eigen::Matrix<double, N, N> G = Eigen::Matrix<double, N, N>::Zero();  // outputs: the slips (row D−1 zero), the facet
  for (int j = 0; j < D - 1; ++j) G.row(j) = t.slip.col(j).dot(gs).derivatives().transpose();
  const Eigen::Matrix<AD<N>, D, 1> nu = missed_direction<D, AD<N>>(t.slip);  // as local()
  const AD<N> along = nu.dot(gs);
  for (int o = 0; o < D * NF; ++o) G.row(D + o) = (nu.dot(t.master.col(o)) * along).derivatives().transpose();
  for (int a = 0; a <= NF; ++a)
    for (int b = 0; b <= NF; ++b)
      add_variation_block(c, node(a), a == 0, node(b), G.template block<D, D>(a * D, b * D), K_r);
}

// The same for a slave holding two constraints: inputs and outputs the
// slave, facet 1's nodes and facet 2's.
template <int D>
void Elimination<D>::add_pair_variation(int c, const Vec<D>& g_s, SparseMatrix& K_r) const {
  if ((*constraints_)[groups_[c].constraint[0]].master.size() == D)
    add_pair_variation_of<D>(c, g_s, K_r);
  else
    add_pair_variation_of<kMaxFacetNodes<D>>(c, g_s, K_r);
}

template <int D>
template <int NF>
void Elimination<D>::add_pair_variation_of(int c, const Vec<D>& g_s, SparseMatrix& K_r) const {
  const Group& g = groups_[c];
  const PairKernelOf<NF> in = pair_input<NF>(g, u_);
  constexpr int N = D * (2 * NF + 1);
  const auto t = zero_work::pair_frictionless_test<D, AD<N>, NF>(variables<N>(in.x), variables<N>(in.dx));
  const Eigen::Matrix<AD<N>, D, 1> gs = g_s.template cast<AD<N>>();
  Eigen::Matrix<double, N, N> G = Eigen::Matrix<double, N, N>::Zero();  // outputs: the slip (rows 1…D−1 zero), the facets
  if constexpr (D == 3) G.row(0) = t.slip.dot(gs).derivatives().transpose();
  for (int o = 0; o < 2 * D * NF; ++o) G.row(D + o) = t.master.col(o).dot(gs).derivatives().transpose();
  auto node = [&](int a) {
    return a == 0 ? g.slave : (*constraints_)[g.constraint[(a - 1) / NF]].master[(a - 1) % NF];
  };
  for (int a = 0; a <= 2 * NF; ++a)
    for (int b = 0; b <= 2 * NF; ++b)
      add_variation_block(c, node(a), a == 0, node(b), G.template block<D, D>(a * D, b * D), K_r);
}

template <int D>
Eigen::MatrixXd Elimination<D>::force_variation(std::size_t c, const Vec<D>& f) const {
  constexpr int N = D * (D + 1);  // inputs and outputs: the slave, then the facet's nodes
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(N, N);
  if (groups_[c].count == 2) return G;
  const Constraint<D>& k = (*constraints_)[groups_[c].constraint[0]];
  const Kernel in = kernel_input(k, u_);  // linear facets only (contact_setup)
  if (k.eliminated >= 0) {
    // Held by facet node b: the force pair is κ c(u)/|c_b(u)| at every
    // node (f at b, −W_xᵀ f = κ c_x/|c_b| at the others), κ = f·ĉ_b held;
    // nodes in the group's order: b, the slave, the facet's other nodes.
    const int b = facet_index(k, k.eliminated);
    const auto t = zero_work::frictionless_test<D, AD<N>>(variables<N>(in.x), variables<N>(in.dx), !k.push,
                                                          k.friction, k.slip_scale);
    Eigen::Matrix<AD<N>, D, D + 1> cf;
    Eigen::Matrix<AD<N>, D, D - 1> slip;
    driven_forces<D, AD<N>>(t, b, cf, slip);
    const AD<N> size = sqrt(cf.col(1 + b).squaredNorm());
    Vec<D> direction;
    for (int i = 0; i < D; ++i) direction(i) = cf(i, 1 + b).value() / size.value();
    const double kappa = f.dot(direction);
    std::array<int, D + 1> order{};  // group order → kernel column
    order[0] = 1 + b;
    for (int a = 0, next = 1; a <= D; ++a)
      if (a != 1 + b) order[next++] = a;
    for (int a = 0; a <= D; ++a)
      for (int i = 0; i < D; ++i) {
        const Eigen::Matrix<double, N, 1> d = (cf(i, order[a]) * (kappa / size)).derivatives();
        for (int e = 0; e <= D; ++e) G.block(a * D + i, e * D, 1, D) = d.segment(order[e] * D, D).transpose();
      }
    return G;
  }
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
  const Eigen::Matrix<AD<N>, D, 1> nu = missed_direction<D, AD<N>>(t.slip);
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
    if (!reduction_->owns(s)) continue;  // another rank's slave: its rank adds β and V
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
  // of another constraint), accumulated from the outer end of the chains;
  // a cycle's members pass theirs to each other, (I − C_KK)ᵀ p_K = h_K.
  Eigen::VectorXd passed = g;
  for (auto k = components_.rbegin(); k != components_.rend(); ++k) {
    const std::vector<int>& members = k->members;
    const auto m = static_cast<int>(members.size());
    if (k->coupling.size() > 0) {
      Eigen::VectorXd h(D * m);
      for (int i = 0; i < m; ++i) h.template segment<D>(i * D) = passed.template segment<D>(slaves_[members[i]] * D);
      h = k->coupling.transpose().fullPivLu().solve(h);
      for (int i = 0; i < m; ++i) passed.template segment<D>(slaves_[members[i]] * D) = h.template segment<D>(i * D);
    }
    for (const int c : members) {
      const Coefficients& l = test_[c];
      const Vec<D> gs = passed.template segment<D>(slaves_[c] * D);
      for (std::size_t a = 0; a < l.nodes.size(); ++a) {
        const int d = slave_of_[l.nodes[a]];
        if (d < 0 || std::find(members.begin(), members.end(), d) != members.end()) continue;
        passed.template segment<D>(l.nodes[a] * D) += l.master.middleCols(a * D, D).transpose() * gs;
      }
    }
  }
  for (std::size_t c = 0; c < groups_.size(); ++c)
    if (reduction_->owns(slaves_[c])) add_variation(static_cast<int>(c), passed.template segment<D>(slaves_[c] * D), K_r);
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
// concave edge (the neighbour rising in front of the facet's plane), to a
// neighbour the slave projects inside with a gap smaller by more than
// round-off (so that it ends behind neither facet).
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
  // Curved facets meet at kinks of their tangent: a convex one's quadratic
  // extension beyond its border bends inside the neighbour, so a slave held
  // just beyond the border (in the wedge between the two) would be pushed
  // behind the neighbour, switched to it, and back at every iterate. A
  // quadratic facet is kept until the slave is kCurvedBorder beyond it.
  const double tol = quadratic<D>(master) ? std::max((*pairs_)[k.pair].search.inside_tolerance, kCurvedBorder)
                                          : (*pairs_)[k.pair].search.inside_tolerance;
  // A neighbour must be lower by more than round-off: on a flat surface
  // (or at a vertex the slave sits on) all facets give the same gap, and a
  // choice made by round-off would hop between iterations.
  const double lower = (*pairs_)[k.pair].search.penetration_tolerance;
  Match<D> best{facet, project_on<D>(xs, master, facet, x)};
  if (switches >= kMaxSwitches) return best;
  // Never onto a facet that faces the way the slave does (find_master).
  const ContactSurface& slave = (*pairs_)[k.pair].slave;
  const Vec<D> facing = node_normal<D>(slave, static_cast<std::size_t>(slave.local_node(k.slave)), x);
  const Match<D> start = best;
  best = follow<D>(xs, best, master, x, tol, &facing);
  // Self-contact: never onto a facet at the slave or its neighbours.
  const std::vector<int> near = (*pairs_)[k.pair].self ? near_nodes(master, k.slave) : std::vector<int>{};
  if (!near.empty() && has_any(master, best.facet, near)) best = start;
  const FacetNodes<D> here = facet_nodes<D>(master, best.facet, x);
  for (int side = 0; side < D; ++side) {
    const int next = master.facet_neighbours(side, best.facet);
    if (next < 0 || (!near.empty() && has_any(master, next, near))) continue;
    const FacetNodes<D> there = facet_nodes<D>(master, next, x);
    // At a concave edge only: the neighbour rises in front of this facet's
    // plane. Behind a convex one (a slave just behind a wall's face, level
    // with its bottom) the slave projects inside the face beyond too, far
    // behind it. (A curved facet's: by its chord.)
    if (!((there.rowwise().mean() - here.col(0)).dot(best.projection.normal) > 0.0)) continue;
    const Projection<D> p = project_on<D>(xs, master, next, x);
    if (p.inside(tol) && p.gap < best.projection.gap - lower && !(p.normal.dot(facing) > 0.0)) best = Match<D>{next, p};
  }
  return best;
}

template <int D>
void Elimination<D>::set_mid_point(Constraint<D>& k, int facet, const Positions<D>& x_mid) const {
  const ContactSurface& master = (*pairs_)[k.pair].master;
  const Projection<D> mid = project_on<D>(x_mid.col(k.slave), master, facet, x_mid);  // (60)–(64), 2
  k.facet = facet;
  k.master = FacetIndex<D>(master.facets, facet);
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
    const FacetWeights<D> N = facet_weights<D>(k.master.size(), k.xi);
    for (int b = 0; b < k.master.size(); ++b)
      relative -= N(b) * (x.col(k.master[b]) - X_.col(k.master[b]) - u_n_.template segment<D>(k.master[b] * D));
    xs -= relative.dot(k.normal) * k.normal;  // flat facet: ξ_{n+½} and n_{n+½} unchanged (curved: to first order)
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

// A driven slave's constraint: its holder b moves along the facet's
// normal n (at the start of the placement) until the slave's gap is γ, or
// under (48) until its normal rate relative to its point of the facet is
// zero: r = N_b (d·n) δ, Newton on the one scalar. The facet is the one the
// slave projects on (settle); a switch takes the new facet's holder.
template <int D>
void Elimination<D>::place_driven(Constraint<D>& k, int group, Positions<D>& x, Positions<D>& x_mid,
                                  int& switches) const {
  const ContactSurface& master = (*pairs_)[k.pair].master;
  const Vec<D> xs = x.col(k.slave);
  const Vec<D> xs_n = X_.col(k.slave) + u_n_.template segment<D>(k.slave * D);
  const Match<D> best = settle(k, xs, k.facet, x, switches);
  if (best.facet != k.facet) {
    ++switches;
    k.facet = best.facet;
    k.master = FacetIndex<D>(master.facets, best.facet);
  }
  if (std::find(k.master.begin(), k.master.end(), k.eliminated) == k.master.end())
    k.eliminated = holder(k, best.projection.xi, group);
  if (k.eliminated < 0) {  // left out at the next build
    set_mid_point(k, k.facet, x_mid);
    return;
  }
  const int b = k.eliminated, jb = facet_index(k, b);
  const Vec<D> xb_n = X_.col(b) + u_n_.template segment<D>(b * D);
  Vec<D> direction = Vec<D>::Zero();
  double previous = std::numeric_limits<double>::infinity();
  for (int iteration = 0; iteration < kCycleIterations; ++iteration) {
    double r = 0.0;
    Vec<D> n, N;
    if (k.rate) {
      x_mid.col(b) = 0.5 * (x.col(b) + xb_n);
      set_mid_point(k, k.facet, x_mid);
      N = facet_shape<D>(k.xi);
      Vec<D> relative = xs - xs_n;
      for (int a = 0; a < D; ++a)
        relative -= N(a) * (x.col(k.master[a]) - X_.col(k.master[a]) - u_n_.template segment<D>(k.master[a] * D));
      n = k.normal;
      r = relative.dot(n);
    } else {
      const Projection<D> p = project<D>(xs, facet_nodes<D>(master, k.facet, x));
      N = facet_shape<D>(p.xi);
      n = p.normal;
      r = p.gap - k.gap;
    }
    if (iteration == 0) direction = n;
    const double scale = std::max(xs.cwiseAbs().maxCoeff(), x.col(b).cwiseAbs().maxCoeff());
    if (std::abs(r) <= 4.0 * std::numeric_limits<double>::epsilon() * scale || !(std::abs(r) < previous)) break;
    previous = std::abs(r);
    x.col(b) += (r / (N(jb) * direction.dot(n))) * direction;
  }
  x_mid.col(b) = 0.5 * (x.col(b) + xb_n);
  set_mid_point(k, k.facet, x_mid);
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
        const Vec<D> m = quadratic<D>(master) ? project_on<D>(xs, master, other, x).normal
                                              : facet_normal<D>(facet_nodes<D>(master, other, x));
        const double cosine = best.projection.normal.dot(m);
        if (best.facet == other || 1.0 - cosine * cosine < kCreaseSine * kCreaseSine)
          best = Match<D>{facet[j], project_on<D>(xs, master, facet[j], x)};
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
void Elimination<D>::place(const Group& g, Positions<D>& x, Positions<D>& x_mid) {
  if (g.count == 2) {
    place_pair(g, x, x_mid);
    return;
  }
  const int c = g.constraint[0];
  Constraint<D>& k = (*constraints_)[c];
  if ((*pairs_)[k.pair].slave_driven()) {
    place_driven(k, slave_of_[g.slave], x, x_mid, switches_[c]);
    return;
  }
  if (k.kind == Kind::stick) {  // (45): the slave at its point of the facet's frame
    zero_work::Facet<D, double> xm;
    for (int b = 0; b < D; ++b) xm.col(b) = x.col(k.master[b]);
    x.col(k.slave) = zero_work::stick_position<D, double>(xm, k.xi, k.gap);
    x_mid.col(k.slave) = 0.5 * (x.col(k.slave) + X_.col(k.slave) + u_n_.template segment<D>(k.slave * D));
  } else {
    place_frictionless(k, x, x_mid, switches_[c]);
  }
}

// How group g's placed slave moves with the positions of its facets'
// nodes to first order: stick, the frame's Jacobian; one frictionless
// gap, N_b n nᵀ (only the normal follows); two, the pair's trial map.
template <int D>
typename Elimination<D>::Coefficients Elimination<D>::placement(const Group& g, const Positions<D>& x) const {
  if (g.count == 2) {  // the pair's trial map at these positions
    const Eigen::VectorXd u = (x - X_).reshaped();
    return local_pair(g, &u).trial;
  }
  const Constraint<D>& k = (*constraints_)[g.constraint[0]];
  if (k.eliminated >= 0) return driven_trial(k, x);
  Coefficients p;
  p.nodes.assign(k.master.begin(), k.master.end());
  if (k.kind == Kind::stick) {
    zero_work::Facet<D, double> xm;
    for (int b = 0; b < D; ++b) xm.col(b) = x.col(k.master[b]);
    p.master = zero_work::stick_jacobian<D, double>(xm, k.xi, k.gap);
    return p;
  }
  const Projection<D> pr = project_on<D>(x.col(k.slave), (*pairs_)[k.pair].master, k.facet, x);
  const FacetWeights<D> N = facet_weights<D>(k.master.size(), pr.xi);
  p.master.resize(D, D * k.master.size());
  for (int b = 0; b < k.master.size(); ++b) p.master.middleCols(b * D, D) = N(b) * pr.normal * pr.normal.transpose();
  return p;
}

// A cycle's slaves each stand where their facets' nodes, among them the
// other slaves, put them: x_K = P(x_K). Newton on it, with P's Jacobian
// from placement(): exact in one iteration for flat facets, where the
// sweeps alone contract only by the slaves' weights outside the cycle.
template <int D>
void Elimination<D>::place_cycle(const std::vector<int>& members, Positions<D>& x, Positions<D>& x_mid) {
  const auto m = static_cast<int>(members.size());
  std::map<int, int> member;
  for (int i = 0; i < m; ++i) member[slaves_[members[i]]] = i;
  Eigen::VectorXd r(D * m);
  // The trial placements may switch facets back and forth; the solve's
  // cap on switches (kMaxSwitches) counts one for a member whose facet
  // differs at the end.
  const std::vector<int> switches = switches_;
  std::map<int, int> facet_before;
  for (const int g : members)
    for (int j = 0; j < groups_[g].count; ++j)
      facet_before[groups_[g].constraint[j]] = (*constraints_)[groups_[g].constraint[j]].facet;
  double previous = std::numeric_limits<double>::infinity();
  for (int iteration = 0; iteration < kCycleIterations; ++iteration) {
    double scale = 0.0;
    for (int i = 0; i < m; ++i) {
      const int s = slaves_[members[i]];
      const Vec<D> before = x.col(s), before_mid = x_mid.col(s);
      place(groups_[members[i]], x, x_mid);
      r.template segment<D>(i * D) = x.col(s) - before;
      scale = std::max(scale, before.cwiseAbs().maxCoeff());
      x.col(s) = before;
      x_mid.col(s) = before_mid;
    }
    if (r.cwiseAbs().maxCoeff() <= 4.0 * std::numeric_limits<double>::epsilon() * scale) break;
    Eigen::MatrixXd J = Eigen::MatrixXd::Identity(D * m, D * m);
    for (int i = 0; i < m; ++i) {
      const Coefficients p = placement(groups_[members[i]], x);
      for (std::size_t a = 0; a < p.nodes.size(); ++a)
        if (const auto j = member.find(p.nodes[a]); j != member.end())
          J.block(i * D, j->second * D, D, D) -= p.master.middleCols(a * D, D);
    }
    // A near-singular J (the cycle's slaves on each other's nodes) or a
    // growing residual ends the iteration: the sweeps' placement stands,
    // and the maps' build leaves the cycle's second pass out (build()).
    Eigen::FullPivLU<Eigen::MatrixXd> lu(J);
    lu.setThreshold(kRedundantPivot);
    const double size = r.norm();
    if (lu.rank() < D * m || !(size < previous)) break;
    previous = size;
    const Eigen::VectorXd step = lu.solve(r);
    for (int i = 0; i < m; ++i) x.col(slaves_[members[i]]) += step.template segment<D>(i * D);
  }
  switches_ = switches;
  for (const int c : members) place(groups_[c], x, x_mid);
  for (const auto& [c, facet] : facet_before)
    if ((*constraints_)[c].facet != facet) switches_[c] = std::max(switches_[c], switches[c] + 1);
}

template <int D>
void Elimination<D>::enforce(Eigen::VectorXd& u) {
  if (!pairs_) throw Error("Elimination::enforce needs the step's geometry (the geometry constructor)");
  Positions<D> x = positions(u), x_mid = 0.5 * (x + positions(u_n_));
  for (int sweep = 0; sweep < 2; ++sweep)  // a second sweep settles chains
    for (const Group& g : groups_) place(g, x, x_mid);
  for (const EliminationComponent& k : components_)
    if (k.coupling.size() > 0) place_cycle(k.members, x, x_mid);
  write_placed(x, u);
  build(&u);
  if (!switch_to_rate()) return;
  for (const Group& g : groups_) {
    Constraint<D>& k = (*constraints_)[g.constraint[0]];
    if (g.count == 1 && k.rate) place(g, x, x_mid);
  }
  for (const EliminationComponent& k : components_)
    if (k.coupling.size() > 0) place_cycle(k.members, x, x_mid);
  write_placed(x, u);
  build(&u);
}

template <int D>
void Elimination<D>::place_each(Eigen::VectorXd& u) {
  if (!pairs_) throw Error("Elimination::place_each needs the step's geometry (the geometry constructor)");
  const std::vector<Constraint<D>> kept = *constraints_;
  const std::vector<int> switches = switches_;
  Positions<D> x = positions(u), x_mid = 0.5 * (x + positions(u_n_));
  std::vector<Vec<D>> placed(groups_.size());
  for (std::size_t g = 0; g < groups_.size(); ++g) {
    const int s = groups_[g].slave;
    const Vec<D> before = x.col(s), before_mid = x_mid.col(s);
    place(groups_[g], x, x_mid);
    placed[g] = x.col(s);
    x.col(s) = before;
    x_mid.col(s) = before_mid;
  }
  for (std::size_t g = 0; g < groups_.size(); ++g)
    u.template segment<D>(groups_[g].slave * D) = placed[g] - X_.col(groups_[g].slave);
  *constraints_ = kept;
  switches_ = switches;
}

// The nodes placement moves: the slaves, and the facet nodes that hold
// driven slaves' constraints (before and after a facet switch).
template <int D>
void Elimination<D>::write_placed(const Positions<D>& x, Eigen::VectorXd& u) const {
  for (const Constraint<D>& k : *constraints_) {
    if (!(*pairs_)[k.pair].slave_driven()) u.template segment<D>(k.slave * D) = x.col(k.slave) - X_.col(k.slave);
    if (k.eliminated >= 0) u.template segment<D>(k.eliminated * D) = x.col(k.eliminated) - X_.col(k.eliminated);
  }
  for (const int s : slaves_) u.template segment<D>(s * D) = x.col(s) - X_.col(s);
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
  std::vector<char> near_repeat(groups_.size(), 0);
  for (const EliminationComponent& k : components_)
    if (k.pivot < kRatePivot && k.pivot < kRatePivotRatio * trial_pivot_[static_cast<std::size_t>(k.members[0])])
      for (const int g : k.members) near_repeat[static_cast<std::size_t>(g)] = 1;
  bool any = false;
  for (std::size_t g = 0; g < groups_.size(); ++g) {
    if (groups_[g].count != 1) continue;
    Constraint<D>& k = (*constraints_)[groups_[g].constraint[0]];
    if (k.kind == Kind::frictionless && !k.rate && (cosine_[g] < kRateCosine || near_repeat[g])) k.rate = any = true;
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
  std::vector<int> switches = std::move(switches_);  // the solve's cap counts every switch, reverted or not
  *this = saved.maps;
  switches_ = std::move(switches);
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
