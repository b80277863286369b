#pragma once
/// Initial conditions of a body: an affine deformation about its centroid,
/// a uniform velocity and a rigid spin about its centre of mass.
#include "model/model.hpp"
#include "model/state.hpp"

namespace conserve::model {

struct InitialMotion {
  Mat3 deformation = Mat3::Identity();   ///< F0: u0 = (F0 − 1)(X − c); 2D uses the upper 2×2
  Vec3 velocity = Vec3::Zero();          ///< [m/s]
  Vec3 angular_velocity = Vec3::Zero();  ///< [rad/s] about the deformed centre of mass (2D: z)
};

/// A state at rest in the reference configuration at t = 0.
template <int D>
State rest_state(const Model<D>& model);

/// Sets u and v of the nodes of body `body`: u = (F0 − 1)(X − c),
/// v = v0 + ω × (x − c'), x = X + u, c' the deformed centroid.
template <int D>
void set_initial_motion(const Model<D>& model, int body, const InitialMotion& motion, State& state);

/// Volume-weighted centroid of a body's cells at displacements u.
template <int D>
Vec<D> body_centroid(const Model<D>& model, int body, const Eigen::VectorXd& u);

}  // namespace conserve::model
