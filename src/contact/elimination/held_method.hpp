#pragma once
/// What direct elimination and the Lagrange multipliers share: the same
/// held constraints (docs/theory.md, "Constraint methods"). The active set
/// (active_set.hpp) decides after each solve which slaves are held; the
/// push-outs' work and, with persistent contact, the slaves' relative
/// velocity are taken back after the step (persistent_velocity.hpp); the
/// constraints and their event times are the saved state. A method of
/// this family adds only how a solve holds them: its Coupling
/// (elimination/method.hpp, lagrange/method.hpp).
#include <memory>
#include <optional>

#include "contact/elimination/active_set.hpp"
#include "contact/elimination/held_statistics.hpp"
#include "contact/elimination/persistent_velocity.hpp"
#include "contact/elimination/tangent_reduction.hpp"
#include "contact/method.hpp"

namespace conserve::contact {

template <int D>
class HeldMethod : public Method<D> {
 public:
  /// `location` (onset > 0) locates impacts (ActiveSet::locate_impacts);
  /// `persistent` sets the active slaves' relative velocity to zero after
  /// each step. `mass` is the assembler's node_mass(); both must outlive the method.
  HeldMethod(const model::Model<D>& model, const SparseMatrix& mass, std::vector<ContactPair<D>> pairs,
             const ImpactLocation& location, bool persistent);

  [[nodiscard]] CollisionSet<D>& collisions() override { return active_.collisions(); }
  void begin_step(std::int64_t step, double dt, const model::State& start) override;
  [[nodiscard]] double split_fraction(const Eigen::VectorXd& u_n, const Eigen::VectorXd& u) override {
    return active_.split_fraction(u_n, u);
  }
  bool recover(const Eigen::VectorXd& u_n) override;
  Verdict settle(const model::State& start, double dt, const Eigen::VectorXd& u_np1, const Eigen::VectorXd& g,
                 Eigen::VectorXd& v_np1, StepContactStats& stats) override;
  void finish_step(const Eigen::VectorXd& u_n, const Eigen::VectorXd& u_np1, Eigen::VectorXd& v_np1,
                   StepContactStats& stats) override;
  [[nodiscard]] double next_step(std::int64_t step, double full, double last, double previous) const override {
    return active_.release_step(step, full, last, previous);
  }
  void allow_splits(bool allow) override { active_.allow_splits(allow); }
  [[nodiscard]] std::string save() const override;
  void load(const std::string& bytes, const std::string& what) override;
  [[nodiscard]] std::vector<ContactForce<D>> contact_forces() const override;
  [[nodiscard]] const std::vector<MethodStatistic>& statistics() const override { return held_statistics(); }

  /// The active set itself (tests).
  [[nodiscard]] ActiveSet<D>& active_set() { return active_; }

 protected:
  /// The elimination of the active constraints for one solve u_n → u
  /// (ActiveSet::elimination, with the kept tangent reduction).
  [[nodiscard]] std::unique_ptr<Elimination<D>> make_elimination(const Eigen::VectorXd& u_n,
                                                                 const Eigen::VectorXd& u) {
    return std::make_unique<Elimination<D>>(active_.elimination(u_n, u, reduction_));
  }
  /// Δt of the step under way.
  [[nodiscard]] double step_length() const { return dt_; }

 private:
  /// Coulomb friction of the accepted solve u_n → u_np1: its dissipation
  /// and the sticking and slipping slaves (StepContactStats).
  void friction(const Eigen::VectorXd& u_n, const Eigen::VectorXd& u_np1, StepContactStats& stats) const;

  const model::Model<D>& model_;
  ActiveSet<D> active_;
  /// The reduced tangent's pattern, kept across passes and steps while the
  /// constraints' nodes do not change.
  std::shared_ptr<TangentReduction<D>> reduction_ = std::make_shared<TangentReduction<D>>();
  /// Takes the work of pushed-out slaves' forces back (Constraint::push).
  PersistentVelocity<D> restorer_;
  std::optional<PersistentVelocity<D>> persistent_;
  /// The constraints' forces at the last step's end (contact_forces), in
  /// their order, with the work and the persistency impulses of the step.
  std::vector<ContactForce<D>> forces_;
  HeldCounts counts_;        ///< the step's own statistics (held_statistics.hpp)
  double end_time_ = 0.0;  ///< t_{n+1} of the step under way
  double dt_ = 0.0;        ///< its length
};

}  // namespace conserve::contact
