#include "time/surface_loads.hpp"

namespace conserve::time {
namespace {

using Load = model::SurfaceLoad;

/// The outward area vector of facet f of `load` at positions x (2D: the
/// length × thickness along the outward normal of contact/facet.hpp).
template <int D>
Vec<D> area_vector(const Load& load, int f, const Eigen::Matrix<double, D, Eigen::Dynamic>& x) {
  const Vec<D> a = x.col(load.facets(1, f)) - x.col(load.facets(0, f));
  if constexpr (D == 2) {
    return load.thickness * Vec<2>(a.y(), -a.x());
  } else {
    return 0.5 * a.cross(Vec<3>(x.col(load.facets(2, f)) - x.col(load.facets(0, f))));
  }
}

template <int D>
Eigen::VectorXd traction_force(const model::Model<D>& model, const Load& load) {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(model.num_dofs());
  for (int k = 0; k < load.facets.cols(); ++k) {
    const double share = area_vector<D>(load, k, model.X).norm() / D;
    for (int a = 0; a < D; ++a) f.segment<D>(load.facets(a, k) * D) += share * load.traction.head<D>();
  }
  return f;
}

}  // namespace

template <int D>
Eigen::VectorXd conservative_load(const model::Model<D>& model) {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(model.num_dofs());
  for (const Load& load : model.loads)
    if (load.conservative()) f += traction_force<D>(model, load);
  return f;
}

template <int D>
SurfaceLoads<D>::SurfaceLoads(const assembly::Assembler<D>& assembler) : assembler_(assembler) {
  for (const Load& load : assembler.model().loads)
    traction_.push_back(load.kind == Load::Kind::traction ? traction_force<D>(assembler.model(), load)
                                                          : Eigen::VectorXd());
}

template <int D>
void SurfaceLoads<D>::begin(const model::State& start, double dt) {
  const auto& model = assembler_.model();
  const double t = start.time + 0.5 * dt;
  factor_.clear();
  for (const Load& load : model.loads) factor_.push_back(load.curve < 0 ? 1.0 : model.prescribed.curves[load.curve].at(t));
  gravity_factor_ = model.gravity_curve < 0 ? 0.0 : model.prescribed.curves[model.gravity_curve].at(t);
  u_n_ = start.u;
  const Eigen::VectorXd f = force(start.u, false);
  start_force_ = f.norm();
  start_energy_ = std::abs(f.dot(start.u));
}

template <int D>
Eigen::VectorXd SurfaceLoads<D>::force(const Eigen::VectorXd& u_np1, bool work_only) const {
  const auto& model = assembler_.model();
  Eigen::VectorXd f = Eigen::VectorXd::Zero(u_np1.size());
  if (model.gravity_curve >= 0) f += gravity_factor_ * assembler_.gravity_force();
  const Eigen::Matrix<double, D, Eigen::Dynamic> x_mid =
      model.X + (0.5 * (u_n_ + u_np1)).reshaped(D, model.num_nodes());
  for (std::size_t l = 0; l < model.loads.size(); ++l) {
    const Load& load = model.loads[l];
    if (work_only && load.conservative()) continue;
    if (load.kind == Load::Kind::traction) {
      f += factor_[l] * traction_[l];
      continue;
    }
    const double p = factor_[l] * load.pressure / D;
    for (int k = 0; k < load.facets.cols(); ++k) {
      const Vec<D> share = -p * area_vector<D>(load, k, x_mid);
      for (int a = 0; a < D; ++a) f.segment<D>(load.facets(a, k) * D) += share;
    }
  }
  return f;
}

template <int D>
void SurfaceLoads<D>::add_value(const Eigen::VectorXd& u_np1, Eigen::VectorXd& g, Eigen::VectorXd& magnitude) {
  const Eigen::VectorXd f = force(u_np1, false);
  g -= f;
  magnitude += f.cwiseAbs();
}

// ∂f/∂u_{n+1} of the pressures: ½ ∂f/∂x_{n+½}, with ∂A/∂x_k = ½[x_{k+2} − x_{k+1}]×
// (3D, nodes cyclic) and ∂A/∂x_1 = −∂A/∂x_0 = t [[0, 1], [−1, 0]] (2D).
template <int D>
void SurfaceLoads<D>::add_derivative(const Eigen::VectorXd& u_np1, SparseMatrix& K) {
  const auto& model = assembler_.model();
  const Eigen::Matrix<double, D, Eigen::Dynamic> x_mid =
      model.X + (0.5 * (u_n_ + u_np1)).reshaped(D, model.num_nodes());
  for (std::size_t l = 0; l < model.loads.size(); ++l) {
    const Load& load = model.loads[l];
    if (load.kind != Load::Kind::pressure) continue;
    const double c = -factor_[l] * load.pressure / D * 0.5;  // f_a = c' A, ∂/∂u = ½ ∂/∂x_mid
    for (int k = 0; k < load.facets.cols(); ++k)
      for (int b = 0; b < D; ++b) {
        Eigen::Matrix<double, D, D> dA;
        if constexpr (D == 2) {
          dA << 0.0, 1.0, -1.0, 0.0;
          dA *= load.thickness * (b == 1 ? 1.0 : -1.0);
        } else {
          const Vec<3> e = x_mid.col(load.facets((b + 2) % 3, k)) - x_mid.col(load.facets((b + 1) % 3, k));
          dA << 0.0, -e.z(), e.y(), e.z(), 0.0, -e.x(), -e.y(), e.x(), 0.0;
          dA *= 0.5;
        }
        for (int a = 0; a < D; ++a) {
          if (!model.owns(load.facets(a, k))) continue;  // another rank's row
          for (int i = 0; i < D; ++i)
            for (int j = 0; j < D; ++j)
              K.coeffRef(load.facets(a, k) * D + i, load.facets(b, k) * D + j) -= c * dA(i, j);
        }
      }
  }
}

template <int D>
double SurfaceLoads<D>::external_work(const Eigen::VectorXd& u_np1) const {
  return force(u_np1, true).dot(u_np1 - u_n_);
}

template class SurfaceLoads<2>;
template class SurfaceLoads<3>;
template Eigen::VectorXd conservative_load<2>(const model::Model<2>&);
template Eigen::VectorXd conservative_load<3>(const model::Model<3>&);

}  // namespace conserve::time
