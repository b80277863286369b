#pragma once
/// Direct elimination (the paper's method) behind the constraint-method
/// interface: the active set (active_set.hpp) decides which slaves are
/// held, the elimination (elimination.hpp) reduces each solve's system to
/// the unknowns the constraints leave, and the push-outs' work and, with
/// persistent contact, the slaves' relative velocity are taken back after
/// the step (persistent_velocity.hpp). docs/theory.md, "The step with contact".
#include <memory>
#include <optional>

#include "contact/elimination/active_set.hpp"
#include "contact/elimination/persistent_velocity.hpp"
#include "contact/elimination/tangent_reduction.hpp"
#include "contact/method.hpp"

namespace conserve::contact {

/// One solve's direct elimination as a coupling: Δu = T q, r = Wᵀ g,
/// K_r = Wᵀ K T + V + β ((41), (43), (56), (58)); without an active
/// constraint, the bodies' system as it is.
template <int D>
class EliminationCoupling final : public Coupling {
 public:
  /// Owns the elimination.
  explicit EliminationCoupling(std::unique_ptr<Elimination<D>> elimination)
      : owned_(std::move(elimination)), e_(owned_.get()) {}
  /// Works on the caller's elimination, which must outlive it (tests).
  explicit EliminationCoupling(Elimination<D>& elimination) : e_(&elimination) {}
  [[nodiscard]] bool plain() const override { return e_->empty(); }
  [[nodiscard]] int equations(int dofs) const override {
    for (const auto& c : e_->constraints()) dofs -= c.kind == Kind::stick ? D : 1;
    return dofs;
  }
  void start(Eigen::VectorXd& u) override {
    if (!plain()) e_->enforce(u);
  }
  void residual(const Eigen::VectorXd&, Eigen::VectorXd& g, Eigen::VectorXd&, Eigen::VectorXd& r) override {
    if (plain())
      r = g;
    else
      e_->reduce_residual(g, r);  // (41), (56)
  }
  bool tangent(const Eigen::VectorXd&, const SparseMatrix& K, const Eigen::VectorXd& g, SparseMatrix& A) override {
    return e_->reduce_tangent(K, g, A);  // (43), (58)
  }
  void update(const Eigen::VectorXd& increment, Eigen::VectorXd& u) override {
    if (plain())
      u += increment;
    else
      e_->update(increment, u);  // (45), (60)–(64)
  }
  void save() override {
    if (!plain()) e_->save(saved_);
  }
  bool restore() override {
    if (plain()) return true;
    if (!saved_) return false;
    e_->restore(*saved_);
    return true;
  }

 private:
  std::unique_ptr<Elimination<D>> owned_;
  Elimination<D>* e_;
  std::optional<typename Elimination<D>::Saved> saved_;
};

template <int D>
class EliminationMethod : public Method<D> {
 public:
  /// `location` (onset > 0) locates impacts (ActiveSet::locate_impacts);
  /// `persistent` sets the active slaves' relative velocity to zero after
  /// each step. `mass` is the assembler's; both must outlive the method.
  EliminationMethod(const model::Model<D>& model, const SparseMatrix& mass, std::vector<ContactPair<D>> pairs,
                    const ImpactLocation& location, bool persistent);

  [[nodiscard]] std::string_view name() const override { return "elimination"; }
  [[nodiscard]] CollisionSet<D>& collisions() override { return active_.collisions(); }
  void begin_step(std::int64_t step, double dt, const model::State& start) override;
  [[nodiscard]] std::unique_ptr<Coupling> coupling(const Eigen::VectorXd& u_n, const Eigen::VectorXd& u_np1) override;
  [[nodiscard]] double split_fraction(const Eigen::VectorXd& u_n, const Eigen::VectorXd& u) override {
    return active_.split_fraction(u_n, u);
  }
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

  /// The active set itself (tests).
  [[nodiscard]] ActiveSet<D>& active_set() { return active_; }

 protected:
  /// The elimination of the active constraints for one solve u_n → u
  /// (ActiveSet::elimination, with the kept tangent reduction).
  [[nodiscard]] std::unique_ptr<Elimination<D>> make_elimination(const Eigen::VectorXd& u_n,
                                                                 const Eigen::VectorXd& u) {
    return std::make_unique<Elimination<D>>(active_.elimination(u_n, u, reduction_));
  }

 private:
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
  double end_time_ = 0.0;  ///< t_{n+1} of the step under way
};

}  // namespace conserve::contact
