#include "model/prescribed.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace conserve::model {

double Curve::at(double time) const {
  if (time <= t.front()) return value.front();
  if (time >= t.back()) return value.back();
  const auto k = static_cast<std::size_t>(std::upper_bound(t.begin(), t.end(), time) - t.begin()) - 1;
  const double s = (time - t[k]) / (t[k + 1] - t[k]);
  return value[k] + s * (value[k + 1] - value[k]);
}

double Curve::slope(double time) const {
  if (time < t.front() || time >= t.back()) return 0.0;
  const auto k = static_cast<std::size_t>(std::upper_bound(t.begin(), t.end(), time) - t.begin()) - 1;
  return (value[k + 1] - value[k]) / (t[k + 1] - t[k]);
}

double Curve::integral(double time) const {
  // ∫_0^time as ∫_{t_0}^time − ∫_{t_0}^0, each over the linear pieces
  // (and the constant ends).
  auto from_start = [&](double s) {
    if (s <= t.front()) return (s - t.front()) * value.front();
    double sum = 0.0;
    for (std::size_t k = 0; k + 1 < t.size() && t[k] < s; ++k) {
      const double end = std::min(s, t[k + 1]);
      sum += 0.5 * (end - t[k]) * (value[k] + at(end));
    }
    if (s > t.back()) sum += (s - t.back()) * value.back();
    return sum;
  };
  return from_start(time) - from_start(0.0);
}

void rigid_placement(const Prescribed& p, const RigidMotion& m, double t, Vec3& d, Mat3& R) {
  const double V = m.velocity_curve < 0 ? t : p.curves[m.velocity_curve].integral(t);
  const double W = m.omega_curve < 0 ? t : p.curves[m.omega_curve].integral(t);
  d = m.velocity * V;
  const double rate = m.omega.norm();
  R = rate > 0.0 ? Eigen::AngleAxisd(rate * W, m.omega / rate).toRotationMatrix() : Mat3::Identity();
}

template <int D>
void apply_prescribed(const Prescribed& p, const Eigen::Matrix<double, D, Eigen::Dynamic>& X, double t,
                      Eigen::VectorXd& u, Eigen::VectorXd* v) {
  for (std::size_t i = 0; i < p.dofs.size(); ++i) {
    const int c = p.curve.empty() ? -1 : p.curve[i];
    const double scale = c < 0 ? 1.0 : p.curves[c].at(t);
    u[p.dofs[i]] = p.value[i] * scale + p.rate[i] * t;
    if (!v) continue;
    (*v)[p.dofs[i]] = p.value[i] * (c < 0 ? 0.0 : p.curves[c].slope(t)) + p.rate[i];
  }
  for (const RigidMotion& m : p.rigid) {
    Vec3 d;
    Mat3 R;
    rigid_placement(p, m, t, d, R);
    const Vec3 velocity = m.velocity * (m.velocity_curve < 0 ? 1.0 : p.curves[m.velocity_curve].at(t));
    const Vec3 omega = m.omega * (m.omega_curve < 0 ? 1.0 : p.curves[m.omega_curve].at(t));
    for (int n = m.first_node; n < m.first_node + m.num_nodes; ++n) {
      Vec3 Xn = Vec3::Zero();
      Xn.head<D>() = X.col(n);
      const Vec3 arm = R * (Xn - m.center);  // x − c − d
      const Vec3 x = m.center + d + arm;
      u.segment<D>(n * D) = (x - Xn).head<D>();
      if (v) v->segment<D>(n * D) = (velocity + omega.cross(arm)).head<D>();
    }
  }
}

template void apply_prescribed<2>(const Prescribed&, const Eigen::Matrix<double, 2, Eigen::Dynamic>&, double,
                                  Eigen::VectorXd&, Eigen::VectorXd*);
template void apply_prescribed<3>(const Prescribed&, const Eigen::Matrix<double, 3, Eigen::Dynamic>&, double,
                                  Eigen::VectorXd&, Eigen::VectorXd*);

}  // namespace conserve::model
