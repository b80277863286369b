#pragma once
/// The start of a step's Newton iteration. The step's solution does not
/// depend on it; the iterations to reach it do.
#include <vector>

#include "model/model.hpp"

namespace conserve::time {

/// How Newton's start u⁰_{n+1} is predicted from (u_n, V_n).
enum class Predictor {
  /// u_n + Δt V_n + ½Δt² g.
  velocity,
  /// u_n + Δt V_rigid + ½Δt² g, V_rigid each free body's rigid part of
  /// V_n (RigidMotion). The mid-point step all but reverses a vibration
  /// whose period is far below Δt (ωΔt ≫ 1), so carrying it forward, as
  /// `velocity` does, starts Newton a vibration amplitude away; its rigid
  /// motion the step does carry (bench/README.md, "Predictors").
  rigid,
};

/// The rigid part of a velocity field, body by body: the velocity
/// v_c + ω × (x_A − c) closest to V in the lumped-mass norm Σ m_A |·|²,
/// at the current positions x = X + u (c the centre of mass). It keeps
/// the body's linear momentum Σ m_A V_A and its angular momentum about c
/// with the lumped masses, and a rigid field is its own rigid part. In 2D
/// ω is normal to the plane. Bodies with a prescribed component, or
/// without mass (bare surfaces), keep V as it is: their motion is not a
/// free body's.
template <int D>
class RigidMotion {
 public:
  /// `node_mass`: the lumped mass per node [kg], the row sums of the
  /// mass matrix (with a consistent mass the fit keeps the body's exact
  /// linear momentum and a lumped approximation of its angular one).
  RigidMotion(const model::Model<D>& model, Eigen::VectorXd node_mass);

  /// Replaces V on each free body by its rigid part.
  void project(const Eigen::VectorXd& u, Eigen::VectorXd& v) const;

 private:
  const model::Model<D>& model_;
  Eigen::VectorXd node_mass_;
  std::vector<bool> free_;  ///< per body
};

}  // namespace conserve::time
