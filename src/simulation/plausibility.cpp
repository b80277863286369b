#include "simulation/plausibility.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "contact/facet.hpp"
#include "contact/search.hpp"

namespace conserve::simulation {
namespace {

/// A body's reference bounding box diagonal [m] and volume [m³].
template <int D>
struct Extent {
  double size = 0.0;
  double volume = 0.0;
};

template <int D>
Extent<D> extent(const model::Model<D>& model, const model::Body& body) {
  Extent<D> e;
  if (body.num_nodes == 0) return e;
  const auto X = model.X.middleCols(body.first_node, body.num_nodes);
  e.size = (X.rowwise().maxCoeff() - X.rowwise().minCoeff()).norm();
  for (int c = body.first_cell; c < body.first_cell + body.num_cells; ++c) e.volume += model.cell_volume(c);
  return e;
}

/// The fastest a point of body `b` moves at t = 0 [m/s]: its velocity and
/// its spin times its half size.
double initial_speed(const io::BodySpec& spec, double size) {
  return spec.velocity.norm() + (spec.rigid ? 0.0 : spec.angular_velocity.norm() * 0.5 * size);
}

/// The speed a fall under gravity across the whole model adds [m/s].
template <int D>
double fall_speed(const io::Scenario& scenario, const model::Model<D>& model) {
  const double g = scenario.gravity.head<D>().norm();
  if (!(g > 0.0) || model.num_nodes() == 0) return 0.0;
  const Vec<D> down = scenario.gravity.head<D>() / g;
  const Eigen::RowVectorXd along = down.transpose() * model.X;
  return std::sqrt(2.0 * g * (along.maxCoeff() - along.minCoeff()));
}

std::optional<std::size_t> body_named(const io::Scenario& scenario, const std::string& name) {
  for (std::size_t b = 0; b < scenario.bodies.size(); ++b)
    if (scenario.bodies[b].name == name) return b;
  return std::nullopt;
}

/// Fast impacts: per deformable body of a contact pair, the closing speed
/// bound against its wave speed.
template <int D>
void check_impacts(const io::Scenario& scenario, const model::Model<D>& model, std::vector<std::string>& out) {
  const double fall = fall_speed<D>(scenario, model);
  std::vector<double> worst(scenario.bodies.size(), 0.0);
  for (const io::ContactSpec& c : scenario.contacts) {
    const auto a = body_named(scenario, c.slave_body), b = body_named(scenario, c.master_body);
    if (!a || !b) continue;
    const double closing = initial_speed(scenario.bodies[*a], extent<D>(model, model.bodies[*a]).size) +
                           initial_speed(scenario.bodies[*b], extent<D>(model, model.bodies[*b]).size) + fall;
    worst[*a] = std::max(worst[*a], closing);
    worst[*b] = std::max(worst[*b], closing);
  }
  for (std::size_t b = 0; b < scenario.bodies.size(); ++b) {
    const io::BodySpec& spec = scenario.bodies[b];
    if (spec.rigid || !(worst[b] > 0.0) || !(spec.material.density > 0.0)) continue;
    const material::Lame lame = model.bodies[b].law->small_strain();
    const double young = lame.mu * (3.0 * lame.lambda + 2.0 * lame.mu) / (lame.lambda + lame.mu);
    const double wave = std::sqrt(young / spec.material.density);
    if (!(worst[b] > kFastImpact * wave)) continue;
    out.push_back(fmt::format(
        "{}: the body may meet its contact partner at up to {:.3g} m/s (initial velocities and spins{}), {:.3g} "
        "times its wave speed sqrt(E / density) = {:.3g} m/s (E its Young's modulus at small strain); above {} of "
        "it, strains near 1 turn Saint Venant-Kirchhoff cells inside out (is the material given in Pa?)",
        scenario.sources.locate(fmt::format("body[{}].material.young", b)), worst[b],
        fall > 0.0 ? fmt::format(", a fall of {:.3g} m/s under gravity", fall) : "", worst[b] / wave, wave,
        kFastImpact));
  }
}

/// Generated meshes whose cell size exceeds the body.
template <int D>
void check_mesh_sizes(const io::Scenario& scenario, const model::Model<D>& model, std::vector<std::string>& out) {
  for (std::size_t b = 0; b < scenario.bodies.size(); ++b) {
    const auto& parameters = scenario.bodies[b].mesh.parameters;
    const auto size = parameters.find("size");
    if (scenario.bodies[b].mesh.generator.empty() || size == parameters.end()) continue;
    const model::Body& body = model.bodies[b];
    const auto X = model.X.middleCols(body.first_node, body.num_nodes);
    const double across = (X.rowwise().maxCoeff() - X.rowwise().minCoeff()).maxCoeff();
    if (!(size->second > across)) continue;
    out.push_back(fmt::format(
        "{}: {:.3g} m is larger than the body it meshes ({:.3g} m across at most): the mesh has {} {} and {} nodes "
        "(is size in the scenario's unit, m?)",
        scenario.sources.locate(fmt::format("body[{}].mesh.size", b)), size->second, across,
        body.num_cells > 0 ? body.num_cells : model::distinct_facets(body).cols(),
        body.num_cells > 0 ? "cells" : "facets", body.num_nodes));
  }
}

/// Densities no solid has.
template <int D>
void check_densities(const io::Scenario& scenario, const model::Model<D>& model, std::vector<std::string>& out) {
  for (std::size_t b = 0; b < scenario.bodies.size(); ++b) {
    const io::BodySpec& spec = scenario.bodies[b];
    const double rho = spec.material.density;
    if (!(rho > 0.0) || (rho >= kLightestSolid && rho <= kDensestSolid)) continue;
    const Extent<D> e = extent<D>(model, model.bodies[b]);
    out.push_back(fmt::format(
        "{}: {:.3g} kg/m³ makes the body's {:.3g} m³ weigh {:.3g} kg; solids lie between {:g} (foams) and {:g} "
        "kg/m³ (is density in kg/m³?{})",
        scenario.sources.locate(fmt::format("body[{}].material.density", b)), rho, e.volume, rho * e.volume,
        kLightestSolid, kDensestSolid,
        rho < kLightestSolid ? fmt::format(" {:g} g/cm³ is {:g} kg/m³", rho, rho * 1000.0) : ""));
  }
}

/// Whether all of a surface's nodes lie in one plane (up to round-off of
/// its size) in the reference configuration. The nodes of a flat master
/// cannot enter the facets of a slave held in front of it, however coarse.
template <int D>
bool flat(const contact::ContactSurface& surface, const model::Model<D>& model) {
  if (surface.num_facets() == 0) return true;
  const Vec<D> normal = contact::facet_normal<D>(contact::facet_nodes<D>(surface, 0, model.X));
  const Vec<D> origin = model.X.col(surface.facets(0, 0));
  double size = 0.0, off = 0.0;
  for (int node : surface.nodes) {
    size = std::max(size, (model.X.col(node) - origin).norm());
    off = std::max(off, std::abs(normal.dot(model.X.col(node) - origin)));
  }
  return off <= 1e-9 * size;
}

/// Slave surfaces coarser than their masters (unless the master is flat).
template <int D>
void check_slave_sizes(const io::Scenario& scenario, const model::Model<D>& model,
                       const std::vector<contact::ContactPair<D>>& pairs, std::vector<std::string>& out) {
  for (std::size_t p = 0; p < pairs.size() && p < scenario.contacts.size(); ++p) {
    const double slave = contact::median_facet_size<D>(pairs[p].slave, model.X),
                 master = contact::median_facet_size<D>(pairs[p].master, model.X);
    if (!(slave > kCoarseSlave * master) || flat<D>(pairs[p].master, model)) continue;
    const io::ContactSpec& c = scenario.contacts[p];
    out.push_back(fmt::format(
        "{}: the slave surface '{}:{}' is coarser than its master '{}:{}' (median facet edge {:.3g} m against "
        "{:.3g} m): contact holds the slave's nodes only, so the master's may sink into its facets between them "
        "(history.csv's master_penetration measures how far); make the finer surface the slave",
        scenario.sources.locate(fmt::format("contact[{}].slave", p)), c.slave_body, c.slave_group, c.master_body,
        c.master_group, slave, master));
  }
}

/// Slave nodes that start behind a bare master surface (a body without
/// cells, whose facets' order alone gives their normals): the search
/// (contact::find_master) at the reference positions finds them behind a
/// facet they project inside. A surface facing away from its slaves puts
/// them all there.
template <int D>
void check_sides(const io::Scenario& scenario, const model::Model<D>& model,
                 const std::vector<contact::ContactPair<D>>& pairs, std::vector<std::string>& out) {
  for (std::size_t p = 0; p < pairs.size() && p < scenario.contacts.size(); ++p) {
    const contact::ContactPair<D>& pair = pairs[p];
    if (model.bodies[static_cast<std::size_t>(pair.master.body)].num_cells > 0 || pair.master.num_facets() == 0)
      continue;
    contact::FacetTree<D> tree;
    tree.build(pair.master.facets, model.X);
    int behind = 0;
    double deepest = 0.0;
    for (const int s : pair.slave.nodes) {
      const auto m = contact::find_master<D>(model.X.col(s), pair.master, tree, model.X, pair.search);
      if (!m || !m->projection.inside(pair.search.inside_tolerance) ||
          !(m->projection.gap < -pair.search.penetration_tolerance))
        continue;
      ++behind;
      deepest = std::min(deepest, m->projection.gap);
    }
    if (behind == 0) continue;
    const io::ContactSpec& c = scenario.contacts[p];
    out.push_back(fmt::format(
        "{}: {} of the {} nodes of the slave surface '{}:{}' start behind the bare master surface '{}:{}' (gaps down "
        "to {:.3g} m): the slaves belong on the side its facets' normals point to (`conserve check` states which); "
        "if they face away, reverse them ([body.mesh] flip_normals)",
        scenario.sources.locate(fmt::format("contact[{}].master", p)), behind, pair.slave.nodes.size(), c.slave_body,
        c.slave_group, c.master_body, c.master_group, deepest));
  }
}

}  // namespace

template <int D>
std::vector<std::string> plausibility_warnings(const io::Scenario& scenario, const model::Model<D>& model,
                                               const std::vector<contact::ContactPair<D>>& pairs) {
  std::vector<std::string> out;
  check_impacts<D>(scenario, model, out);
  check_mesh_sizes<D>(scenario, model, out);
  check_densities<D>(scenario, model, out);
  check_slave_sizes<D>(scenario, model, pairs, out);
  check_sides<D>(scenario, model, pairs, out);
  return out;
}

template std::vector<std::string> plausibility_warnings<2>(const io::Scenario&, const model::Model<2>&,
                                                           const std::vector<contact::ContactPair<2>>&);
template std::vector<std::string> plausibility_warnings<3>(const io::Scenario&, const model::Model<3>&,
                                                           const std::vector<contact::ContactPair<3>>&);

}  // namespace conserve::simulation
