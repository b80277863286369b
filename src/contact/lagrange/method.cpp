#include "contact/lagrange/method.hpp"

#include <algorithm>

#include "core/error.hpp"

namespace conserve::contact {
namespace {

/// Directions of a slave's force or motion its slips miss: the unit
/// vectors `seeds` (its constraints' normals; stick: the axes) with the
/// columns of `slips` (the slave's own block of W or T) projected out,
/// orthonormalised in order.
template <int D>
std::vector<Vec<D>> missed_directions(const Mat<D>& slips, const std::vector<Vec<D>>& seeds) {
  std::vector<Vec<D>> basis;  // the slips' column space, then the result
  for (int j = 0; j < D; ++j) {
    Vec<D> v = slips.col(j);
    for (const Vec<D>& b : basis) v -= b.dot(v) * b;
    if (v.norm() > 1e-10 * std::max(1.0, slips.norm())) basis.push_back(v.normalized());
  }
  std::vector<Vec<D>> out;
  for (const Vec<D>& seed : seeds) {
    Vec<D> v = seed;
    for (const Vec<D>& b : basis) v -= b.dot(v) * b;
    if (v.norm() < 1e-10) continue;  // degenerate: dropped
    v.normalize();
    basis.push_back(v);
    out.push_back(v);
  }
  return out;
}

/// One multiplier: its slave's group, its force direction ν (at the slave;
/// −W_aᵀ ν at the nodes a of its facets), its motion direction μ, and its
/// slot among the multipliers (fixed for the solve: the constraint's).
template <int D>
struct Multiplier {
  int group = -1;  ///< the slave's row in SlaveRows
  Vec<D> force = Vec<D>::Zero();
  Vec<D> motion = Vec<D>::Zero();
  int slot = -1;
};

template <int D>
class LagrangeCoupling final : public Coupling {
 public:
  LagrangeCoupling(std::unique_ptr<Elimination<D>> elimination, double beta)
      : e_(std::move(elimination)), beta_(beta) {
    for (const Constraint<D>& c : e_->constraints()) {
      first_.push_back(m_);
      m_ += c.kind == Kind::stick ? D : 1;
    }
    lambda_ = Eigen::VectorXd::Zero(m_);
  }
  [[nodiscard]] bool plain() const override { return e_->empty(); }
  [[nodiscard]] int equations(int free) const override { return free + m_; }
  void start(Eigen::VectorXd& u) override {
    if (!plain()) e_->enforce(u);  // the same start as elimination's
  }

  void residual(const Eigen::VectorXd& u, Eigen::VectorXd& g, Eigen::VectorXd& magnitude,
                Eigen::VectorXd& r) override {
    const auto n = u.size();
    // Where the constraints hold, from u: the elimination places the
    // slaves (and its maps follow that configuration).
    placed_ = u;
    e_->enforce(placed_);
    // The constraint rows: each slave from where its own facet at u puts
    // it, as their derivative C (local trial coefficients) says.
    local_ = u;
    e_->place_each(local_);
    directions();
    r.resize(n + m_);
    r.head(n) = g;
    const SlaveRows<D> rows = e_->slave_rows();
    // A multiplier of a constraint left out at this iterate: λ = 0.
    for (const int k : idle_) r[n + k] = beta_ * lambda_[k];
    for (const Multiplier<D>& mk : multipliers_) {
      const int k = mk.slot;
      const int s = rows.slaves[static_cast<std::size_t>(mk.group)];
      const typename Elimination<D>::Coefficients& w = e_->local_test(static_cast<std::size_t>(mk.group));
      const Vec<D> f = lambda_[k] * mk.force;
      r.template segment<D>(s * D) += f;
      magnitude.template segment<D>(s * D) += f.cwiseAbs();
      for (std::size_t a = 0; a < w.nodes.size(); ++a) {
        const Vec<D> fa = -(w.master.block(0, static_cast<Eigen::Index>(a) * D, D, D).transpose() * f);
        r.template segment<D>(w.nodes[a] * D) += fa;
        magnitude.template segment<D>(w.nodes[a] * D) += fa.cwiseAbs();
      }
      r[n + k] = beta_ * mk.motion.dot(u.template segment<D>(s * D) - local_.template segment<D>(s * D));
    }
  }

  bool tangent(const Eigen::VectorXd& u, const SparseMatrix& K, const Eigen::VectorXd&, SparseMatrix& A) override {
    const auto n = u.size();
    std::vector<Eigen::Triplet<double>> t;
    t.reserve(static_cast<std::size_t>(K.nonZeros()) + static_cast<std::size_t>(m_) * 8 * D * D);
    for (int col = 0; col < K.outerSize(); ++col)
      for (SparseMatrix::InnerIterator it(K, col); it; ++it) t.emplace_back(it.row(), col, it.value());
    const SlaveRows<D> rows = e_->slave_rows();
    // Each constraint's terms are added by the rank that owns its slave
    // (the others' go to it: solver/petsc_system.hpp).
    for (const int k : idle_)
      if (e_->owns(slot_slave(k))) t.emplace_back(static_cast<int>(n) + k, static_cast<int>(n) + k, beta_);
    for (const Multiplier<D>& mk : multipliers_) {
      const int k = mk.slot;
      const int s = rows.slaves[static_cast<std::size_t>(mk.group)];
      if (!e_->owns(s)) continue;
      const auto lam = static_cast<int>(n) + k;
      for (int i = 0; i < D; ++i) {
        t.emplace_back(s * D + i, lam, mk.force(i));           // B
        t.emplace_back(lam, s * D + i, beta_ * mk.motion(i));  // β C: the slave's motion ...
      }
      const typename Elimination<D>::Coefficients& w = e_->local_test(static_cast<std::size_t>(mk.group));
      for (std::size_t a = 0; a < w.nodes.size(); ++a) {
        const Vec<D> column = -(w.master.block(0, static_cast<Eigen::Index>(a) * D, D, D).transpose() * mk.force);
        for (int i = 0; i < D; ++i) t.emplace_back(w.nodes[a] * D + i, lam, column(i));
      }
      // ... less its facets' nodes' that it follows (its slips are missed by μ)
      const typename Elimination<D>::Coefficients& tr = e_->local_trial(static_cast<std::size_t>(mk.group));
      for (std::size_t a = 0; a < tr.nodes.size(); ++a) {
        const Vec<D> row = -(tr.master.block(0, static_cast<Eigen::Index>(a) * D, D, D).transpose() * mk.motion);
        for (int i = 0; i < D; ++i) t.emplace_back(lam, tr.nodes[a] * D + i, beta_ * row(i));
      }
      t.emplace_back(lam, lam, 0.0);  // the zero block's diagonal, kept in the pattern
    }
    add_force_variation(t);
    SparseMatrix fresh(n + m_, n + m_);
    fresh.setFromTriplets(t.begin(), t.end());
    fresh.makeCompressed();
    const bool same = A.rows() == fresh.rows() && A.nonZeros() == fresh.nonZeros() &&
                      std::equal(A.outerIndexPtr(), A.outerIndexPtr() + A.outerSize() + 1, fresh.outerIndexPtr()) &&
                      std::equal(A.innerIndexPtr(), A.innerIndexPtr() + A.nonZeros(), fresh.innerIndexPtr());
    if (same)
      std::copy(fresh.valuePtr(), fresh.valuePtr() + fresh.nonZeros(), A.valuePtr());
    else
      A = std::move(fresh);
    return !same;
  }

  void update(const Eigen::VectorXd& increment, Eigen::VectorXd& u) override {
    const auto n = u.size();
    u += increment.head(n);
    lambda_ += increment.tail(m_);
  }
  void save() override {
    saved_lambda_ = lambda_;
    e_->save(saved_);
  }
  bool restore() override {
    if (!saved_) return false;
    lambda_ = saved_lambda_;
    e_->restore(*saved_);
    return true;
  }

 private:
  /// The multipliers' directions from the maps at the last enforce():
  /// per slave, its constraints' normals (stick: the axes) with the test
  /// (force) or trial (motion) slips projected out.
  void directions() {
    const SlaveRows<D> rows = e_->slave_rows();
    multipliers_.clear();
    std::vector<char> used(static_cast<std::size_t>(m_), 0);
    for (std::size_t c = 0; c < rows.slaves.size(); ++c) {
      std::vector<Vec<D>> seeds;
      std::vector<int> slots;
      for (const int j : e_->group_constraints(c)) {
        if (j < 0) continue;
        const Constraint<D>& k = e_->constraints()[static_cast<std::size_t>(j)];
        if (k.kind == Kind::stick)
          for (int i = 0; i < D; ++i) seeds.push_back(Vec<D>::Unit(i)), slots.push_back(first_[j] + i);
        else
          seeds.push_back(k.normal), slots.push_back(first_[j]);
      }
      const auto slips = [](const typename Elimination<D>::Coefficients& l) {
        Mat<D> block = Mat<D>::Zero();
        block.template leftCols<D - 1>() = l.slip;
        return block;
      };
      const std::vector<Vec<D>> force = missed_directions<D>(slips(e_->local_test(c)), seeds);
      const std::vector<Vec<D>> motion = missed_directions<D>(slips(e_->local_trial(c)), seeds);
      if (force.size() != seeds.size() || motion.size() != seeds.size())
        throw SolverError("a contact constraint's multiplier direction is degenerate (its slips span its normal)");
      for (std::size_t j = 0; j < seeds.size(); ++j) {
        multipliers_.push_back({static_cast<int>(c), force[j], motion[j], slots[j]});
        used[static_cast<std::size_t>(slots[j])] = 1;
      }
    }
    idle_.clear();
    for (int k = 0; k < m_; ++k)
      if (!used[static_cast<std::size_t>(k)]) idle_.push_back(k);
  }

  /// B's own variation, ∂(Bλ)/∂u: per slave, the derivative of its force
  /// pair f = Σ λ_k ν_k (Elimination::force_variation, at the placed
  /// configuration the maps belong to) with its inputs taken to u through
  /// the placement: the slave keeps its motion along its slips and follows
  /// its facet's along μ (frictionless: Π = 1 − μμᵀ on its own motion,
  /// μμᵀ T_a on node a's), or entirely (stick: 0 and T_a); a facet node
  /// that is itself a slave (a chain) the same way, one link deep. Left
  /// out: a slave holding two constraints, cycles, the further links of a
  /// chain, and μ's own variation (its term vanishes with c): Newton
  /// converges quadratically on single constraints, with friction too, and
  /// on a driven slave's held by its facet's node.
  void add_force_variation(std::vector<Eigen::Triplet<double>>& t) const {
    const SlaveRows<D> rows = e_->slave_rows();
    const std::size_t groups = rows.slaves.size();
    std::vector<Vec<D>> force(groups, Vec<D>::Zero()), motion(groups, Vec<D>::Zero());
    for (const Multiplier<D>& mk : multipliers_) {
      force[static_cast<std::size_t>(mk.group)] += lambda_[mk.slot] * mk.force;
      motion[static_cast<std::size_t>(mk.group)] = mk.motion;
    }
    std::vector<char> stick(groups, 0);
    for (std::size_t c = 0; c < groups; ++c)
      stick[c] = e_->constraints()[static_cast<std::size_t>(e_->group_constraints(c)[0])].kind == Kind::stick;
    constexpr int N = D * (D + 1);
    for (std::size_t c = 0; c < groups; ++c) {
      if (!e_->owns(rows.slaves[c])) continue;  // the slave's rank adds it
      // Every entry is kept, zero or not, so that the pattern stays while the constraints do.
      const Eigen::MatrixXd G = force[c].isZero() ? Eigen::MatrixXd::Zero(N, N) : e_->force_variation(c, force[c]);
      const typename Elimination<D>::Coefficients& tr = e_->local_trial(c);
      const Mat<D> follow = stick[c] ? Mat<D>::Identity() : Mat<D>(motion[c] * motion[c].transpose());
      const int s = rows.slaves[c];
      auto node = [&](int a) { return a == 0 ? s : tr.nodes[static_cast<std::size_t>(a - 1)]; };
      auto add = [&](int b_node, const Eigen::Matrix<double, N, D>& column) {
        for (int a = 0; a <= D; ++a)
          for (int i = 0; i < D; ++i)
            for (int j = 0; j < D; ++j) t.emplace_back(node(a) * D + i, b_node * D + j, column(a * D + i, j));
      };
      for (int b = 0; b <= D; ++b) {
        // Column block b of G taken to u: the inputs' dependence on node b's displacement.
        if (b == 0) {
          add(s, G.middleCols(0, D) * (Mat<D>::Identity() - follow));
          continue;
        }
        const Eigen::Matrix<double, N, D> column =
            G.middleCols(b * D, D) +
            G.middleCols(0, D) * follow * tr.master.block(0, static_cast<Eigen::Index>(b - 1) * D, D, D);
        const int e = node(b), d = rows.slave_of[static_cast<std::size_t>(e)];
        if (d < 0 || static_cast<std::size_t>(d) == c) {
          add(e, column);
          continue;
        }
        // A facet node that is itself a slave (a chain): placed too, it
        // keeps its own motion off its follow directions and takes its
        // facet's nodes' along them, one link deep.
        const Mat<D> follow_d = stick[static_cast<std::size_t>(d)]
                                    ? Mat<D>::Identity()
                                    : Mat<D>(motion[static_cast<std::size_t>(d)] * motion[static_cast<std::size_t>(d)].transpose());
        add(e, column * (Mat<D>::Identity() - follow_d));
        const typename Elimination<D>::Coefficients& tr_d = e_->local_trial(static_cast<std::size_t>(d));
        for (std::size_t x = 0; x < tr_d.nodes.size(); ++x)
          add(tr_d.nodes[x], column * follow_d * tr_d.master.block(0, static_cast<Eigen::Index>(x) * D, D, D));
      }
    }
  }

  /// The slave of the constraint whose multipliers hold slot k.
  [[nodiscard]] int slot_slave(int k) const {
    const auto j = std::upper_bound(first_.begin(), first_.end(), k) - first_.begin() - 1;
    return e_->constraints()[static_cast<std::size_t>(j)].slave;
  }

  std::unique_ptr<Elimination<D>> e_;
  double beta_;
  int m_ = 0;
  std::vector<int> first_;  ///< per constraint: its first multiplier's slot
  std::vector<int> idle_;   ///< slots of the constraints left out at the last enforce()
  Eigen::VectorXd lambda_, saved_lambda_;
  Eigen::VectorXd placed_, local_;
  std::vector<Multiplier<D>> multipliers_;
  std::optional<typename Elimination<D>::Saved> saved_;
};

}  // namespace

template <int D>
LagrangeMethod<D>::LagrangeMethod(const model::Model<D>& model, const SparseMatrix& mass,
                                  std::vector<ContactPair<D>> pairs, const ImpactLocation& location,
                                  bool persistent)
    : HeldMethod<D>(model, mass, std::move(pairs), location, persistent), mean_mass_(model::mean_dof_mass<D>(mass)) {}

template <int D>
std::unique_ptr<Coupling> LagrangeMethod<D>::coupling(const Eigen::VectorXd& u_n, const Eigen::VectorXd& u_np1) {
  return std::make_unique<LagrangeCoupling<D>>(this->make_elimination(u_n, u_np1), 2.0 / (this->step_length() * this->step_length()) * mean_mass_);
}

template class LagrangeMethod<2>;
template class LagrangeMethod<3>;

}  // namespace conserve::contact
