#include "assembly/assembler.hpp"

#include <limits>

namespace conserve::assembly {

template <int D>
Assembler<D>::Assembler(const model::Model<D>& model, bool lumped_mass)
    : model_(model), pattern_(model.num_nodes(), model.cells), mass_(pattern_.make_matrix()) {
  double* values = mass_.valuePtr();
  for (int c = 0; c < model.num_cells(); ++c) {
    const double density = model.bodies[model.cell_body[c]].density;
    const auto Me = fem::element_mass<D>(density, model.geometry[c].volume, lumped_mass);
    for (int b = 0; b <= D; ++b)
      for (int a = 0; a <= D; ++a)
        for (int i = 0; i < D; ++i) values[pattern_.position(c, a, b, i, i)] += Me(a, b);
  }
  Eigen::VectorXd g(model.num_dofs());
  for (int n = 0; n < model.num_nodes(); ++n) g.segment<D>(n * D) = model.gravity;
  gravity_force_ = mass_ * g;
  stiffness_scale_.setZero(model.num_dofs());
  for (int c = 0; c < model.num_cells(); ++c) {
    const auto& geometry = model.geometry[c];
    const double modulus = lame(c).lambda + 2.0 * lame(c).mu;
    for (int a = 0; a <= D; ++a)
      stiffness_scale_.segment<D>(model.cells(a, c) * D).array() +=
          geometry.volume * modulus * geometry.grad.col(a).norm();
  }
}

template <int D>
fem::NodeMatrix<D> Assembler<D>::cell_positions(int cell, const Eigen::VectorXd& u) const {
  fem::NodeMatrix<D> x;
  for (int a = 0; a <= D; ++a) {
    const int node = model_.cells(a, cell);
    x.col(a) = model_.X.col(node) + u.segment<D>(node * D);
  }
  return x;
}

template <int D>
void Assembler<D>::internal_force(const Eigen::VectorXd& u_n, const Eigen::VectorXd& u_np1, fem::StressScheme scheme,
                                  Eigen::VectorXd& f, Eigen::VectorXd* magnitude) const {
  f.setZero(model_.num_dofs());
  if (magnitude) magnitude->setZero(model_.num_dofs());
  for (int c = 0; c < model_.num_cells(); ++c) {
    const fem::StepPositions<D> x{cell_positions(c, u_n), cell_positions(c, u_np1)};
    const fem::NodeMatrix<D> fe = fem::internal_force<D>(model_.geometry[c], lame(c), x, scheme);
    for (int a = 0; a <= D; ++a) f.segment<D>(model_.cells(a, c) * D) += fe.col(a);
    if (magnitude)
      for (int a = 0; a <= D; ++a) magnitude->segment<D>(model_.cells(a, c) * D) += fe.col(a).cwiseAbs();
  }
}

template <int D>
void Assembler<D>::internal_force_tangent(const Eigen::VectorXd& u_n, const Eigen::VectorXd& u_np1,
                                          fem::StressScheme scheme, Eigen::VectorXd& f, SparseMatrix& K) const {
  f.setZero(model_.num_dofs());
  std::fill(K.valuePtr(), K.valuePtr() + K.nonZeros(), 0.0);
  double* values = K.valuePtr();
  fem::NodeMatrix<D> fe;
  fem::ElementMatrix<D> Ke;
  for (int c = 0; c < model_.num_cells(); ++c) {
    const fem::StepPositions<D> x{cell_positions(c, u_n), cell_positions(c, u_np1)};
    fem::internal_force_tangent<D>(model_.geometry[c], lame(c), x, scheme, fe, Ke);
    for (int a = 0; a <= D; ++a) f.segment<D>(model_.cells(a, c) * D) += fe.col(a);
    for (int b = 0; b <= D; ++b)
      for (int k = 0; k < D; ++k)
        for (int a = 0; a <= D; ++a)
          for (int i = 0; i < D; ++i) values[pattern_.position(c, a, b, i, k)] += Ke(a * D + i, b * D + k);
  }
}

template <int D>
Orientation Assembler<D>::min_det_F(const Eigen::VectorXd& u) const {
  Orientation o{std::numeric_limits<double>::infinity(), -1};
  for (int c = 0; c < model_.num_cells(); ++c) {
    const double det = fem::deformation_gradient<D>(cell_positions(c, u), model_.geometry[c]).determinant();
    if (det < o.det_F) o = {det, c};
  }
  return o;
}

template <int D>
double Assembler<D>::strain_energy(const Eigen::VectorXd& u) const {
  double W = 0.0;
  for (int c = 0; c < model_.num_cells(); ++c)
    W += fem::strain_energy<D>(model_.geometry[c], lame(c), cell_positions(c, u));
  return W;
}

template class Assembler<2>;
template class Assembler<3>;

}  // namespace conserve::assembly
