#include "time/diagnostics.hpp"

#include "time/surface_loads.hpp"

namespace conserve::time {

template <int D>
Diagnostics diagnostics(const assembly::Assembler<D>& assembler, const model::State& state) {
  const auto& model = assembler.model();
  const Eigen::VectorXd p = assembler.mass_times(state.v);
  Diagnostics d;
  d.kinetic = 0.5 * state.v.dot(p);
  const auto& measures = assembler.measures(state.u);  // the step's check made them
  d.strain = measures.strain_energy;
  d.potential = model.gravity_curve < 0 ? -assembler.gravity_force().dot(state.u) : 0.0;
  if (!model.loads.empty()) d.potential -= conservative_load<D>(model).dot(state.u);
  d.load_work = state.load_work;
  for (double w : state.support_work) d.support_work += w;
  d.released = state.released;
  d.dissipated = state.dissipated;
  d.total = d.kinetic + d.strain + d.potential - d.load_work - d.support_work;
  for (int n = 0; n < model.num_nodes(); ++n) {
    Vec3 x = Vec3::Zero(), pn = Vec3::Zero();
    x.head<D>() = model.X.col(n) + state.u.segment<D>(n * D);
    pn.head<D>() = p.segment<D>(n * D);
    d.linear += pn;
    d.angular += x.cross(pn);
    d.momentum_magnitude += pn.norm();
  }
  const assembly::Orientation o = measures.orientation;
  d.min_det_F = o.cell < 0 ? 1.0 : o.det_F;
  d.min_det_F_cell = o.cell;
  for (const auto& body : model.bodies) {
    Vec3 L = Vec3::Zero();
    for (int n = body.first_node; n < body.first_node + body.num_nodes; ++n) L.head<D>() += p.segment<D>(n * D);
    d.body_linear.push_back(L);
  }
  return d;
}

template Diagnostics diagnostics<2>(const assembly::Assembler<2>&, const model::State&);
template Diagnostics diagnostics<3>(const assembly::Assembler<3>&, const model::State&);

}  // namespace conserve::time
