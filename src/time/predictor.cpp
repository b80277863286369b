#include "time/predictor.hpp"

#include <utility>

namespace conserve::time {

template <int D>
RigidMotion<D>::RigidMotion(const model::Model<D>& model, Eigen::VectorXd node_mass)
    : model_(model), node_mass_(std::move(node_mass)), free_(model.bodies.size(), true) {
  std::vector<int> body_of(model.num_nodes(), -1);
  for (std::size_t b = 0; b < model.bodies.size(); ++b) {
    const auto& body = model.bodies[b];
    for (int n = body.first_node; n < body.first_node + body.num_nodes; ++n) body_of[n] = static_cast<int>(b);
    if (!(node_mass_.segment(body.first_node, body.num_nodes).sum() > 0.0)) free_[b] = false;
  }
  for (int dof : model.prescribed.dofs)
    if (const int b = body_of[dof / D]; b >= 0) free_[b] = false;
}

template <int D>
void RigidMotion<D>::project(const Eigen::VectorXd& u, Eigen::VectorXd& v) const {
  for (std::size_t b = 0; b < model_.bodies.size(); ++b) {
    if (!free_[b]) continue;
    const auto& body = model_.bodies[b];
    const int first = body.first_node, last = body.first_node + body.num_nodes;
    // In 3D throughout: in 2D the third components are zero and ω = ω_z e_z.
    auto position = [&](int n) {
      Vec3 x = Vec3::Zero();
      x.head<D>() = model_.X.col(n) + u.segment<D>(n * D);
      return x;
    };
    auto velocity = [&](int n) {
      Vec3 x = Vec3::Zero();
      x.head<D>() = v.segment<D>(n * D);
      return x;
    };
    double mass = 0.0;
    Vec3 c = Vec3::Zero(), p = Vec3::Zero();
    for (int n = first; n < last; ++n) {
      mass += node_mass_[n];
      c += node_mass_[n] * position(n);
      p += node_mass_[n] * velocity(n);
    }
    c /= mass;
    const Vec3 v_c = p / mass;
    // ω solves I ω = J: the normal equations of the least-squares fit.
    Mat3 inertia = Mat3::Zero();
    Vec3 spin = Vec3::Zero();
    for (int n = first; n < last; ++n) {
      const Vec3 r = position(n) - c;
      inertia += node_mass_[n] * (r.squaredNorm() * Mat3::Identity() - r * r.transpose());
      spin += node_mass_[n] * r.cross(velocity(n) - v_c);
    }
    Vec3 omega = Vec3::Zero();
    if constexpr (D == 3)
      omega = inertia.ldlt().solve(spin);  // LDLT leaves a zero pivot's component at 0
    else if (inertia(2, 2) > 0.0)
      omega.z() = spin.z() / inertia(2, 2);
    for (int n = first; n < last; ++n) v.segment<D>(n * D) = (v_c + omega.cross(position(n) - c)).template head<D>();
  }
}

template class RigidMotion<2>;
template class RigidMotion<3>;

}  // namespace conserve::time
