#include "time/surface_loads.hpp"

#include "fem/facet_integrals.hpp"

namespace conserve::time {
namespace {

using Load = model::SurfaceLoad;

/// Calls f(FacetIntegrals<D, P>{}) for the order of the load's facets
/// (D rows: P1; D(D+1)/2: P2).
template <int D, class F>
void with_facet_order(const Load& load, F&& f) {
  if (load.facets.rows() == D)
    f(fem::FacetIntegrals<D, 1>{});
  else
    f(fem::FacetIntegrals<D, 2>{});
}

/// The nodes of facet k of `load` at positions x.
template <class I, int D>
typename I::Nodes facet_nodes(const Load& load, int k, const Eigen::Matrix<double, D, Eigen::Dynamic>& x) {
  typename I::Nodes n;
  for (int a = 0; a < I::kNodes; ++a) n.col(a) = x.col(load.facets(a, k));
  return n;
}

/// f_a = t ∫ N_a dA_0: the nominal traction's nodal forces at factor 1.
template <int D>
Eigen::VectorXd traction_force(const model::Model<D>& model, const Load& load) {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(model.num_dofs());
  with_facet_order<D>(load, [&]<class I>(I) {
    for (int k = 0; k < load.facets.cols(); ++k) {
      const auto share = I::measure_shares(facet_nodes<I, D>(load, k, model.X), load.thickness);
      for (int a = 0; a < I::kNodes; ++a) f.segment<D>(load.facets(a, k) * D) += share(a) * load.traction.head<D>();
    }
  });
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
    const double p = factor_[l] * load.pressure;
    with_facet_order<D>(load, [&]<class I>(I) {
      for (int k = 0; k < load.facets.cols(); ++k) {
        const typename I::Nodes share = -p * I::area_shares(facet_nodes<I, D>(load, k, x_mid), load.thickness);
        for (int a = 0; a < I::kNodes; ++a) f.segment<D>(load.facets(a, k) * D) += share.col(a);
      }
    });
  }
  return f;
}

template <int D>
void SurfaceLoads<D>::add_value(const Eigen::VectorXd& u_np1, Eigen::VectorXd& g, Eigen::VectorXd& magnitude) {
  const Eigen::VectorXd f = force(u_np1, false);
  g -= f;
  magnitude += f.cwiseAbs();
}

// ∂(−f)/∂u_{n+1} of the pressures: f_a = −p s_a(x_{n+½}), ∂/∂u_{n+1} = ½ ∂/∂x_{n+½}
// (fem/facet_integrals.hpp).
template <int D>
void SurfaceLoads<D>::add_derivative(const Eigen::VectorXd& u_np1, SparseMatrix& K) {
  const auto& model = assembler_.model();
  const Eigen::Matrix<double, D, Eigen::Dynamic> x_mid =
      model.X + (0.5 * (u_n_ + u_np1)).reshaped(D, model.num_nodes());
  for (std::size_t l = 0; l < model.loads.size(); ++l) {
    const Load& load = model.loads[l];
    if (load.kind != Load::Kind::pressure) continue;
    const double c = factor_[l] * load.pressure * 0.5;  // g ∋ −f = p s_a: ∂g/∂u_{n+1} = ½ p ∂s_a/∂x_{n+½}
    with_facet_order<D>(load, [&]<class I>(I) {
      for (int k = 0; k < load.facets.cols(); ++k) {
        const auto d = I::area_share_derivatives(facet_nodes<I, D>(load, k, x_mid), load.thickness);
        for (int a = 0; a < I::kNodes; ++a) {
          if (!model.owns(load.facets(a, k))) continue;  // another rank's row
          for (int b = 0; b < I::kNodes; ++b) {
            const Mat<D>& dab = d[static_cast<std::size_t>(a * I::kNodes + b)];
            for (int i = 0; i < D; ++i)
              for (int j = 0; j < D; ++j)
                K.coeffRef(load.facets(a, k) * D + i, load.facets(b, k) * D + j) += c * dab(i, j);
          }
        }
      }
    });
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
