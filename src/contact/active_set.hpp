#pragma once
/// The active set (ALGORITHM.md §7): after each converged solve of a step,
/// release the constraints whose slave pulls on its master (f_N = g_s·n < 0,
/// (46)/(65)) and activate the slaves found behind a master facet
/// (g_N,n+1 < 0), their projection taken on the mid-point configuration.
/// The caller solves the step again while the set changes.
#include <vector>

#include "contact/constraint.hpp"
#include "model/model.hpp"

namespace conserve::contact {

/// What happened to the active set during one step.
struct StepContactStats {
  int passes = 0;                ///< solves of the step
  int activations = 0;
  int releases = 0;
  double max_activation_gap = 0.0;  ///< largest g_N(t_n) of a slave activated in the step [m]
};

template <int D>
class ActiveSet {
 public:
  ActiveSet(const model::Model<D>& model, std::vector<ContactPair<D>> pairs);

  [[nodiscard]] bool empty() const { return pairs_.empty(); }
  [[nodiscard]] const std::vector<Constraint<D>>& constraints() const { return active_; }
  [[nodiscard]] const std::vector<ContactPair<D>>& pairs() const { return pairs_; }
  /// Normal force f_N = g_s·n_{n+½} of each constraint after the last update [N].
  [[nodiscard]] const std::vector<double>& normal_forces() const { return normal_forces_; }

  /// Starts a step: forgets which slaves were released in the previous one.
  void begin_step() { released_.assign(released_.size(), 0); }

  /// After a converged solve of u_n → u_{n+1} with full residual g: updates
  /// the set; true if it changed (then solve the step again).
  bool update(const Eigen::VectorXd& u_n, const Eigen::VectorXd& u_np1, const Eigen::VectorXd& g,
              StepContactStats& stats);

  /// Replaces the active set (restoring a checkpoint or a failed step's
  /// start, or taking back the slave updates of a solve); the per-node
  /// flags follow, the normal forces are zero until the next update.
  void set_constraints(std::vector<Constraint<D>> constraints);

 private:
  bool release_tensile(const Positions<D>& x_mid, const Eigen::VectorXd& g, StepContactStats& stats);
  bool activate_penetrating(const Positions<D>& x_n, const Positions<D>& x_np1, StepContactStats& stats);
  [[nodiscard]] Positions<D> positions(const Eigen::VectorXd& u) const;

  const model::Model<D>& model_;
  std::vector<ContactPair<D>> pairs_;
  std::vector<Constraint<D>> active_;
  std::vector<double> normal_forces_;
  std::vector<char> is_active_;   ///< per node: slave of an active constraint
  std::vector<char> released_;    ///< per node: released during this step
  std::vector<char> prescribed_;  ///< per node: some dof prescribed (never a slave)
};

}  // namespace conserve::contact
