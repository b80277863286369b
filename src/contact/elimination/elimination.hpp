#pragma once
/// Direct elimination of the active slaves' unknowns (paper (35), (41),
/// (43)–(45), (49), (56)–(64); docs/theory.md, "Direct elimination
/// (33)–(65)"). The reduced unknowns q have the size of u; a slave's slots
/// hold its slip increments (frictionless: Δξ[, Δη]) and dummies with zero
/// right-hand side, so the number of equations never changes. Two maps:
///   trial T: the slave's first-order motion, Δu = T q. Stick: the slave
///     moves with its point of the master facet's frame, F(x_m) =
///     N(ξ̄) x_m + γ n(x_m), (35); frictionless: with the end facet's point
///     and its slips, N Δu_m + τ Δξ (49), then it is moved back along the
///     normal to its held gap γ (exact for flat facets, so T is exact to
///     first order); the facet is the one the slave's end position projects
///     on, and the contact force acts on it too;
///   test W: the reduced residual r = Wᵀ g (41)/(56), built from the
///     zero-work force directions of contact/elimination/zero_work.hpp (the paper's N
///     and τ at the mid-point when (48) holds);
/// and the reduced tangent K_r = Wᵀ K T + V + β, with V = (δW)ᵀ g from
/// automatic differentiation of the zero-work kernels and β = tr(K_ss)/D
/// on the dummy diagonal (44)/(59). A slave whose master node is itself a
/// slave (a chain) is expanded by substitution in both maps (V is then
/// taken to first order through the chained rows); slaves that depend on
/// each other in a cycle (two passes, self-contact) are solved together,
/// and a cycle of repeated constraints is refused as redundant.
/// A node on two slave surfaces may hold two frictionless constraints (of
/// two pairs, with facet normals n_1, n_2 not parallel), and so may a
/// slave at a crease of one master surface (two facets that share a node,
/// ActiveSet::crease): it keeps one slip
/// (3D: along n_1 × n_2; 2D: none), Δx_s = C [n_1ᵀ N_1 Δx_m1; n_2ᵀ N_2 Δx_m2]
/// + (n_1 × n_2) Δξ with C = [n_1 n_2] G⁻¹, G = the normals' Gram matrix, so
/// both gaps are held, and its residual is split between the two
/// constraints' zero-work directions (zero_work::pair_frictionless_test).
/// The maps, their rows and the reduced tangent's blocks are per slave
/// node (a "group" of one or two constraints).
#include <array>
#include <memory>
#include <optional>
#include <vector>

#include "contact/constraint.hpp"
#include "contact/elimination/tangent_reduction.hpp"

namespace conserve::contact {

/// Eliminated slaves that depend on each other through their master nodes
/// (a cycle), or one slave: `members` are groups, `coupling` is I − C_KK
/// of the cycle's coefficients on its own slaves (empty for one slave).
struct EliminationComponent {
  std::vector<int> members;
  Eigen::MatrixXd coupling;
  /// A cycle's smallest pivot of (I − C_KK) against its largest (1 for a
  /// lone group): how near the cycle's slaves are to repeating each other.
  double pivot = 1.0;
};

template <int D>
class Elimination {
 public:
  /// Maps from the constraints' stored ξ and τ alone, as if every slave
  /// were on its facet (γ = 0: the paper's (35), (49), (41), (56)); no
  /// geometry, V = 0. For tests of the maps.
  Elimination(int num_nodes, std::vector<Constraint<D>>& constraints);

  /// The elimination of one step from u_n (`pairs` must outlive it) at the
  /// iterate u, which is not modified (call enforce()). The constraints
  /// belong to the caller (the active set) and must outlive the
  /// elimination: it keeps no copy, and enforce() and update() move their
  /// facets, ξ, n and τ in place. `reduction`: the
  /// reduced tangent's pattern and maps, shared with the eliminations of
  /// earlier passes and steps so that they are rebuilt (and a solver's
  /// analysis redone) only when the constraints' nodes change; a new one
  /// if null.
  Elimination(const Positions<D>& X, const Eigen::VectorXd& u_n, const Eigen::VectorXd& u,
              std::vector<Constraint<D>>& constraints, const std::vector<ContactPair<D>>& pairs,
              std::shared_ptr<TangentReduction<D>> reduction = nullptr);

  Elimination(Elimination&&) noexcept = default;
  Elimination& operator=(Elimination&&) noexcept = default;

  [[nodiscard]] bool empty() const { return constraints_->empty(); }
  [[nodiscard]] const std::vector<Constraint<D>>& constraints() const { return *constraints_; }

  /// What update() changes, the maps and the constraints' facets, ξ, n
  /// and τ, kept for a line search to go back to.
  struct Saved;
  /// Copies it into `saved` (reusing its storage).
  void save(std::optional<Saved>& saved) const;
  /// Back to what save() kept; the constraints must be the same slaves.
  void restore(const Saved& saved);
  /// The trial map T, ndof × ndof (assembled on request: the reduction
  /// works with the slaves' rows).
  [[nodiscard]] SparseMatrix map() const { return assemble(trial_rows_); }
  /// The test map W, ndof × ndof (assembled on request).
  [[nodiscard]] SparseMatrix test_map() const { return assemble(test_rows_); }

  /// r = Wᵀ g (the dummy slots come out zero): g with the slave rows
  /// passed on through W.
  void reduce_residual(const Eigen::VectorXd& g, Eigen::VectorXd& r) const;
  /// K_r = Wᵀ K T + V(g) + β on the dummy slots; g is the full residual at
  /// the same iterate. Wᵀ K T is K where T and W are the identity plus the
  /// slave rows and columns mapped (contact/elimination/tangent_reduction.hpp); K_r's
  /// pattern stays the same (explicit zeros kept) while K's pattern and
  /// the constraints' nodes do not change. Returns whether K_r was given a
  /// new pattern (K_r keeps its storage otherwise).
  bool reduce_tangent(const SparseMatrix& K, const Eigen::VectorXd& g, SparseMatrix& K_r) const;
  /// Δu = T q.
  void expand(const Eigen::VectorXd& q, Eigen::VectorXd& du) const;
  /// Applies the reduced increment: u += T q, then enforce(u).
  void update(const Eigen::VectorXd& q, Eigen::VectorXd& u);
  /// Puts the slaves where their constraints hold: stick slaves at F(x_m),
  /// frictionless slaves back to their gap γ on their end facet (or by
  /// (48) if Constraint::rate: switched there when the held gap's zero-work
  /// direction turns more than 60° from the normal); updates
  /// the facets (end and mid-point) and ξ, n, τ of the constraints, and the
  /// maps.
  void enforce(Eigen::VectorXd& u);
  /// Each group's slave (a driven constraint's holder) where its own
  /// constraints put it with every other node at u, one group at a time
  /// (not a cycle's joint placement, nor a chain's sweeps): what a method
  /// holding each constraint by its own unknown measures the constraint's
  /// residual from. The constraints and the maps are left as they were.
  void place_each(Eigen::VectorXd& u);
  /// Whether this rank owns `node` (TangentReduction::owns): it adds the
  /// terms of the constraints whose slave it is.
  [[nodiscard]] bool owns(int node) const { return reduction_->owns(node); }
  /// Pattern builds of the reduced tangent so far (by all the eliminations
  /// sharing its reduction).
  [[nodiscard]] int pattern_builds() const { return reduction_->builds(); }
  /// The slaves' rows of T and W, per slave node (the maps at the last
  /// enforce()): what a method holding the same constraints by other means
  /// (multipliers, contact/lagrange/) reads them from.
  [[nodiscard]] SlaveRows<D> slave_rows() const { return {slave_of_, slaves_, trial_rows_, test_rows_}; }
  /// The constraints (indices into constraints()) group g holds: one, or
  /// two (the second −1 otherwise). A constraint in no group is left out
  /// of the maps at this iterate (a repeat, or a driven slave's no node
  /// can hold).
  [[nodiscard]] std::array<int, 2> group_constraints(std::size_t g) const { return groups_[g].constraint; }

  /// One constraint's coefficients over `nodes` (master nodes, global):
  /// `master` is D × D·nodes.size() (column a·D + i for node nodes[a],
  /// component i), `slip` the slave's slip slots (frictionless).
  struct Coefficients {
    std::vector<int> nodes;
    Eigen::MatrixXd master;
    Tangents<D> slip = Tangents<D>::Zero();
  };
  /// Per slave node (group g, of slave_rows().slaves[g]): its motion
  /// (trial) and force (test) coefficients over its own facets' nodes and
  /// its slip slots, before chains are composed: what a method holding
  /// each constraint by its own unknown reads.
  [[nodiscard]] const Coefficients& local_trial(std::size_t g) const { return trial_[g]; }
  [[nodiscard]] const Coefficients& local_test(std::size_t g) const { return test_[g]; }
  /// For a method holding group g's constraint by a force f on the slave
  /// (the multipliers, contact/lagrange/): the derivative of that force
  /// pair, f at the slave and −W_aᵀ f at its facet's nodes a (W_a its test
  /// coefficients), by the positions of these nodes at the maps' iterate,
  /// with f = λ ν turning as ν does (λ = f·ν held): ν the unit direction
  /// the slave's test slips miss (frictionless and Coulomb: their span's
  /// normal, which friction turns with the slip), or fixed (stick: f is
  /// held along the axes, W_a alone varies). D(D+1) × D(D+1), node blocks
  /// in the order slave, facet nodes (k.master), outputs by inputs,
  /// by automatic differentiation of the zero-work kernels. Zero for a
  /// group of two constraints (not differentiated). A driven slave's
  /// constraint (ContactPair::slave_driven): its holder in the slave's
  /// place, then the facet's other nodes as in local_trial().
  [[nodiscard]] Eigen::MatrixXd force_variation(std::size_t g, const Vec<D>& f) const;

 private:
  /// A copy would work on the same constraints: only save() makes one,
  /// together with a copy of them.
  Elimination(const Elimination&) = default;
  Elimination& operator=(const Elimination&) = default;

  struct Local {
    Coefficients trial, test;
    double cosine = 1.0;  ///< frictionless: â·n of its zero-work direction (zero_work::TestColumns)
  };

  /// The constraints of one eliminated slave node: one, or two
  /// frictionless ones on two facets (of different pairs, or a crease
  /// pair of one).
  struct Group {
    int slave = -1;
    int count = 0;
    std::array<int, 2> constraint{-1, -1};
  };

  /// A constraint's nodes (slave, facet nodes) for the zero-work kernels:
  /// end positions, displacements over the step (from displacement
  /// differences, exact), the facet's start positions, and for stick the
  /// slave's start offset from its frozen point.
  /// NF: the facet's nodes (D, or kMaxFacetNodes for a quadratic one).
  template <int NF>
  struct KernelOf {
    Eigen::Matrix<double, D, NF + 1> x, dx;
    Eigen::Matrix<double, D, NF> xm_n;
    Vec<D> offset = Vec<D>::Zero();
  };
  using Kernel = KernelOf<D>;
  template <int NF = D>
  [[nodiscard]] KernelOf<NF> kernel_input(const Constraint<D>& k, const Eigen::VectorXd& u) const;
  /// A frictionless constraint's maps at u (not a driven slave's): the
  /// trial map N_b n nᵀ and τ, the test map from the zero-work kernel.
  template <int NF>
  [[nodiscard]] Local local_frictionless(const Constraint<D>& k, const Eigen::VectorXd& u) const;
  /// add_variation for such a constraint.
  template <int NF>
  void add_frictionless_variation(int c, const Constraint<D>& k, const Vec<D>& g_s, SparseMatrix& K_r) const;
  /// End positions and displacements of a two-constraint group's nodes:
  /// the slave, facet 1's nodes, facet 2's.
  template <int NF>
  struct PairKernelOf {
    Eigen::Matrix<double, D, 2 * NF + 1> x, dx;
  };
  template <int NF>
  [[nodiscard]] PairKernelOf<NF> pair_input(const Group& g, const Eigen::VectorXd& u) const;
  /// Marks the second pass's constraints that repeat another at u (suspended_).
  void suspend_repeats(const Eigen::VectorXd* u);
  /// Groups of the constraints not suspended at u (if given), the driven
  /// slaves' holders chosen last.
  void make_groups(const Eigen::VectorXd* u);
  /// The node that holds driven constraint k with its slave at ξ on its
  /// facet (group: its own group, whose node may be kept), or −1.
  [[nodiscard]] int holder(const Constraint<D>& k, const Xi<D>& xi, int group) const;
  /// The position of `node` among k's facet nodes.
  [[nodiscard]] static int facet_index(const Constraint<D>& k, int node);
  /// The trial map of driven constraint k (held by k.eliminated) at
  /// positions x (k's stored ξ, n, τ without geometry).
  [[nodiscard]] Coefficients driven_trial(const Constraint<D>& k, const Positions<D>& x) const;
  /// Places driven constraint k's holder (group: its group).
  void place_driven(Constraint<D>& k, int group, Positions<D>& x, Positions<D>& x_mid, int& switches) const;
  /// u at the nodes placement moved, from x.
  void write_placed(const Positions<D>& x, Eigen::VectorXd& u) const;
  /// The groups' local coefficients and composed rows at u.
  void compose(const Eigen::VectorXd* u);
  void build(const Eigen::VectorXd* u);
  [[nodiscard]] Local local(const Constraint<D>& k, const Eigen::VectorXd& u) const;
  /// Two constraints on one slave: the trial map from the facets' normals
  /// n_k and shape values at the slave's projections (ξ_k), the test map
  /// from the zero-work directions if u is given, else the trial's.
  [[nodiscard]] Local local_pair(const Group& g, const Eigen::VectorXd* u) const;
  template <int NF>
  [[nodiscard]] Local local_pair_of(const Group& g, const Eigen::VectorXd* u) const;
  /// The facet of constraint k's master surface that slave position xs
  /// projects on, starting from `facet` (walking and, at a concave edge,
  /// taking a lower neighbour while switches stay under the cap).
  [[nodiscard]] Match<D> settle(const Constraint<D>& k, const Vec<D>& xs, int facet, const Positions<D>& x,
                                int switches) const;
  /// Constraint k on `facet` at the mid-point positions: its master nodes, ξ, n, τ.
  void set_mid_point(Constraint<D>& k, int facet, const Positions<D>& x_mid) const;
  void place_frictionless(Constraint<D>& k, Positions<D>& x, Positions<D>& x_mid, int& switches) const;
  /// Both constraints' gaps held at once (one Gram solve per pass); the
  /// two facets of a crease pair are kept apart (never one, nor two within
  /// kCreaseSine of coplanar).
  void place_pair(const Group& g, Positions<D>& x, Positions<D>& x_mid);
  /// Puts group g's slave where its constraints hold (enforce()).
  void place(const Group& g, Positions<D>& x, Positions<D>& x_mid);
  /// How that placement moves with its facets' nodes, to first order.
  [[nodiscard]] Coefficients placement(const Group& g, const Positions<D>& x) const;
  /// Places the slaves of a cycle (groups `members`) together.
  void place_cycle(const std::vector<int>& members, Positions<D>& x, Positions<D>& x_mid);
  static constexpr int kCycleIterations = 20;
  [[nodiscard]] SparseMatrix assemble(const std::vector<BlockRow<D>>& rows) const;
  void add_variation(int c, const Vec<D>& g_s, SparseMatrix& K_r) const;
  void add_pair_variation(int c, const Vec<D>& g_s, SparseMatrix& K_r) const;
  template <int NF>
  void add_pair_variation_of(int c, const Vec<D>& g_s, SparseMatrix& K_r) const;
  /// K_r += Ŵ_aᵀ G T̂_b: the derivative G of constraint c's test output at
  /// node `out` (its slip slots if `slip`) by the position of node `in`,
  /// through the nodes' rows of W and T (the identity for a free node).
  void add_variation_block(int c, int out, bool slip, int in, const Mat<D>& G, SparseMatrix& K_r) const;
  [[nodiscard]] Positions<D> positions(const Eigen::VectorXd& u) const;

  std::vector<Constraint<D>>* constraints_;  ///< the caller's (the active set's)
  const std::vector<ContactPair<D>>* pairs_ = nullptr;
  Positions<D> X_;
  Eigen::VectorXd u_n_, u_;  ///< start of the step; the iterate the maps belong to
  int num_nodes_ = 0;
  std::vector<Group> groups_;                        ///< per eliminated slave node
  std::vector<int> slave_of_;                        ///< per node: its group, or −1
  std::vector<int> slaves_;                          ///< per group: its slave node
  std::vector<BlockRow<D>> trial_rows_, test_rows_;  ///< per group: the slave's rows of T and W (chains composed)
  std::vector<Coefficients> test_;                   ///< per group: its test coefficients
  std::vector<Coefficients> trial_;                  ///< per group: its trial coefficients (before chains)
  /// Groups that depend on each other, each component after those of its
  /// members' master nodes (the test map's).
  std::vector<EliminationComponent> components_;
  std::shared_ptr<TangentReduction<D>> reduction_;   ///< K_r's pattern and maps, kept while the nodes are unchanged
  static constexpr int kMaxSwitches = 2;
  /// Frictionless slaves whose ā_s points closer than this to the facet
  /// plane (â·n below it: more than 60° from the normal) at an iterate
  /// hold the rate condition (48) for the rest of the step (Constraint::rate).
  static constexpr double kRateCosine = 0.5;
  /// A cycle of the test maps whose pivot (EliminationComponent::pivot) is
  /// below kRatePivot and below kRatePivotRatio of the trial map's takes
  /// (48) too: its slaves nearly repeat each other, and the zero-work
  /// directions, leaning off the normals, make (I − C_KK) nearer singular
  /// than the trial map's; under (48) the two are alike. A cycle whose
  /// trial map is as near singular repeats itself (repeats(), kRepeatPivot).
  static constexpr double kRatePivot = 1e-2;
  static constexpr double kRatePivotRatio = 0.25;
  /// Switches to (48) the single frictionless constraints whose zero-work
  /// direction at the last build was degenerate (â·n < kRateCosine) or
  /// whose cycle nearly repeats itself in the test maps only (kRatePivot).
  bool switch_to_rate();
  std::vector<double> cosine_;  ///< per group: â·n at the last build (1 if not applicable)
  std::vector<double> trial_pivot_;  ///< per group: its trial map's cycle's pivot at the last build (1 if none)
  std::vector<int> switches_;  ///< facet switches per constraint in this solve
  /// Per constraint: left out of the maps at this iterate (make_groups).
  std::vector<char> suspended_;
};

template <int D>
struct Elimination<D>::Saved {
  Elimination<D> maps;
  std::vector<Constraint<D>> constraints;
};

}  // namespace conserve::contact
