#pragma once
/// Penalty contact (`[[contact]] method = "penalty"`): every slave node
/// behind a master facet at either end of a step is pushed out by the
/// potential ½ k ⟨−g⟩² (penalty_force.hpp), k = ε × the node's share of its
/// surface; with kind = "stick" it is also tied to its anchor on the facet,
/// where it was at the start of the step it was caught in, by a spring in
/// the facet's plane, let go (with the energy it stores, reported as
/// contact_released) when the slave ends a step in front of the facet.
/// With the discrete-gradient force the mid-point scheme conserves the
/// total energy including the springs' (reported as contact_energy), L and
/// J; the slave penetrates by about its pressure / ε. With kind =
/// "coulomb" the spring's anchor slips by a return map when the spring's
/// force would leave the Coulomb cone (penalty_force.hpp), and the work
/// the friction takes out is reported as dissipated: E_{n+1} + D = E_n.
///
/// Within a step each coupled slave has one facet at the step's end (the
/// step's pairing): the slaves the last step ended coupled and those behind
/// a facet at the predictor, and after each solve those found behind one at
/// its end (solved again while that adds slaves or moves one to another
/// facet). Its potential at the step's start is the one the last step ended
/// with (on its facet then, or 0): a slave that moves to another facet gets
/// the switching discrete gradient (penalty_force.hpp), so that no energy
/// appears or vanishes at a facet switch. The tangent's pattern
/// is the bodies' with the blocks of every slave–facet coupling met so
/// far: it grows when a new one appears and is otherwise kept.
#include <array>
#include <limits>
#include <map>
#include <memory>
#include <vector>

#include "contact/method.hpp"
#include "contact/penalty/penalty_force.hpp"

namespace conserve::contact {

/// One slave–facet coupling of a step.
struct PenaltyCoupling {
  int pair = -1;
  int slave = -1;  ///< global node
  int facet = -1;  ///< of the pair's master surface, at the step's end
  double k = 0.0;  ///< ε a_s [N/m]
  /// The facet around which its potential at the step's start is measured
  /// (the last step ended on it), −1 if the slave was not coupled then.
  int start_facet = -1;
  bool stick = false;               ///< held by a spring to its anchor (stick, or Coulomb with μ > 0)
  std::array<double, 2> anchor{};  ///< ξ₀ (D − 1 entries): where the spring is tied on the facet
  bool slipped = false;  ///< Coulomb: the anchor slipped in the last step
};

/// The part of a master surface nearest to a slave (penalty_force.hpp).
template <int D>
struct Feature {
  int facet = -1;                                        ///< the facet it belongs to
  penalty::FeatureKind kind = penalty::FeatureKind::face;
  std::array<int, 2> node{-1, -1};                       ///< an edge's or the vertex's global nodes
  Vec<D> point = Vec<D>::Zero();                         ///< the nearest point
  Vec<D> normal = Vec<D>::Zero();                        ///< its pseudo-normal (not unit)
  double distance = 0.0;                                 ///< [m]
  bool behind = false;                                   ///< the slave is behind the surface there
};

/// How a coupling's potential is evaluated over a step: the nearest parts
/// at its start, mid-point and end, the energy it starts from, and whether
/// all three are the face of one facet (then the discrete gradient in
/// invariants applies, else the switching one).
template <int D>
struct StepPlan {
  Feature<D> start, mid, end;
  double phi_n = 0.0;  ///< Φ at the step's start [J]
  bool same = false;
};

/// The automatic penalty ε of a pair [Pa/m]: the smaller of E / h over its
/// deformable sides, E a side's body's Young's modulus (small-strain) and
/// h the median longest edge of that side's facets (FEBio's automatic
/// penalty, E·A/V of the element under a facet, is of the same order).
template <int D>
double automatic_penalty(const model::Model<D>& model, const ContactPair<D>& pair);

template <int D>
class PenaltyMethod final : public Method<D> {
 public:
  /// `penalty[p]`: ε of pair p [Pa/m], ≤ 0 (or missing) for automatic;
  /// `conserving`: the discrete-gradient force, else the mid-point one.
  PenaltyMethod(const model::Model<D>& model, std::vector<ContactPair<D>> pairs, const std::vector<double>& penalty,
                bool conserving);

  [[nodiscard]] std::string_view name() const override { return "penalty"; }
  [[nodiscard]] CollisionSet<D>& collisions() override { return collisions_; }
  /// Whether this rank owns `node` (model::Model::owns): it adds the
  /// tangents of the couplings whose slave it is.
  [[nodiscard]] bool owns(int node) const { return model_.owns(node); }
  void begin_step(std::int64_t step, double dt, const model::State& start) override;
  [[nodiscard]] std::unique_ptr<Coupling> coupling(const Eigen::VectorXd& u_n, const Eigen::VectorXd& u_np1) override;
  [[nodiscard]] double split_fraction(const Eigen::VectorXd&, const Eigen::VectorXd&) override { return 1.0; }
  Verdict settle(const model::State& start, double dt, const Eigen::VectorXd& u_np1, const Eigen::VectorXd& g,
                 Eigen::VectorXd& v_np1, StepContactStats& stats) override;
  void finish_step(const Eigen::VectorXd& u_n, const Eigen::VectorXd& u_np1, Eigen::VectorXd& v_np1,
                   StepContactStats& stats) override;
  [[nodiscard]] double next_step(std::int64_t, double full, double, double) const override { return full; }
  void allow_splits(bool) override {}
  [[nodiscard]] std::string save() const override;
  void load(const std::string& bytes, const std::string& what) override;
  [[nodiscard]] std::vector<ContactForce<D>> contact_forces() const override { return forces_; }
  /// "penalty[p]": ε of pair p [Pa/m].
  [[nodiscard]] std::vector<std::pair<std::string, double>> settings() const override;

  /// ε of pair p [Pa/m].
  [[nodiscard]] double penalty(int p) const { return epsilon_[static_cast<std::size_t>(p)]; }
  /// The force ∂Φ/∂u of the couplings over the step u_n → u (added to g)
  /// and, if K is given, its derivative by u (added at K's entries, which
  /// must be in its pattern).
  void add_force(const std::vector<PenaltyCoupling>& couplings, const Eigen::VectorXd& u_n, const Eigen::VectorXd& u,
                 Eigen::VectorXd& g, Eigen::VectorXd* magnitude, SparseMatrix* K) const;
  /// The bodies' pattern (that of K) with the blocks of `couplings`
  /// added; grows the kept pattern if needed. Returns the kept pattern
  /// (explicit zeros) and, in `from_K`, where each of K's entries lies in it.
  const SparseMatrix& pattern(const SparseMatrix& K, const std::vector<PenaltyCoupling>& couplings,
                              const std::vector<int>*& from_K, int& builds);

 private:
  /// Slaves behind a master facet at u, each with the facet the search
  /// gives (the step from x_n).
  [[nodiscard]] std::vector<PenaltyCoupling> behind_at(const Eigen::VectorXd& u);
  [[nodiscard]] Positions<D> positions(const Eigen::VectorXd& u) const {
    return model_.X + u.reshaped(D, model_.X.cols());
  }
  [[nodiscard]] Eigen::Matrix<double, D, D + 1> nodes(const PenaltyCoupling& c, const Positions<D>& x) const;
  /// Facet f of pair p's master and the facets sharing a node with it.
  [[nodiscard]] std::vector<int> around(int p, int f) const;
  /// The part of pair p's master nearest to slave s at x among around(p, f).
  [[nodiscard]] Feature<D> nearest(int p, int s, int f, const Positions<D>& x) const;
  /// Coulomb's μ of a spring's pair: its anchor slips when the spring's
  /// force leaves the cone (infinite: a stick spring, or none).
  [[nodiscard]] double friction(const PenaltyCoupling& c) const {
    return collisions_.pair(c.pair).friction.value_or(std::numeric_limits<double>::infinity());
  }
  /// A frictionless coupling's potential on `feature` at x [J].
  [[nodiscard]] double potential(const PenaltyCoupling& c, const Feature<D>& feature, const Positions<D>& x) const;
  /// A Coulomb coupling whose slave's projection left its facet at x: to
  /// the facet around it that holds the projection, its spring's anchor
  /// placed so that the spring keeps its length and direction in the
  /// new facet's plane (its energy). False if none holds it.
  bool move_anchor(PenaltyCoupling& c, const Positions<D>& x) const;
  /// How coupling c is evaluated over the step x_n → x.
  [[nodiscard]] StepPlan<D> plan(const PenaltyCoupling& c, const Positions<D>& x_n, const Positions<D>& x) const;

  const model::Model<D>& model_;
  CollisionSet<D> collisions_;
  std::vector<double> epsilon_;             ///< per pair [Pa/m]
  std::vector<std::map<int, double>> area_;  ///< per pair: slave node → its share of the slave surface [m²]
  bool conserving_;
  // The step under way.
  Eigen::VectorXd u_n_;
  Positions<D> x_n_;
  std::vector<PenaltyCoupling> pairing_;  ///< this pass's (empty before the first)
  // The state a step leaves (saved).
  std::vector<PenaltyCoupling> end_;  ///< couplings behind their facet at the last step's end
  double stored_ = 0.0;               ///< their energy [J]
  std::vector<ContactForce<D>> forces_;
  // The kept tangent pattern.
  std::vector<std::vector<int>> extra_;  ///< per node: the nodes it is coupled to beyond the bodies' pattern
  SparseMatrix pattern_;
  std::vector<int> from_K_;
  Eigen::Index K_nonzeros_ = -1;
};

}  // namespace conserve::contact
