#pragma once
/// Prescribed motion: load curves, prescribed displacement components
/// ([[boundary]]) and the rigid motions of rigid bodies, evaluated at a
/// time. Plain data (built by simulation/setup) and their evaluation.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/types.hpp"

namespace conserve::model {

/// A load curve: piecewise linear through (t_k, c_k), t strictly
/// increasing, constant beyond the first and the last point.
struct Curve {
  std::vector<double> t, value;
  /// c(time).
  [[nodiscard]] double at(double time) const;
  /// c'(time), the right derivative at a point (0 beyond the last).
  [[nodiscard]] double slope(double time) const;
  /// ∫_0^time c(s) ds (exact for the piecewise linear c; negative for time < 0).
  [[nodiscard]] double integral(double time) const;
};

/// A rigid body's motion: its nodes move as
///   x(t) = c + d(t) + R(θ(t)) (X − c),  d = velocity · V(t),  θ = |ω| W(t),
/// R the rotation about the fixed axis ω/|ω| (2D: about z), V and W the
/// integrals of the velocity's and the angular velocity's curves (t
/// without one).
struct RigidMotion {
  int first_node = 0, num_nodes = 0;
  Vec3 center = Vec3::Zero();    ///< c, the point it turns about, at t = 0 [m]
  Vec3 velocity = Vec3::Zero();  ///< [m/s]
  Vec3 omega = Vec3::Zero();     ///< angular velocity ω [rad/s]; 2D: z only
  int velocity_curve = -1;       ///< index into Prescribed::curves; −1: none
  int omega_curve = -1;
};

/// What holds or drives a set of prescribed dofs: a [[boundary]] group
/// ("BODY:GROUP"; the boundaries of one group merged) or a rigid body (its
/// name). Its reaction and work are reported (time/integrator.hpp).
struct Support {
  std::string name;
  std::vector<int> entries;  ///< indices into Prescribed::dofs
};

/// Prescribed degrees of freedom: u[dofs[i]](t) = value[i] · c(t) + rate[i] · t
/// (c the dof's curve, 1 without one), except the dofs of rigid motions,
/// which follow their motion.
struct Prescribed {
  std::vector<int> dofs;
  std::vector<double> value;  ///< [m]
  std::vector<double> rate;   ///< [m/s]
  std::vector<int> curve;     ///< per dof: index into `curves`, −1 none
  std::vector<Curve> curves;
  std::vector<RigidMotion> rigid;
  /// Every dof belongs to one support; supports in the scenario's order
  /// (boundaries, then rigid bodies).
  std::vector<Support> supports;
};

/// Sets the prescribed dofs of u (and of v, if given, to their exact
/// velocity) at time t; X are the model's reference coordinates (D × n).
template <int D>
void apply_prescribed(const Prescribed& p, const Eigen::Matrix<double, D, Eigen::Dynamic>& X, double t,
                      Eigen::VectorXd& u, Eigen::VectorXd* v = nullptr);

/// The displacement (d(t), the rotation matrix R(θ(t))) of rigid motion m at time t.
void rigid_placement(const Prescribed& p, const RigidMotion& m, double t, Vec3& d, Mat3& R);

}  // namespace conserve::model
