#include "model/initial_state.hpp"

namespace conserve::model {

template <int D>
State rest_state(const Model<D>& model) {
  State s;
  s.u.setZero(model.num_dofs());
  s.v.setZero(model.num_dofs());
  s.support_work.assign(model.prescribed.supports.size(), 0.0);
  return s;
}

namespace {

/// Mean of a body's nodal positions at displacements u (the centroid of a
/// body without cells, e.g. a rigid bare surface).
template <int D>
Vec<D> node_mean(const Model<D>& model, const Body& b, const Eigen::VectorXd& u) {
  Vec<D> sum = Vec<D>::Zero();
  for (int n = b.first_node; n < b.first_node + b.num_nodes; ++n) sum += model.X.col(n) + u.template segment<D>(n * D);
  return b.num_nodes > 0 ? Vec<D>(sum / b.num_nodes) : sum;
}

}  // namespace

/// A body without cells (no volume) has the mean of its nodes as centroid.
template <int D>
Vec<D> body_centroid(const Model<D>& model, int body, const Eigen::VectorXd& u) {
  const Body& b = model.bodies[body];
  if (b.num_cells == 0) return node_mean<D>(model, b, u);
  Vec<D> sum = Vec<D>::Zero();
  double volume = 0.0;
  if (model.order == 2) {  // ∫x dV / ∫dV by the mass rule (exact on straight-sided cells)
    using Shape = fem::Quadratic<D>::Shape;
    const auto rule = fem::quadrature<D, D == 2 ? 4 : 5>();
    for (int c = b.first_cell; c < b.first_cell + b.num_cells; ++c) {
      fem::QuadraticNodes<D> x;
      for (int a = 0; a < Shape::kNodes; ++a) {
        const int n = model.cells(a, c);
        x.col(a) = model.X.col(n) + u.template segment<D>(n * D);
      }
      for (int q = 0; q < rule.kPoints; ++q) {
        const double v = rule.weights[q] * fem::quadratic_jacobian<D>(x, rule.points[q]).determinant();
        sum += v * (x * Shape::shape(rule.points[q]));
        volume += v;
      }
    }
    return sum / volume;
  }
  for (int c = b.first_cell; c < b.first_cell + b.num_cells; ++c) {
    fem::NodeMatrix<D> x;
    for (int a = 0; a <= D; ++a) {
      const int n = model.cells(a, c);
      x.col(a) = model.X.col(n) + u.template segment<D>(n * D);
    }
    const double v = fem::signed_measure<D>(x);
    sum += v * x.rowwise().mean();
    volume += v;
  }
  return sum / volume;
}

template <int D>
void set_initial_motion(const Model<D>& model, int body, const InitialMotion& motion, State& state) {
  const Body& b = model.bodies[body];
  const Mat<D> F0 = motion.deformation.topLeftCorner<D, D>();
  const Vec<D> c = body_centroid<D>(model, body, state.u);
  for (int n = b.first_node; n < b.first_node + b.num_nodes; ++n)
    state.u.template segment<D>(n * D) = (F0 - Mat<D>::Identity()) * (model.X.col(n) - c);
  const Vec<D> c_def = body_centroid<D>(model, body, state.u);
  for (int n = b.first_node; n < b.first_node + b.num_nodes; ++n) {
    Vec3 r = Vec3::Zero();
    r.head<D>() = model.X.col(n) + state.u.template segment<D>(n * D) - c_def;
    const Vec3 spin = motion.angular_velocity.cross(r);
    state.v.template segment<D>(n * D) = motion.velocity.head<D>() + spin.head<D>();
  }
}

template State rest_state<2>(const Model<2>&);
template State rest_state<3>(const Model<3>&);
template Vec<2> body_centroid<2>(const Model<2>&, int, const Eigen::VectorXd&);
template Vec<3> body_centroid<3>(const Model<3>&, int, const Eigen::VectorXd&);
template void set_initial_motion<2>(const Model<2>&, int, const InitialMotion&, State&);
template void set_initial_motion<3>(const Model<3>&, int, const InitialMotion&, State&);

}  // namespace conserve::model
