#pragma once
/// Direct elimination (the paper's method) behind the constraint-method
/// interface: the constraints held as every method of the family holds
/// them (held_method.hpp), each solve's system reduced to the unknowns
/// they leave (elimination.hpp). docs/theory.md, "The step with contact".
#include <memory>
#include <optional>

#include "contact/elimination/held_method.hpp"

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
class EliminationMethod final : public HeldMethod<D> {
 public:
  using HeldMethod<D>::HeldMethod;
  [[nodiscard]] std::string_view name() const override { return "elimination"; }
  [[nodiscard]] std::unique_ptr<Coupling> coupling(const Eigen::VectorXd& u_n, const Eigen::VectorXd& u_np1) override {
    // The elimination works on the active set's constraints: the updates of
    // the solve move their facets, ξ, n and τ there.
    return std::make_unique<EliminationCoupling<D>>(this->make_elimination(u_n, u_np1));
  }
};

}  // namespace conserve::contact
