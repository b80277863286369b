#include "simulation/contact_setup.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "core/error.hpp"
#include "simulation/plausibility.hpp"

namespace conserve::simulation {
namespace {

template <int D>
int body_index(const model::Model<D>& model, const std::string& name) {
  for (std::size_t b = 0; b < model.bodies.size(); ++b)
    if (model.bodies[b].name == name) return static_cast<int>(b);
  throw InputError(fmt::format("no body named '{}'", name));
}

template <int D>
double longest_edge(const contact::ContactSurface& s, const model::Model<D>& model) {
  const std::vector<double> sizes = contact::facet_sizes<D>(s, model.X);
  return sizes.empty() ? 0.0 : *std::max_element(sizes.begin(), sizes.end());
}

}  // namespace

template <int D>
std::vector<contact::ContactPair<D>> make_contact_pairs(const io::Scenario& scenario, const model::Model<D>& model) {
  std::vector<contact::ContactPair<D>> pairs;
  for (std::size_t i = 0; i < scenario.contacts.size(); ++i) {
    const io::ContactSpec& spec = scenario.contacts[i];
    contact::ContactPair<D> pair;
    const auto surface = [&](const char* key, const std::string& body, const std::string& group) {
      try {
        contact::ContactSurface s = contact::make_surface<D>(model, body_index(model, body), group);
        if (s.facets.rows() != D) {
          // Quadratic facets: frictionless contact by elimination, one pass.
          const char* missing = spec.method != "elimination"          ? "methods other than elimination"
                                : spec.kind != io::ContactKind::frictionless ? "stick or Coulomb contact"
                                : spec.passes > 1                     ? "two passes"
                                : spec.slave_body == spec.master_body ? "self-contact"
                                                                      : nullptr;
          if (missing)
            throw InputError(fmt::format("body '{}', group '{}': quadratic facets have frictionless contact by "
                                         "elimination in one pass; {} on them is not available in this version "
                                         "(mesh the body with order = 1)",
                                         body, group, missing));
        }
        return s;
      } catch (const InputError& e) {
        throw InputError(fmt::format("{}: {}", scenario.sources.locate(fmt::format("contact[{}].{}", i, key)), e.what()));
      }
    };
    pair.slave = surface("slave", spec.slave_body, spec.slave_group);
    pair.master = surface("master", spec.master_body, spec.master_group);
    // General contact: the finer surface is the slave (the first pass's),
    // where the check would warn of a coarse slave.
    if (spec.finer_slave &&
        contact::median_facet_size<D>(pair.slave, model.X) > kCoarseSlave * contact::median_facet_size<D>(pair.master, model.X))
      std::swap(pair.slave, pair.master);
    pair.kind = spec.kind == io::ContactKind::stick ? contact::Kind::stick : contact::Kind::frictionless;
    if (spec.kind == io::ContactKind::coulomb) {
      // Slaves of a Coulomb pair are activated sticking (a trial the active
      // set turns to slip when the force leaves the cone); with μ = 0 they
      // slip from the start, as frictionless slaves.
      pair.friction = spec.friction;
      if (spec.friction > 0.0) pair.kind = contact::Kind::stick;
    }
    pair.search.depth_factor = spec.depth_factor;
    const double h = longest_edge(pair.master, model);
    pair.search.search_distance = spec.depth_factor * h;
    // Round-off of positions of the model's size: a node lying on a surface
    // (gap 0 up to round-off) is not activated, one behind it by more is.
    pair.search.penetration_tolerance = 1e-13 * model.size();
    pair.contact = static_cast<int>(i);
    pair.passes = spec.passes;
    pair.self = spec.slave_body == spec.master_body && spec.slave_group == spec.master_group;
    pairs.push_back(std::move(pair));
  }
  // Two passes: the master's nodes against the slave's facets, the broad
  // phase's radius from the slave's facets. Each node then holds its
  // constraints on the other side, and slaves of both sides on each
  // other's facets are eliminated together (contact/elimination/).
  const std::size_t first = pairs.size();
  for (std::size_t p = 0; p < first; ++p) {
    if (scenario.contacts[p].passes < 2) continue;
    contact::ContactPair<D> second;
    second.slave = pairs[p].master;
    second.master = pairs[p].slave;
    second.kind = pairs[p].kind;
    second.friction = pairs[p].friction;
    second.search = pairs[p].search;
    second.search.search_distance = second.search.depth_factor * longest_edge(second.master, model);
    second.contact = pairs[p].contact;
    second.passes = 2;
    second.second_pass = true;
    if (second.slave.rigid) {
      // A driven body's nodes: held by the deformable side's facet nodes,
      // never by one with a prescribed dof.
      std::vector<char> held(static_cast<std::size_t>(model.num_nodes()), 0);
      for (const int d : model.held_dofs()) held[static_cast<std::size_t>(d / D)] = 1;
      for (const int node : second.master.nodes)
        if (held[static_cast<std::size_t>(node)]) second.fixed.push_back(node);
    }
    pairs.push_back(std::move(second));
  }
  return pairs;
}

template std::vector<contact::ContactPair<2>> make_contact_pairs<2>(const io::Scenario&, const model::Model<2>&);
template std::vector<contact::ContactPair<3>> make_contact_pairs<3>(const io::Scenario&, const model::Model<3>&);

}  // namespace conserve::simulation
