#include "simulation/setup.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <set>
#include <unordered_map>

#include "contact/surface.hpp"
#include "core/error.hpp"
#include "mesh/generators.hpp"
#include "mesh/stl_reader.hpp"
#include "mesh/surface_mesh.hpp"
#include "mesh/topology.hpp"
#include "material/law.hpp"
#include "model/initial_state.hpp"
#include "simulation/rank_numbering.hpp"
#include "solver/ordering.hpp"
#include "solver/ranks.hpp"
#include "time/integrator.hpp"

namespace conserve::simulation {
namespace {

/// "FILE:LINE: PATH (body 'NAME'): WHAT": an error found while building
/// body `i`, at its scenario key `key` ("mesh.file", "mesh.group").
InputError body_error(const io::Scenario& scenario, std::size_t i, std::string_view key, std::string_view what) {
  return InputError(fmt::format("{} (body '{}'): {}", scenario.sources.locate(fmt::format("body[{}].{}", i, key)),
                                scenario.bodies[i].name, what));
}

/// f(), with an InputError it throws located at key `key` of body `i`.
template <class F>
auto at_key(const io::Scenario& scenario, std::size_t i, std::string_view key, F&& f) {
  try {
    return f();
  } catch (const InputError& e) {
    throw body_error(scenario, i, key, e.what());
  }
}

/// A body's mesh, rotated and translated. A generated mesh's nodes are renumbered in
/// reverse Cuthill–McKee order and its cells follow them (a generator's
/// numbering is its own: Gmsh's scatters a cell's nodes across the whole
/// body, and every cell loop and ILU(0) pays for it). A file's numbering
/// is kept unless `reorder` asks otherwise: outputs and messages then name
/// its nodes and cells as the file does.
mesh::Mesh body_mesh(const io::Scenario& scenario, std::size_t i, int dim) {
  const io::BodySpec& spec = scenario.bodies[i];
  mesh::Mesh m;
  if (spec.mesh.generator.empty()) {
    const auto bare = spec.rigid ? mesh::BareSurface::accepted : mesh::BareSurface::rejected;
    m = at_key(scenario, i, "mesh.file", [&] { return mesh::read_mesh_file(spec.mesh.file, dim, bare); });
    if (m.num_cells() == 0 && !spec.mesh.group.empty())
      throw body_error(scenario, i, "mesh.group", "the mesh is a bare surface, without cells to choose from");
    if (m.num_cells() > 0) m = at_key(scenario, i, "mesh.group", [&] { return mesh::extract(m, spec.mesh.group); });
    if (spec.mesh.flip_normals && m.num_cells() > 0)
      throw body_error(scenario, i, "mesh.flip_normals",
                       "the mesh has cells, whose facets face outward (only a bare surface's can be flipped)");
    if (spec.mesh.flip_normals) mesh::flip_normals(m);
  } else {
    m = at_key(scenario, i, "mesh.generator",
               [&] { return mesh::generate_mesh(spec.mesh.generator, spec.mesh.parameters); });
  }
  if ((!spec.mesh.generator.empty() || spec.mesh.reorder) && m.num_cells() > 0) {
    std::vector<int> offsets, neighbours;
    mesh::node_graph(m, offsets, neighbours);
    m = mesh::renumbered(m, solver::reverse_cuthill_mckee(offsets, neighbours));
  }
  if (!spec.rotate.isIdentity()) m.points = spec.rotate.topLeftCorner(m.dim, m.dim) * m.points;
  m.points.colwise() += spec.translate.head(m.dim);
  return m;
}

/// Placeholder material of a rigid body given without elastic constants:
/// its cells' rows are all held (prescribed or moved by its free-body
/// unknowns), so the Lamé constants never act on a free dof (and a rigid
/// motion has no strain anyway). Without a density too (0), the body is
/// massless, like a bare surface, and adds nothing to the energies and
/// momenta.
io::MaterialSpec rigid_placeholder(double density) {
  return {.model = "svk", .parameters = {{"young", 1.0}, {"poisson", 0.0}}, .density = density};
}

/// Adds body `i` of the scenario to the model, with its mesh (body_mesh).
template <int D>
void add_body(const io::Scenario& scenario, std::size_t i, const mesh::Mesh& mesh, model::Model<D>& model) {
  const io::BodySpec& spec = scenario.bodies[i];
  const bool placeholder = spec.rigid && (!(spec.material.density > 0.0) || spec.material.parameters.empty());
  const io::MaterialSpec material = placeholder ? rigid_placeholder(spec.material.density) : spec.material;
  auto law = at_key(scenario, i, "material", [&] { return material::make_law(material.model, material.parameters); });
  const char* mesh_key = spec.mesh.generator.empty() ? "mesh.file" : "mesh.generator";
  if (mesh.num_cells() == 0 && !spec.rigid)
    throw body_error(scenario, i, mesh_key,
                     "the mesh has no cells; only a rigid body may be a bare surface (set rigid = true)");
  if (mesh.num_cells() == 0 && spec.free)
    throw body_error(scenario, i, mesh_key,
                     "the mesh has no cells; a free rigid body needs them (its mass, centre and inertia come from "
                     "them and its density)");
  if (spec.mean_dilatation && mesh.order() != 2)
    throw body_error(scenario, i, "dilatation",
                     "`mean` needs quadratic cells ([body.mesh] order = 2, or a .msh file of second-order elements)");
  at_key(scenario, i, mesh_key,
         [&] { model::add_body<D>(model, mesh, spec.name, std::move(law), material.density, spec.thickness); });
  model.bodies.back().mean_dilatation = spec.mean_dilatation;
}

/// The index of curve `name` in the model's curves (−1 for none).
int curve_index(const io::Scenario& scenario, const std::string& name) {
  if (name.empty()) return -1;
  for (std::size_t k = 0; k < scenario.curves.size(); ++k)
    if (scenario.curves[k].name == name) return static_cast<int>(k);
  throw InputError(fmt::format("{}: no [[curve]] named '{}'", scenario.file.string(), name));  // the parser checks
}

/// The support named `name`, appended if there is none yet.
model::Support& support_named(model::Prescribed& prescribed, const std::string& name) {
  for (model::Support& s : prescribed.supports)
    if (s.name == name) return s;
  return prescribed.supports.emplace_back(model::Support{name, {}});
}

/// Every dof of a rigid body. A translation at a constant velocity is
/// u = velocity · t exactly; a turning or curve-driven body follows its
/// rigid motion (model/prescribed.hpp).
template <int D>
void prescribe_rigid(const io::Scenario& scenario, const io::BodySpec& spec, const model::Body& body,
                     const model::Model<D>& model, model::Prescribed& prescribed) {
  const bool plain = spec.angular_velocity.isZero() && spec.velocity_curve.empty() && spec.angular_velocity_curve.empty();
  model::Support& support = support_named(prescribed, body.name);
  for (int n = body.first_node; n < body.first_node + body.num_nodes; ++n)
    for (int k = 0; k < D; ++k) {
      support.entries.push_back(static_cast<int>(prescribed.dofs.size()));
      prescribed.dofs.push_back(model::dof<D>(n, k));
      prescribed.value.push_back(0.0);
      prescribed.rate.push_back(plain ? spec.velocity[k] : 0.0);
      prescribed.curve.push_back(-1);
    }
  if (plain) return;
  model::RigidMotion m{.first_node = body.first_node, .num_nodes = body.num_nodes};
  if (spec.center) {
    m.center = *spec.center;
  } else if (body.num_nodes > 0) {
    const auto X = model.X.middleCols(body.first_node, body.num_nodes);
    m.center.head<D>() = 0.5 * (X.rowwise().minCoeff() + X.rowwise().maxCoeff());
  }
  if constexpr (D == 2) m.center.z() = 0.0;
  m.velocity = spec.velocity;
  m.omega = D == 3 ? spec.angular_velocity : Vec3(0.0, 0.0, spec.angular_velocity.z());
  m.velocity_curve = curve_index(scenario, spec.velocity_curve);
  m.omega_curve = curve_index(scenario, spec.angular_velocity_curve);
  prescribed.rigid.push_back(m);
}

/// The surface loads, on the facets of their groups (contact::make_surface
/// checks that the group exists and lies on the body's boundary, and
/// orients it outward), and the gravity's curve.
template <int D>
void add_loads(const io::Scenario& scenario, model::Model<D>& model) {
  model.gravity_curve = curve_index(scenario, scenario.gravity_curve);
  for (std::size_t i = 0; i < scenario.loads.size(); ++i) {
    const io::LoadSpec& spec = scenario.loads[i];
    const auto body = std::find_if(model.bodies.begin(), model.bodies.end(),
                                   [&](const model::Body& b) { return b.name == spec.body; });
    model::SurfaceLoad load;
    load.body = static_cast<int>(body - model.bodies.begin());
    try {
      load.facets = contact::make_surface<D>(model, load.body, spec.group).facets;
    } catch (const InputError& e) {
      std::string what = e.what();
      if (const std::string prefix = "contact surface: "; what.rfind(prefix, 0) == 0) what.erase(0, prefix.size());
      throw InputError(fmt::format("{}: {}", scenario.sources.locate(fmt::format("load[{}].group", i)), what));
    }
    load.kind = spec.pressure ? model::SurfaceLoad::Kind::pressure : model::SurfaceLoad::Kind::traction;
    load.traction = spec.traction;
    load.pressure = spec.pressure_value;
    load.curve = curve_index(scenario, spec.curve);
    load.thickness = body->thickness;
    model.loads.push_back(std::move(load));
  }
}

template <int D>
void add_prescribed(const io::Scenario& scenario, model::Model<D>& model) {
  for (const io::CurveSpec& c : scenario.curves) {
    model::Curve curve;
    for (const auto& [t, value] : c.points) curve.t.push_back(t), curve.value.push_back(value);
    model.prescribed.curves.push_back(std::move(curve));
  }
  std::set<int> seen;
  const auto where = [&](std::size_t i, std::string_view key) {
    return scenario.sources.locate(fmt::format("boundary[{}].{}", i, key));
  };
  for (std::size_t i = 0; i < scenario.boundaries.size(); ++i) {
    const io::BoundarySpec& bc = scenario.boundaries[i];
    const auto body =
        std::find_if(model.bodies.begin(), model.bodies.end(), [&](const model::Body& b) { return b.name == bc.body; });
    if (body == model.bodies.end())
      throw InputError(fmt::format("{}: no body named '{}'", where(i, "body"), bc.body));
    if (scenario.bodies[static_cast<std::size_t>(body - model.bodies.begin())].rigid)
      throw InputError(
          fmt::format("{}: body '{}' is rigid: all its degrees of freedom are already prescribed (remove this "
                      "[[boundary]])",
                      where(i, "body"), bc.body));
    std::vector<int> nodes;
    try {
      nodes = model::group_nodes(*body, bc.group);
    } catch (const InputError& e) {
      throw InputError(fmt::format("{}: {}", where(i, "group"), e.what()));
    }
    model::Support& support = support_named(model.prescribed, bc.body + ":" + bc.group);
    for (int n : nodes)
      for (int k : bc.components) {
        const int d = model::dof<D>(n, k);
        if (!seen.insert(d).second)
          throw InputError(fmt::format("{}: node {} component {} of body '{}' is already prescribed",
                                       where(i, "components"), n - body->first_node, "xyz"[k], bc.body));
        support.entries.push_back(static_cast<int>(model.prescribed.dofs.size()));
        model.prescribed.dofs.push_back(d);
        model.prescribed.value.push_back(bc.value[k]);
        model.prescribed.rate.push_back(bc.rate[k]);
        model.prescribed.curve.push_back(curve_index(scenario, bc.curve));
      }
  }
  for (std::size_t i = 0; i < scenario.bodies.size(); ++i) {
    const io::BodySpec& spec = scenario.bodies[i];
    const model::Body& body = model.bodies[i];
    if (spec.free)
      model.free_bodies.push_back({.body = static_cast<int>(i), .first_node = body.first_node, .num_nodes = body.num_nodes});
    else if (spec.rigid)
      prescribe_rigid<D>(scenario, spec, body, model, model.prescribed);
  }
}

template <int D>
using Positions = Eigen::Matrix<double, D, Eigen::Dynamic>;

/// The cells of one body that meet a box, binned on a uniform grid by their
/// bounding boxes.
template <int D>
class CellGrid {
 public:
  using Box = Eigen::AlignedBox<double, D>;
  CellGrid(const model::Model<D>& model, const model::Body& body, const Positions<D>& x, const Box& within)
      : model_(model), x_(x) {
    double extent = 0.0;
    for (int c = body.first_cell; c < body.first_cell + body.num_cells; ++c) extent += box(c).sizes().maxCoeff();
    h_ = std::max(extent / std::max(body.num_cells, 1), 1e-300);
    for (int c = body.first_cell; c < body.first_cell + body.num_cells; ++c) {
      const auto b = box(c);
      if (!b.intersects(within)) continue;
      bounds_.extend(b);
      const Eigen::Array<long, D, 1> lo = key_of(b.min()), hi = key_of(b.max());
      for_each_key(lo, hi, [&](long k) { bins_[k].push_back(c); });
    }
  }

  /// A cell containing `p` strictly inside (barycentric coordinates all
  /// above a round-off tolerance, so that touching bodies pass), or -1.
  [[nodiscard]] int cell_containing(const Vec<D>& p) const {
    if (bounds_.isEmpty() || !bounds_.contains(p)) return -1;
    const auto it = bins_.find(flat(key_of(p)));
    if (it == bins_.end()) return -1;
    for (int c : it->second)
      if (strictly_inside(c, p)) return c;
    return -1;
  }

 private:
  [[nodiscard]] Box box(int c) const {
    Box b;
    for (int a = 0; a < model_.cells.rows(); ++a) b.extend(x_.col(model_.cells(a, c)));  // a quadratic cell's midside nodes too
    return b;
  }
  [[nodiscard]] Eigen::Array<long, D, 1> key_of(const Vec<D>& p) const {
    return (p.array() / h_).floor().template cast<long>();
  }
  [[nodiscard]] static long flat(const Eigen::Array<long, D, 1>& k) {
    long key = 0;
    for (int i = 0; i < D; ++i) key = key * 2000003L + k[i];
    return key;
  }
  template <class F>
  void for_each_key(const Eigen::Array<long, D, 1>& lo, const Eigen::Array<long, D, 1>& hi, F&& f) const {
    Eigen::Array<long, D, 1> k = lo;
    for (;;) {
      f(flat(k));
      int i = 0;
      while (i < D && k[i] == hi[i]) k[i] = lo[i], ++i;
      if (i == D) return;
      ++k[i];
    }
  }
  [[nodiscard]] bool strictly_inside(int c, const Vec<D>& p) const {
    Mat<D> J;
    const Vec<D> x0 = x_.col(model_.cells(0, c));
    for (int a = 0; a < D; ++a) J.col(a) = x_.col(model_.cells(a + 1, c)) - x0;
    const Vec<D> lambda = J.partialPivLu().solve(p - x0);
    constexpr double tol = 1e-8;
    return lambda.minCoeff() > tol && 1.0 - lambda.sum() > tol;
  }

  const model::Model<D>& model_;
  const Positions<D>& x_;
  double h_ = 1.0;
  Box bounds_;
  std::unordered_map<long, std::vector<int>> bins_;
};

/// Throws InputError if a node of one body lies strictly inside a cell of
/// another in the initial configuration x0 = X + u0 (bodies may touch).
template <int D>
void check_overlaps(const io::Scenario& scenario, const model::Model<D>& model, const Eigen::VectorXd& u0) {
  const Positions<D> x = model.X + u0.reshaped(D, model.num_nodes());
  for (std::size_t b = 0; b < model.bodies.size(); ++b) {
    const model::Body& host = model.bodies[b];
    if (host.num_cells == 0) continue;
    // Only the other bodies' nodes within the host's box can be inside it:
    // its cells that meet their box are binned, none if there are none.
    typename CellGrid<D>::Box host_box, probes;
    for (int n = host.first_node; n < host.first_node + host.num_nodes; ++n) host_box.extend(x.col(n));
    for (std::size_t a = 0; a < model.bodies.size(); ++a)
      if (a != b)
        for (int n = model.bodies[a].first_node; n < model.bodies[a].first_node + model.bodies[a].num_nodes; ++n)
          if (host_box.contains(x.col(n))) probes.extend(x.col(n));
    if (probes.isEmpty()) continue;
    const CellGrid<D> grid(model, host, x, probes);
    for (std::size_t a = 0; a < model.bodies.size(); ++a) {
      if (a == b) continue;
      const model::Body& guest = model.bodies[a];
      for (int n = guest.first_node; n < guest.first_node + guest.num_nodes; ++n) {
        const int c = grid.cell_containing(x.col(n));
        if (c < 0) continue;
        throw InputError(
            fmt::format("{}: bodies '{}' and '{}' overlap at t = 0: node {} of '{}' at ({}) is inside cell {} of '{}' "
                        "(move them apart, e.g. with translate)",
                        scenario.sources.locate(fmt::format("body[{}].translate", a)), guest.name, host.name, n - guest.first_node, guest.name,
                        fmt::join(x.col(n).data(), x.col(n).data() + D, ", "), c - host.first_cell, host.name));
      }
    }
  }
}

/// The largest magnitude a derived scale may have: the solver sums squares
/// of forces (norms), so a scale's square must stay finite in double
/// precision (1.8e308).
constexpr double kLargestScale = 1e150;

/// One derived scale of a body and the keys it comes from.
struct Scale {
  const char* what;  ///< e.g. "elastic force scale (λ + 2μ)·V/L"
  const char* unit;
  double value;
  const char* keys;  ///< the scenario keys that set it
};

/// Throws InputError naming the keys if a body's derived force or energy
/// scales are not finite or too large for the solver's norms (young =
/// 1e308 gives an infinite elastic force scale, density = 1e308 an
/// infinite inertia).
template <int D>
void check_scales(const io::Scenario& scenario, const model::Model<D>& model) {
  const double dt = scenario.time.step, g = scenario.gravity.norm();
  for (std::size_t b = 0; b < model.bodies.size(); ++b) {
    const io::BodySpec& spec = scenario.bodies[b];
    if (spec.rigid) continue;  // prescribed: its material never acts
    const model::Body& body = model.bodies[b];
    double volume = 0.0;
    for (int c = body.first_cell; c < body.first_cell + body.num_cells; ++c) volume += model.cell_volume(c);
    const auto X = model.X.middleCols(body.first_node, body.num_nodes);
    const double size = (X.rowwise().maxCoeff() - X.rowwise().minCoeff()).norm();
    const material::Lame lame = body.law->small_strain();
    const double modulus = lame.lambda + 2.0 * lame.mu, mass = body.density * volume;
    const double speed = spec.velocity.norm() + spec.angular_velocity.norm() * size;
    std::string law_keys;  // "material.young and material.poisson"
    for (const auto& p : material::law_catalog().at(spec.material.model).parameters)
      law_keys += (law_keys.empty() ? "material." : " and material.") + p.name;
    const Scale scales[] = {
        {"P-wave modulus λ + 2μ", "Pa", modulus, law_keys.c_str()},
        {"elastic force scale (λ + 2μ)·V/L", "N", modulus * volume / size, law_keys.c_str()},
        {"elastic energy scale (λ + 2μ)·V", "J", modulus * volume, law_keys.c_str()},
        {"mass", "kg", mass, "material.density"},
        {"inertia force scale m·L/Δt²", "N", mass * size / (dt * dt), "material.density and time.step"},
        {"momentum force scale 2 m v/Δt", "N", 2.0 * mass * speed / dt, "material.density, velocity and time.step"},
        {"kinetic energy scale m v²/2", "J", 0.5 * mass * speed * speed, "material.density and velocity"},
        {"weight m g", "N", mass * g, "material.density and loads.gravity"},
    };
    for (const Scale& sc : scales)
      if (!(std::abs(sc.value) <= kLargestScale))
        throw InputError(fmt::format(
            "{} (body '{}'): {}: its {} is {:.3g} {}, beyond what the solver can hold in double precision "
            "(at most {:g} {}, so that norms of forces stay finite)",
            scenario.sources.locate(fmt::format("body[{}].material", b)), spec.name, sc.keys, sc.what, sc.value, sc.unit, kLargestScale, sc.unit));
  }
}

}  // namespace

template <int D>
Problem<D> setup(const io::Scenario& scenario) {
  Problem<D> p;
  std::vector<mesh::Mesh> meshes;
  std::vector<bool> renumber;  // the body's numbering is the program's
  for (std::size_t i = 0; i < scenario.bodies.size(); ++i) {
    meshes.push_back(body_mesh(scenario, i, D));
    renumber.push_back(!scenario.bodies[i].mesh.generator.empty() || scenario.bodies[i].mesh.reorder);
  }
  // On several ranks each owns a range of the nodes holding about equal
  // shares of the cells' corners (the assembly's work).
  if (const int ranks = solver::ranks::size(); ranks > 1) {
    const RankNumbering n = number_for_ranks(meshes, renumber, ranks, scenario.solver.graph_partition);
    p.model.rank_nodes = n.rank_nodes;
    p.model.rank = solver::ranks::rank();
    p.model.numbered_for_ranks = n.by_parts ? ranks : 0;
  }
  for (std::size_t i = 0; i < scenario.bodies.size(); ++i) add_body<D>(scenario, i, meshes[i], p.model);
  meshes = {};
  check_scales<D>(scenario, p.model);
  p.model.gravity = scenario.gravity.head<D>();
  add_prescribed<D>(scenario, p.model);
  add_loads<D>(scenario, p.model);
  p.initial = model::rest_state<D>(p.model);
  for (std::size_t i = 0; i < scenario.bodies.size(); ++i) {
    const io::BodySpec& spec = scenario.bodies[i];
    if (spec.rigid && !spec.free) continue;  // fully prescribed: u and v come from apply_prescribed below
    model::set_initial_motion<D>(p.model, static_cast<int>(i),
                                 {spec.initial_deformation, spec.velocity, spec.angular_velocity}, p.initial);
  }
  // A free body turns about its centre of mass, the centroid of its cells
  // (time::FreeBodies takes its nodes' arms from the same point).
  for (const model::FreeBody& b : p.model.free_bodies) {
    const io::BodySpec& spec = scenario.bodies[static_cast<std::size_t>(b.body)];
    model::RigidBodyState s;
    s.center.head<D>() = model::body_centroid<D>(p.model, b.body, p.initial.u);
    s.velocity.head<D>() = spec.velocity.head<D>();
    s.spin = D == 3 ? spec.angular_velocity : Vec3(0.0, 0.0, spec.angular_velocity.z());
    p.initial.rigid.push_back(s);
  }
  model::apply_prescribed<D>(p.model.prescribed, p.model.X, 0.0, p.initial.u, &p.initial.v);
  check_overlaps<D>(scenario, p.model, p.initial.u);
  return p;
}

template Problem<2> setup<2>(const io::Scenario&);
template Problem<3> setup<3>(const io::Scenario&);

}  // namespace conserve::simulation
