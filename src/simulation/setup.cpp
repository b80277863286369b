#include "simulation/setup.hpp"

#include <fmt/format.h>
#include <set>

#include "core/error.hpp"
#include "mesh/generators.hpp"
#include "mesh/msh_reader.hpp"
#include "mesh/topology.hpp"
#include "model/initial_state.hpp"
#include "time/integrator.hpp"

namespace conserve::simulation {
namespace {

mesh::Mesh body_mesh(const io::BodySpec& spec, int dim) {
  mesh::Mesh m = spec.mesh.generator.empty() ? mesh::extract(mesh::read_msh(spec.mesh.file, dim), spec.mesh.group)
                                             : mesh::generate_mesh(spec.mesh.generator, spec.mesh.parameters);
  m.points.colwise() += spec.translate.head(m.dim);
  return m;
}

template <int D>
void add_prescribed(const io::Scenario& scenario, model::Model<D>& model) {
  std::set<int> seen;
  for (std::size_t i = 0; i < scenario.boundaries.size(); ++i) {
    const io::BoundarySpec& bc = scenario.boundaries[i];
    const auto body =
        std::find_if(model.bodies.begin(), model.bodies.end(), [&](const model::Body& b) { return b.name == bc.body; });
    if (body == model.bodies.end())
      throw InputError(fmt::format("{}: boundary[{}]: no body named '{}'", scenario.file.string(), i, bc.body));
    std::vector<int> nodes;
    try {
      nodes = model::group_nodes(*body, bc.group);
    } catch (const InputError& e) {
      throw InputError(fmt::format("{}: boundary[{}].group: {}", scenario.file.string(), i, e.what()));
    }
    for (int n : nodes)
      for (int k : bc.components) {
        const int d = model::dof<D>(n, k);
        if (!seen.insert(d).second)
          throw InputError(fmt::format("{}: boundary[{}]: node {} component {} of body '{}' is already prescribed",
                                       scenario.file.string(), i, n - body->first_node, "xyz"[k], bc.body));
        model.prescribed.dofs.push_back(d);
        model.prescribed.value.push_back(bc.value[k]);
        model.prescribed.rate.push_back(bc.rate[k]);
      }
  }
}

}  // namespace

template <int D>
Problem<D> setup(const io::Scenario& scenario) {
  Problem<D> p;
  for (std::size_t i = 0; i < scenario.bodies.size(); ++i) {
    const io::BodySpec& spec = scenario.bodies[i];
    try {
      const auto lame = material::Lame::from_young_poisson(spec.material.young, spec.material.poisson);
      model::add_body<D>(p.model, body_mesh(spec, D), spec.name, lame, spec.material.density, spec.thickness);
    } catch (const InputError& e) {
      throw InputError(fmt::format("{}: body[{}] '{}': {}", scenario.file.string(), i, spec.name, e.what()));
    }
  }
  p.model.gravity = scenario.gravity.head<D>();
  add_prescribed<D>(scenario, p.model);
  p.initial = model::rest_state<D>(p.model);
  for (std::size_t i = 0; i < scenario.bodies.size(); ++i) {
    const io::BodySpec& spec = scenario.bodies[i];
    model::set_initial_motion<D>(p.model, static_cast<int>(i),
                                 {spec.initial_deformation, spec.velocity, spec.angular_velocity}, p.initial);
  }
  time::apply_prescribed(p.model.prescribed, 0.0, p.initial.u, &p.initial.v);
  return p;
}

template Problem<2> setup<2>(const io::Scenario&);
template Problem<3> setup<3>(const io::Scenario&);

}  // namespace conserve::simulation
