#include "simulation/fingerprint.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>

#include "material/law.hpp"
#include "solver/ranks.hpp"

namespace conserve::simulation {
namespace {

/// The entry of a numbering by N ranks' graph parts (its value: N).
constexpr const char* kRankNumbering = "node numbering";

/// FNV-1a over raw bytes.
class Hasher {
 public:
  void bytes(const void* data, std::size_t size) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i) hash_ = (hash_ ^ p[i]) * 1099511628211ULL;
  }
  template <class T>
  void value(const T& v) {
    bytes(&v, sizeof v);
  }
  void text(const std::string& s) {
    value(static_cast<std::int64_t>(s.size()));
    bytes(s.data(), s.size());
  }
  template <class M>
  void matrix(const M& m) {
    value(static_cast<std::int64_t>(m.rows()));
    value(static_cast<std::int64_t>(m.cols()));
    for (Eigen::Index j = 0; j < m.cols(); ++j)
      for (Eigen::Index i = 0; i < m.rows(); ++i) value(m(i, j));
  }
  template <class T>
  void vector(const std::vector<T>& v) {
    value(static_cast<std::int64_t>(v.size()));
    bytes(v.data(), sizeof(T) * v.size());
  }
  [[nodiscard]] std::uint64_t get() const { return hash_; }

 private:
  std::uint64_t hash_ = 14695981039346656037ULL;
};

/// Collects the entries; each `add` hashes what its function feeds.
class Builder {
 public:
  template <class F>
  void add(std::string name, std::string value, F&& feed) {
    Hasher h;
    feed(h);
    entries_.push_back({std::move(name), h.get(), std::move(value)});
  }
  /// A setting whose printable value is all there is to it.
  void setting(std::string name, const std::string& value) {
    add(std::move(name), value, [&](Hasher& h) { h.text(value); });
  }
  Fingerprint take() { return std::move(entries_); }

 private:
  Fingerprint entries_;
};

/// The first `n` components, "[a, b, c]" (shortest round-trip digits).
std::string components(const Eigen::Vector3d& v, int n) {
  return fmt::format("[{}]", fmt::join(v.data(), v.data() + n, ", "));
}

template <int D>
std::string deformation(const Eigen::Matrix3d& f) {
  std::vector<std::string> rows(D);
  for (int i = 0; i < D; ++i) rows[i] = components(f.row(i).transpose(), D);
  return fmt::format("[{}]", fmt::join(rows, ", "));
}

std::string material(const io::BodySpec& b) {
  if (b.rigid && !(b.material.density > 0.0)) return "none (rigid, massless)";
  std::string text = fmt::format("model {}", b.material.model);
  for (const auto& p : material::law_catalog().at(b.material.model).parameters)
    text += fmt::format(", {} {}{}", p.name, b.material.parameter(p.name), p.unit.empty() ? "" : " " + p.unit);
  return text + fmt::format(", density {} kg/m³", b.material.density);
}

template <int D>
void add_body(Builder& f, const io::BodySpec& spec, const model::Model<D>& model, const model::Body& body) {
  const std::string name = fmt::format("body '{}' ", body.name);
  f.add(name + "material", material(spec), [&](Hasher& h) {
    h.text(spec.rigid && !(spec.material.density > 0.0) ? "none" : spec.material.model);
    for (const auto& [parameter, value] : spec.material.parameters) {
      h.text(parameter);
      h.value(value);
    }
    h.value(body.density);
  });
  f.setting(name + "thickness", fmt::format("{}", spec.thickness));
  f.setting(name + "dilatation", spec.mean_dilatation ? "mean" : "points");
  f.setting(name + "motion", spec.free ? "free rigid" : spec.rigid ? "prescribed rigid" : "deformable");
  f.setting(name + "velocity", components(spec.velocity, D));
  f.setting(name + "angular_velocity",
            D == 3 ? components(spec.angular_velocity, 3) : fmt::format("{}", spec.angular_velocity.z()));
  f.setting(name + "initial_deformation", deformation<D>(spec.initial_deformation));
  f.add(name + "node coordinates", "",
        [&](Hasher& h) { h.matrix(model.X.middleCols(body.first_node, body.num_nodes)); });
  f.add(name + "cells", "", [&](Hasher& h) { h.matrix(model.cells.middleCols(body.first_cell, body.num_cells)); });
  f.add(name + "cell volumes", "", [&](Hasher& h) {  // hold the 2D thickness
    for (int c = body.first_cell; c < body.first_cell + body.num_cells; ++c) h.value(model.cell_volume(c));
  });
  f.add(name + "facet groups", "", [&](Hasher& h) {
    for (const auto& [group, facets] : body.facet_groups) {
      h.text(group);
      h.matrix(facets);
    }
  });
}

void add_contact(Builder& f, std::size_t i, const io::ContactSpec& c) {
  const std::string name = fmt::format("contact[{}] ", i);
  f.setting(name + "surfaces",
            fmt::format("slave {}:{}, master {}:{}", c.slave_body, c.slave_group, c.master_body, c.master_group));
  f.setting(name + "kind", c.kind == io::ContactKind::stick     ? "stick"
                           : c.kind == io::ContactKind::coulomb ? "coulomb"
                                                                : "frictionless");
  if (c.kind == io::ContactKind::coulomb) f.setting(name + "friction", fmt::format("{}", c.friction));
  f.setting(name + "depth_factor", fmt::format("{}", c.depth_factor));
  if (c.passes != 1) f.setting(name + "passes", fmt::format("{}", c.passes));
  f.setting(name + "method", c.method);
  if (c.method == "penalty") {
    f.setting(name + "penalty", fmt::format("{}", c.penalty));
    f.setting(name + "penalty_force", c.penalty_force == io::PenaltyForce::midpoint ? "midpoint" : "conserving");
  }
}

const FingerprintEntry* find(const Fingerprint& f, const std::string& name) {
  const auto it = std::find_if(f.begin(), f.end(), [&](const FingerprintEntry& e) { return e.name == name; });
  return it == f.end() ? nullptr : &*it;
}

}  // namespace

template <int D>
Fingerprint scenario_fingerprint(const io::Scenario& sc, const model::Model<D>& model) {
  Builder f;
  if (model.numbered_for_ranks > 0) f.setting(kRankNumbering, fmt::format("{}", model.numbered_for_ranks));
  f.setting("dimension", fmt::format("{}", D));
  std::vector<std::string> names;
  for (const auto& b : model.bodies) names.push_back(b.name);
  f.setting("bodies", fmt::format("{}", fmt::join(names, ", ")));
  for (std::size_t b = 0; b < model.bodies.size(); ++b) add_body<D>(f, sc.bodies[b], model, model.bodies[b]);
  f.add("[loads] gravity", components(sc.gravity, D), [&](Hasher& h) { h.matrix(model.gravity); });
  f.setting("[loads] gravity_curve", sc.gravity_curve);
  for (std::size_t i = 0; i < sc.loads.size(); ++i) {
    const io::LoadSpec& l = sc.loads[i];
    f.setting(fmt::format("load[{}]", i),
              fmt::format("{}:{} {} {}, curve '{}'", l.body, l.group, l.pressure ? "pressure" : "traction",
                          l.pressure ? fmt::format("{}", l.pressure_value) : components(l.traction, D), l.curve));
  }
  f.add("prescribed displacements", "", [&](Hasher& h) {  // [[boundary]] and rigid bodies
    h.vector(model.prescribed.dofs);
    h.vector(model.prescribed.value);
    h.vector(model.prescribed.rate);
    h.vector(model.prescribed.curve);
    for (const model::RigidMotion& m : model.prescribed.rigid) {
      h.value(m.first_node);
      h.value(m.num_nodes);
      for (const Vec3* v : {&m.center, &m.velocity, &m.omega}) h.value(v->x()), h.value(v->y()), h.value(v->z());
      h.value(m.velocity_curve);
      h.value(m.omega_curve);
    }
  });
  for (const io::CurveSpec& c : sc.curves)
    f.add(fmt::format("curve '{}'", c.name), fmt::format("{} points", c.points.size()), [&](Hasher& h) {
      for (const auto& [t, value] : c.points) h.value(t), h.value(value);
    });
  f.add("[time] step", fmt::format("{}", sc.time.step), [&](Hasher& h) { h.value(sc.time.step); });
  f.setting("[time] scheme", sc.time.scheme == io::StressScheme::midpoint ? "midpoint" : "conserving");
  f.setting("[time] mass", sc.time.mass == io::MassKind::lumped ? "lumped" : "consistent");
  f.add("[newton] residual_tolerance", fmt::format("{}", sc.newton.residual_tolerance),
        [&](Hasher& h) { h.value(sc.newton.residual_tolerance); });
  // these change the iterates at round-off level
  f.setting("[solver] method", sc.solver.method);
  f.setting("[solver] preconditioner", sc.solver.preconditioner);
  f.setting("[solver] gamg_from", fmt::format("{}", sc.solver.gamg_from));
  f.setting("[solver] max_linear_iterations", fmt::format("{}", sc.solver.max_linear_iterations));
  f.add("[solver] forcing_max", fmt::format("{}", sc.solver.forcing_max),
        [&](Hasher& h) { h.value(sc.solver.forcing_max); });
  f.setting("[solver] modified_newton", sc.solver.modified_newton ? "true" : "false");
  f.setting("[solver] petsc_options", sc.solver.petsc_options);
  // how contact is resolved changes the trajectory ([active_set]
  // max_passes does not, unless a step fails: it may be raised to get past one)
  f.setting("[active_set] scheme", sc.active_set.scheme == io::ContactScheme::persistent ? "persistent" : "paper");
  f.setting("[active_set] locate_impacts", sc.active_set.locate_impacts ? "true" : "false");
  f.setting("[active_set] locate_releases", sc.active_set.locate_releases ? "true" : "false");
  f.add("[active_set] gap_tolerance", fmt::format("{}", sc.active_set.gap_tolerance),
        [&](Hasher& h) { h.value(sc.active_set.gap_tolerance); });
  f.add("[active_set] cluster_tolerance", fmt::format("{}", sc.active_set.cluster_tolerance),
        [&](Hasher& h) { h.value(sc.active_set.cluster_tolerance); });
  f.setting("contact pairs", fmt::format("{}", sc.contacts.size()));
  for (std::size_t i = 0; i < sc.contacts.size(); ++i) add_contact(f, i, sc.contacts[i]);
  return f.take();
}

std::string first_difference(const Fingerprint& checkpoint, const Fingerprint& scenario) {
  // Nodes numbered for one rank count (simulation/rank_numbering.hpp).
  const FingerprintEntry *was = find(checkpoint, kRankNumbering), *is = find(scenario, kRankNumbering);
  const int ranks = solver::ranks::size();
  const std::string run = fmt::format("this run has {} rank{}", ranks, ranks == 1 ? "" : "s");
  if (was && (!is || was->value != is->value))
    return fmt::format(
        "the checkpoint was written on {} ranks, whose graph parts number its nodes, and {}{}: restart "
        "on {} ranks (or run both with [solver] partition = \"ranges\", the same numbering on any "
        "rank count)",
        was->value, run, is ? "" : " numbering them as the meshes do", was->value);
  if (is && !was)
    return fmt::format(
        "the checkpoint's nodes are numbered as the meshes number them, and {} numbering them by "
        "their graph parts: run with [solver] partition = \"ranges\"",
        run);
  for (const auto& was : checkpoint) {
    const FingerprintEntry* is = find(scenario, was.name);
    if (!is) return fmt::format("{} is not in this scenario", was.name);
    if (is->hash == was.hash) continue;
    if (!was.value.empty() && !is->value.empty() && was.value != is->value)
      return fmt::format("the checkpoint was written with {} = {}, this scenario has {}", was.name, was.value,
                         is->value);
    return fmt::format("{} {}", was.name, was.name.back() == 's' ? "differ" : "differs");
  }
  for (const auto& is : scenario)
    if (!find(checkpoint, is.name)) return fmt::format("{} is not in the checkpoint", is.name);
  return {};
}

template Fingerprint scenario_fingerprint<2>(const io::Scenario&, const model::Model<2>&);
template Fingerprint scenario_fingerprint<3>(const io::Scenario&, const model::Model<3>&);

}  // namespace conserve::simulation
