#pragma once
/// The step's residual as a sum of terms (paper (19)–(20)):
///   g(u_{n+1}) = (2/Δt²) M Δu − (2/Δt) M V_n   inertia
///              + f_int(u_n, u_{n+1})           internal force, (17)
///              − f_ext                         body force (gravity), surface loads
/// Each term gives its value and its derivative by u_{n+1}; the tangent is
/// the sum of the derivatives. Contact is not a term: a constraint method's
/// coupling (contact/method.hpp) forms the Newton system from the sum
/// (elimination reduces it, a penalty adds its forces in a grown pattern,
/// multipliers add unknowns).
#include <memory>
#include <string_view>
#include <vector>

#include "assembly/assembler.hpp"
#include "model/state.hpp"

namespace conserve::time {

template <int D>
class StepTerm {
 public:
  virtual ~StepTerm() = default;
  [[nodiscard]] virtual std::string_view name() const = 0;
  /// Starts the step from `start` (u_n, V_n) with step size Δt [s]: what
  /// every evaluation of the step shares is computed here, once.
  virtual void begin(const model::State& start, double dt) = 0;
  /// The norm of the term's force at the start of the step [N]: a scale
  /// for the residual.
  [[nodiscard]] virtual double start_force() const = 0;
  /// The term's energy at the start of the step (kinetic, stored, or the
  /// work of a constant force, in absolute value) [J]: a scale for the
  /// work a residual can do.
  [[nodiscard]] virtual double start_energy() const = 0;
  /// g += the term's value at u_{n+1}; magnitude += the magnitudes of the
  /// summands it is made of (what a sum cancels: ε times it bounds the
  /// value's round-off) [N].
  virtual void add_value(const Eigen::VectorXd& u_np1, Eigen::VectorXd& g, Eigen::VectorXd& magnitude) = 0;
  /// K += ∂(value)/∂u_{n+1}; K has the assembler's pattern.
  virtual void add_derivative(const Eigen::VectorXd& u_np1, SparseMatrix& K) = 0;
  /// add_value() and add_derivative() at once (a term whose value and
  /// derivative share their work does both in one pass): the same bits.
  virtual void add_value_and_derivative(const Eigen::VectorXd& u_np1, Eigen::VectorXd& g, Eigen::VectorXd& magnitude,
                                        SparseMatrix& K) {
    add_value(u_np1, g, magnitude);
    add_derivative(u_np1, K);
  }
  /// The work over the step to u_{n+1} of the term's external forces that
  /// have no potential (model::State::load_work) [J].
  [[nodiscard]] virtual double external_work(const Eigen::VectorXd&) const { return 0.0; }
};

template <int D>
using StepTerms = std::vector<std::unique_ptr<StepTerm<D>>>;

/// (2/Δt²) M (u_{n+1} − u_n) − (2/Δt) M V_n: M (V_{n+1} − V_n)/Δt with
/// V_{n+1} = (2/Δt)Δu − V_n (19). Derivative (2/Δt²) M.
template <int D>
class Inertia final : public StepTerm<D> {
 public:
  explicit Inertia(const assembly::Assembler<D>& assembler) : assembler_(assembler) {}
  [[nodiscard]] std::string_view name() const override { return "inertia"; }
  void begin(const model::State& start, double dt) override;
  [[nodiscard]] double start_force() const override { return momentum_.norm(); }
  [[nodiscard]] double start_energy() const override { return kinetic_; }
  void add_value(const Eigen::VectorXd& u_np1, Eigen::VectorXd& g, Eigen::VectorXd& magnitude) override;
  void add_derivative(const Eigen::VectorXd& u_np1, SparseMatrix& K) override;

 private:
  const assembly::Assembler<D>& assembler_;
  Eigen::VectorXd u_n_;
  double c_ = 0.0;            ///< 2/Δt² [1/s²]
  Eigen::VectorXd momentum_;  ///< (2/Δt) M V_n [N]
  Eigen::VectorXd momentum_magnitude_;  ///< (2/Δt) M |V_n| + c M |u_n| [N]
  double kinetic_ = 0.0;
};

/// f_int(u_n, u_{n+1}) of the chosen stress scheme, (17) (conserving: S
/// from the mid-point strain, Gonzalez's correction; docs/theory.md,
/// "The conserving step (18)–(26)").
/// Derivative: the element tangents.
template <int D>
class InternalForce final : public StepTerm<D> {
 public:
  InternalForce(const assembly::Assembler<D>& assembler, fem::StressScheme scheme)
      : assembler_(assembler), scheme_(scheme) {}
  [[nodiscard]] std::string_view name() const override { return "internal force"; }
  void begin(const model::State& start, double dt) override;
  [[nodiscard]] double start_force() const override { return start_force_; }
  [[nodiscard]] double start_energy() const override { return stored_; }
  void add_value(const Eigen::VectorXd& u_np1, Eigen::VectorXd& g, Eigen::VectorXd& magnitude) override;
  void add_derivative(const Eigen::VectorXd& u_np1, SparseMatrix& K) override;
  /// One pass over the cells.
  void add_value_and_derivative(const Eigen::VectorXd& u_np1, Eigen::VectorXd& g, Eigen::VectorXd& magnitude,
                                SparseMatrix& K) override;

 private:
  /// The round-off magnitudes add_value() adds beyond the cells' forces.
  void add_round_off(const Eigen::VectorXd& u_np1, Eigen::VectorXd& magnitude) const;
  const assembly::Assembler<D>& assembler_;
  fem::StressScheme scheme_;
  std::shared_ptr<const typename assembly::Assembler<D>::StepStart> cells_n_;  ///< each cell's F_n
  double start_force_ = 0.0, stored_ = 0.0;
};

/// −f_ext: the constant gravity force f_A = Σ_B M_AB g. No derivative.
template <int D>
class BodyForce final : public StepTerm<D> {
 public:
  explicit BodyForce(const assembly::Assembler<D>& assembler) : assembler_(assembler) {}
  [[nodiscard]] std::string_view name() const override { return "body force"; }
  void begin(const model::State& start, double dt) override;
  [[nodiscard]] double start_force() const override { return assembler_.gravity_force().norm(); }
  [[nodiscard]] double start_energy() const override { return work_; }
  void add_value(const Eigen::VectorXd& u_np1, Eigen::VectorXd& g, Eigen::VectorXd& magnitude) override;
  void add_derivative(const Eigen::VectorXd&, SparseMatrix&) override {}

 private:
  const assembly::Assembler<D>& assembler_;
  double work_ = 0.0;  ///< |f_ext · u_n| [J]
};

/// The terms of an elastodynamic step: inertia, internal force, body force.
template <int D>
[[nodiscard]] StepTerms<D> elastodynamic_terms(const assembly::Assembler<D>& assembler, fem::StressScheme scheme);

}  // namespace conserve::time
