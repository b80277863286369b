#pragma once
/// The state of a run at one instant: flat node-major vectors.
#include <Eigen/Core>

namespace conserve::model {

struct State {
  int step = 0;
  double time = 0.0;  ///< [s]
  Eigen::VectorXd u;  ///< displacements from the reference configuration [m]
  Eigen::VectorXd v;  ///< velocities [m/s]
};

}  // namespace conserve::model
