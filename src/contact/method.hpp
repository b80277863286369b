#pragma once
/// A constraint method: how contact takes part in the time step, whatever
/// the method (issue 46). The integrator and the stepper see only this;
/// each method is one folder (elimination/, penalty/) registered in
/// methods.cpp. Per step: begin_step(), then per solve ("pass") a Coupling
/// that forms the Newton system from the bodies' residual and tangent,
/// settle() after the solve (accept, solve again, or split the step), and
/// finish_step() once the step is taken. A method owns its state; one
/// serialisation (save/load) serves both the stepper's retries and the
/// checkpoints.
#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "contact/collision_set.hpp"
#include "core/statistic.hpp"
#include "core/types.hpp"
#include "io/scenario.hpp"
#include "model/state.hpp"

namespace conserve::contact {

/// A statistic a method reports besides StepContactStats' common ones,
/// declared by the method (Method::statistics): its history.csv column
/// (empty: summary.json only) and its run values; its value for a step is
/// the matching entry of StepContactStats::own.
struct MethodStatistic {
  std::string_view column;
  std::vector<RunValue> summary = {};
};

/// What contact did during one step, and its geometry at the step's end:
/// the figures every method reports (those it has no use for stay 0), and
/// the values of the statistics it declares for itself.
struct StepContactStats {
  int passes = 0;  ///< solves of the step
  int activations = 0;
  int releases = 0;
  /// < 1: the step met an impact and was not taken; end it at this
  /// fraction of its length instead (Method::settle says split).
  double split_fraction = 1.0;
  /// Earlier attempts of the step given up to end it at an impact, and the
  /// solves (passes) they took (set by the stepper).
  int splits = 0;
  int split_passes = 0;
  /// At the end of the step: the deepest slave behind a master facet,
  /// active or not (0 if none), the deepest master node behind a slave
  /// facet (0 if none), and the extreme gaps of the active slaves (NaN if
  /// none) [m].
  double slave_penetration = 0.0;
  double master_penetration = 0.0;
  double min_active_gap = std::numeric_limits<double>::quiet_NaN();
  double max_active_gap = std::numeric_limits<double>::quiet_NaN();
  /// Energy the method stores at the step's end (a penalty's springs; 0
  /// for constraints held exactly) [J]; part of the total energy.
  double contact_energy = 0.0;
  /// Energy a method let go of outside the step's balance [J]: a penalty
  /// stick spring's at its release, and the change of a penalty slave's
  /// potential when it moves to another facet between steps; 0 for the
  /// others. total + Σ contact_released is conserved.
  double contact_released = 0.0;
  /// Coulomb friction: the work the friction forces took out of the step
  /// (≥ 0), and the slaves of Coulomb pairs sticking and slipping at its
  /// end. E_{n+1} + dissipated = E_n.
  double dissipated = 0.0;
  int sticking = 0;
  int slipping = 0;
  /// Unknowns of the step's last linear system (prescribed and eliminated
  /// ones left out, multipliers counted).
  int equations = 0;
  /// The step's values of the method's own statistics, in the order of
  /// Method::statistics() (set by finish_step; empty before).
  std::vector<double> own;
};

/// What settle() decides after a converged solve.
enum class Verdict {
  accept,   ///< the solve is the step's
  changed,  ///< the contact state changed: solve the step again
  split,    ///< an impact within the step: end it at StepContactStats::split_fraction
};

/// One solve's contact: how the Newton system's residual, tangent and
/// unknowns are formed from the bodies' (the step's terms, time/step_terms.hpp).
/// Reduce/expand (elimination), added terms (penalty) and added unknowns
/// (multipliers) are all this.
class Coupling {
 public:
  virtual ~Coupling() = default;
  /// True when the system is the bodies' own (q = Δu, r = g, tangent K):
  /// a factorization of it may be reused.
  [[nodiscard]] virtual bool plain() const = 0;
  /// Unknowns of the system for `dofs` unknowns of the bodies (their free
  /// ones): fewer by the eliminated, more by the multipliers.
  [[nodiscard]] virtual int equations(int dofs) const = 0;
  /// Puts the method's constraints on the predictor u before the first
  /// residual (elimination: the slaves on their facets).
  virtual void start(Eigen::VectorXd& u) = 0;
  /// The system's residual r from the bodies' g at iterate u; `g` may be
  /// changed to the full force balance at u (a penalty adds its forces), and
  /// `magnitude` gets the magnitudes of what was added [N].
  virtual void residual(const Eigen::VectorXd& u, Eigen::VectorXd& g, Eigen::VectorXd& magnitude,
                        Eigen::VectorXd& r) = 0;
  /// The system's tangent from the bodies' K and the last residual's g at
  /// u, into A; true when A's pattern differs from the last call's.
  virtual bool tangent(const Eigen::VectorXd& u, const SparseMatrix& K, const Eigen::VectorXd& g,
                       SparseMatrix& A) = 0;
  /// u (and the method's own unknowns) advanced by the system's increment.
  virtual void update(const Eigen::VectorXd& increment, Eigen::VectorXd& u) = 0;
  /// Keeps, then takes back, the state update() moves (a line search's revert).
  virtual void save() = 0;
  virtual bool restore() = 0;
};

/// One contact's force on its slave node over the last step: the normal
/// part f_N along its master's normal n [N], and what the master gave the
/// slave over the step (the momentum and the work it transmitted, whose
/// opposite a prescribed master takes: simulation/output.cpp's reactions).
template <int D>
struct ContactForce {
  int slave = -1;  ///< global node
  double normal = 0.0;
  Vec<D> direction = Vec<D>::Zero();
  int pair = -1;                  ///< the contact pair (index of [[contact]])
  bool sticks = false;            ///< held where it is on its facet (stick, or Coulomb inside its cone); else slips
  Vec<D> force = Vec<D>::Zero();  ///< the mean force on the slave over the step [N]
  Vec3 moment = Vec3::Zero();     ///< its moment about the origin, at the slave's mid-point position [N m]
  double work = 0.0;              ///< its work on the slave over the step [J]
  Vec<D> impulse = Vec<D>::Zero();  ///< an impulse at the step's end (persistent contact) [N s]
  /// The master facet's nodes and the weights N_b(ξ) with which they took
  /// the opposite of `impulse` (a prescribed master's reaction).
  FacetIndex<D> master{};
  FacetWeights<D> weights = FacetWeights<D>::Zero(D);
};

/// a × b for D-vectors as a 3-vector (2D: along z).
template <int D>
Vec3 moment_of(const Vec<D>& a, const Vec<D>& b) {
  Vec3 a3 = Vec3::Zero(), b3 = Vec3::Zero();
  a3.template head<D>() = a;
  b3.template head<D>() = b;
  return a3.cross(b3);
}

template <int D>
class Method {
 public:
  virtual ~Method() = default;
  [[nodiscard]] virtual std::string_view name() const = 0;
  [[nodiscard]] virtual CollisionSet<D>& collisions() = 0;
  [[nodiscard]] const std::vector<ContactPair<D>>& pairs() { return collisions().pairs(); }

  /// Starts step `step` (its index once taken) of length dt from `start`.
  virtual void begin_step(std::int64_t step, double dt, const model::State& start) = 0;
  /// The coupling of one solve of the step u_n → u_np1 (the iterate).
  [[nodiscard]] virtual std::unique_ptr<Coupling> coupling(const Eigen::VectorXd& u_n,
                                                           const Eigen::VectorXd& u_np1) = 0;
  /// Where the step u_n → u should end for an impact it holds (1: none):
  /// asked of an unconverged iterate so that a doomed solve stops early.
  [[nodiscard]] virtual double split_fraction(const Eigen::VectorXd& u_n, const Eigen::VectorXd& u) = 0;
  /// After a converged solve u_n → u_np1 whose full force balance is `g`
  /// (unmasked; on a slave held by a constraint, its contact force):
  /// accept, solve again, or split. May set v_np1 (empty on entry) when it
  /// changes the velocity the step ends with (work taken back).
  virtual Verdict settle(const model::State& start, double dt, const Eigen::VectorXd& u_np1, const Eigen::VectorXd& g,
                         Eigen::VectorXd& v_np1, StepContactStats& stats) = 0;
  /// The step is taken, ending at u_np1 with velocities v_np1 (which the
  /// method may change: persistent contact): end-of-step figures in stats.
  virtual void finish_step(const Eigen::VectorXd& u_n, const Eigen::VectorXd& u_np1, Eigen::VectorXd& v_np1,
                           StepContactStats& stats) = 0;
  /// After a solve of the step from u_n that did not converge: whether the
  /// method changed its set so that the step is worth solving again at the
  /// same Δt, from its prediction (a Coulomb slave whose slip the solve
  /// could not settle sticks). False by default.
  virtual bool recover(const Eigen::VectorXd& u_n) {
    (void)u_n;
    return false;
  }

  /// The longest next step the method asks for after step `step` (of
  /// length `last`, after one of `previous`; `full` the scenario's).
  [[nodiscard]] virtual double next_step(std::int64_t step, double full, double last, double previous) const = 0;
  /// Whether settle() may ask for a split.
  virtual void allow_splits(bool allow) = 0;

  /// The method's state as bytes, and back: a failed attempt's retry and
  /// the checkpoints use the same. load() throws InputError naming `what`
  /// on bytes it cannot read.
  [[nodiscard]] virtual std::string save() const = 0;
  virtual void load(const std::string& bytes, const std::string& what) = 0;

  /// The statistics the method reports besides StepContactStats' common
  /// ones (their step values in StepContactStats::own), in history.csv's
  /// column order; none by default.
  [[nodiscard]] virtual const std::vector<MethodStatistic>& statistics() const {
    static const std::vector<MethodStatistic> none;
    return none;
  }
  /// The method's settings as it uses them (a penalty's ε per pair,
  /// automatic ones resolved), by name, for summary.json.
  [[nodiscard]] virtual std::vector<std::pair<std::string, double>> settings() const { return {}; }
  /// The contacts carrying force at the last step's end (or update).
  [[nodiscard]] virtual std::vector<ContactForce<D>> contact_forces() const = 0;
};

/// The value in `stats` of `method`'s own statistic with history column
/// `column` (throws std::out_of_range if the method declares none such).
template <int D>
double own_statistic(const Method<D>& method, const StepContactStats& stats, std::string_view column) {
  const std::vector<MethodStatistic>& declared = method.statistics();
  for (std::size_t i = 0; i < declared.size(); ++i)
    if (declared[i].column == column) return i < stats.own.size() ? stats.own[i] : 0.0;
  throw std::out_of_range("the contact method '" + std::string(method.name()) + "' reports no statistic '" +
                          std::string(column) + "'");
}

/// The method the scenario's [[contact]] `method` names, for `model` with
/// the contact `pairs` (built from the scenario's [[contact]] tables, in
/// order); each method reads its own keys of the scenario. `mass` is the
/// assembler's node_mass() (M_AB). Throws InputError on an unknown name.
template <int D>
std::unique_ptr<Method<D>> make_method(const io::Scenario& scenario, const model::Model<D>& model,
                                       const SparseMatrix& mass, std::vector<ContactPair<D>> pairs);
/// The registered methods' names.
[[nodiscard]] std::vector<std::string> method_names();

}  // namespace conserve::contact
