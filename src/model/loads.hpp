#pragma once
/// Surface loads on a body's boundary facets (issue 47): a nominal
/// traction (force per reference area, fixed direction: conservative) or a
/// follower pressure (along the current normal: not conservative), each
/// optionally scaled by a curve. Plain data, built by simulation/setup.
#include <Eigen/Core>

#include "core/types.hpp"

namespace conserve::model {

struct SurfaceLoad {
  enum class Kind { traction, pressure };
  Kind kind = Kind::traction;
  int body = -1;
  Eigen::MatrixXi facets;          ///< NF × n global nodes (NF = D, or 3 | 6 for P2), outward oriented
  Vec3 traction = Vec3::Zero();    ///< nominal traction [Pa] (traction)
  double pressure = 0.0;           ///< [Pa], positive pushing into the body (pressure)
  int curve = -1;                  ///< index into Prescribed::curves; −1: constant
  double thickness = 1.0;          ///< 2D: the body's out-of-plane size [m]

  /// Conservative: a constant nominal traction, whose potential −F·u is
  /// counted in `potential`; the others' work is counted in `load_work`.
  [[nodiscard]] bool conservative() const { return kind == Kind::traction && curve < 0; }
};

}  // namespace conserve::model
