#pragma once
/// The state of a run at one instant: flat node-major vectors.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

namespace conserve::model {

/// The motion of a free rigid body (time/free_bodies.hpp): its nodes are at
/// x = center + rotation (X − the reference centre), moving at
/// velocity + spin × (x − center). In 2D, rotation and spin are about z.
struct RigidBodyState {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();    ///< its centre of mass [m]
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  ///< [m/s]
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d spin = Eigen::Vector3d::Zero();  ///< angular velocity ω, spatial [rad/s]
};

struct State {
  std::int64_t step = 0;  ///< steps since t = 0 (64-bit: long runs pass 2^31 steps)
  double time = 0.0;      ///< [s]
  Eigen::VectorXd u;      ///< displacements from the reference configuration [m]
  Eigen::VectorXd v;      ///< velocities [m/s]
  /// Work done on the bodies since t = 0 by the loads that have no
  /// potential (curves, follower pressure) [J]: E − load_work is conserved.
  double load_work = 0.0;
  /// Per support (Prescribed::supports), the work its prescribed motion
  /// has done on the bodies since t = 0 [J]: E − load_work − Σ support_work
  /// is conserved.
  std::vector<double> support_work;
  /// Energy contact let go of outside the steps' balance since t = 0 (a
  /// penalty's released springs) [J]: counted with E in the drift.
  double released = 0.0;
  /// Energy Coulomb friction has dissipated since t = 0 [J]: counted with
  /// E in the drift (E + dissipated is conserved).
  double dissipated = 0.0;
  /// The free rigid bodies' motions (Model::free_bodies, in order).
  std::vector<RigidBodyState> rigid;
};

}  // namespace conserve::model
