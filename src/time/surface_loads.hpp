#pragma once
/// −f_ext of the surface loads (model/loads.hpp) and of a gravity that
/// follows a curve, as a step term (time/step_terms.hpp). A load's curve
/// is taken at the step's mid-point time; a follower pressure acts on the
/// facets' mid-point configuration, f_a = −p ∫ N_a n da at x_{n+½}, and a
/// nominal traction gives f_a = t ∫ N_a dA_0 (fem/facet_integrals.hpp: A/D
/// per node of a P1 facet, the integral of the quadratic shape functions on
/// a P2 one). The pressures' rule is exact, so on a closed surface they
/// have no resultant and no moment (∮ n da = 0, ∮ x × n da = 0) and L and J
/// are kept. The work f·Δu of the loads without a potential is counted
/// (external_work).
#include "time/step_terms.hpp"

namespace conserve::time {

template <int D>
class SurfaceLoads final : public StepTerm<D> {
 public:
  explicit SurfaceLoads(const assembly::Assembler<D>& assembler);
  [[nodiscard]] std::string_view name() const override { return "surface loads"; }
  void begin(const model::State& start, double dt) override;
  [[nodiscard]] double start_force() const override { return start_force_; }
  [[nodiscard]] double start_energy() const override { return start_energy_; }
  void add_value(const Eigen::VectorXd& u_np1, Eigen::VectorXd& g, Eigen::VectorXd& magnitude) override;
  void add_derivative(const Eigen::VectorXd& u_np1, SparseMatrix& K) override;
  [[nodiscard]] double external_work(const Eigen::VectorXd& u_np1) const override;

 private:
  /// The loads' nodal forces at u_{n+1} (pressures at the mid-point); only
  /// the non-conservative ones if `work_only`.
  [[nodiscard]] Eigen::VectorXd force(const Eigen::VectorXd& u_np1, bool work_only) const;
  const assembly::Assembler<D>& assembler_;
  std::vector<Eigen::VectorXd> traction_;  ///< each traction's nodal forces at factor 1 [N] (empty for pressures)
  Eigen::VectorXd u_n_;
  std::vector<double> factor_;  ///< each load's curve at the step's mid-point time
  double gravity_factor_ = 1.0;
  double start_force_ = 0.0, start_energy_ = 0.0;
};

/// The nodal forces of a constant nominal traction (∫ N_a dA_0 on the
/// reference facets), the conservative loads' potential −F·u's F.
template <int D>
Eigen::VectorXd conservative_load(const model::Model<D>& model);

}  // namespace conserve::time
