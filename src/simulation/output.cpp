#include "simulation/output.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "contact/debug_output.hpp"
#include "core/error.hpp"
#include "solver/ranks.hpp"

namespace conserve::simulation {

std::vector<std::string> history_columns(const std::vector<std::string>& body_names,
                                         const std::vector<std::string>& pair_names,
                                         const std::vector<std::string>& support_names,
                                         const std::vector<std::string>& free_names,
                                         const std::vector<contact::MethodStatistic>& own) {
  std::vector<std::string> c = {"step", "time", "kinetic", "strain", "potential", "total",
                                "L_x",  "L_y",  "L_z",     "J_x",    "J_y",       "J_z"};
  for (std::string& s : statistic_columns(own)) c.push_back(std::move(s));
  c.insert(c.end(), {"drift_E", "drift_L", "drift_J"});
  for (const auto& name : body_names)
    for (const char* axis : {"x", "y", "z"}) c.push_back(fmt::format("L_{}:{}", axis, name));
  for (const auto& name : pair_names)
    for (const char* axis : {"x", "y", "z"}) c.push_back(fmt::format("F_{}:{}", axis, name));
  for (const auto& name : support_names) {
    for (const char* quantity : {"R", "M", "u"})
      for (const char* axis : {"x", "y", "z"}) c.push_back(fmt::format("{}_{}:{}", quantity, axis, name));
    c.push_back("work:" + name);
  }
  for (const auto& name : free_names)
    for (const char* axis : {"x", "y", "z"}) c.push_back(fmt::format("w_{}:{}", axis, name));
  return c;
}

namespace {
/// The contact method's own statistics (none without contact).
template <int D>
const std::vector<contact::MethodStatistic>& own_statistics(const contact::Method<D>* contacts) {
  static const std::vector<contact::MethodStatistic> none;
  return contacts ? contacts->statistics() : none;
}

template <int D>
std::vector<std::string> body_names(const model::Model<D>& model) {
  std::vector<std::string> names;
  for (const auto& b : model.bodies) names.push_back(b.name);
  return names;
}

template <int D>
std::vector<std::string> free_names(const model::Model<D>& model) {
  std::vector<std::string> names;
  for (const auto& b : model.free_bodies) names.push_back(model.bodies[static_cast<std::size_t>(b.body)].name);
  return names;
}

template <int D>
std::vector<std::string> support_names(const model::Model<D>& model) {
  std::vector<std::string> names;
  for (const auto& s : model.prescribed.supports) names.push_back(s.name);
  return names;
}

template <int D>
std::vector<std::string> pair_names(const contact::Method<D>* contacts) {
  std::vector<std::string> names;
  if (contacts)
    for (const auto& p : const_cast<contact::Method<D>*>(contacts)->pairs())
      names.push_back(p.slave.name + ">" + p.master.name);
  return names;
}

/// Appends the distinct facets of every body without cells to `facets`
/// (D × n) and its index to `body` per facet.
template <int D>
void add_bare_surfaces(const model::Model<D>& model, Eigen::MatrixXi& facets, std::vector<int>& body) {
  facets.resize(D, 0);
  for (std::size_t b = 0; b < model.bodies.size(); ++b) {
    if (model.bodies[b].num_cells > 0) continue;
    const Eigen::MatrixXi f = model::distinct_facets(model.bodies[b]);
    if (f.cols() == 0) continue;
    facets.conservativeResize(D, facets.cols() + f.cols());
    facets.rightCols(f.cols()) = f;
    body.insert(body.end(), static_cast<std::size_t>(f.cols()), static_cast<int>(b));
  }
}

/// Length (2D) or area (3D) of facet f of `surface` at positions x.
template <int D>
double facet_measure(const contact::ContactSurface& surface, int f, const contact::Positions<D>& x) {
  const Vec<D> a = x.col(surface.facets(1, f)) - x.col(surface.facets(0, f));
  if constexpr (D == 2) {
    return a.norm();
  } else {
    const Vec<D> b = x.col(surface.facets(2, f)) - x.col(surface.facets(0, f));
    return 0.5 * a.cross(b).norm();
  }
}

/// The part of facet f's measure (`measure`) that node `node` of it takes
/// for its contact pressure: 1/D of a linear facet's; of a quadratic one, split into
/// sub-facets at its edges' middles (4 triangles, 2 segments) shared
/// equally by their corners, 1/12 at a vertex and 1/4 at an edge's middle
/// (2D: 1/4 and 1/2). (The consistent ∫N_a dA is 0 at a 6-node triangle's
/// vertices.)
template <int D>
double tributary_area(const contact::ContactSurface& surface, int f, int node, double measure) {
  if (!contact::quadratic<D>(surface)) return measure / D;
  int a = 0;
  while (surface.facets(a, f) != node) ++a;
  if constexpr (D == 3)
    return measure * (a < D ? 1.0 / 12.0 : 0.25);
  else
    return measure * (a < D ? 0.25 : 0.5);
}

/// The mean displacement of the nodes of support `s` (of the dofs it
/// prescribes: a component it leaves free counts as 0) [m].
template <int D>
Vec3 mean_displacement(const model::Model<D>& model, const model::Support& s, const Eigen::VectorXd& u) {
  Vec3 sum = Vec3::Zero();
  std::set<int> nodes;
  for (int e : s.entries) {
    const int d = model.prescribed.dofs[static_cast<std::size_t>(e)];
    sum[d % D] += u[d];
    nodes.insert(d / D);
  }
  return nodes.empty() ? sum : sum / static_cast<double>(nodes.size());
}

std::filesystem::path prepared(const std::filesystem::path& dir, int vtu_every) {
  std::error_code ec;
  std::filesystem::create_directories(vtu_every > 0 ? dir / "vtu" : dir, ec);
  if (ec) throw Error(fmt::format("cannot create output directory {}: {}", dir.string(), ec.message()));
  return dir;
}
}  // namespace

template <int D>
OutputWriter<D>::OutputWriter(const assembly::Assembler<D>& assembler, const std::filesystem::path& directory,
                              const io::OutputSpec& spec, contact::Method<D>* contacts,
                              std::optional<double> resume_time)
    : assembler_(assembler),
      contacts_(contacts),
      contact_state_(spec.contact_state && contacts),
      directory_(solver::ranks::root() ? prepared(directory, spec.vtu_every) : directory),
      vtu_every_(spec.vtu_every),
      format_{.compress = spec.compress, .single_precision = spec.single_precision},
      rank_(solver::ranks::rank()),
      ranks_(solver::ranks::size()) {
  if (rank_ == 0)
    history_.emplace(
        directory / "history.csv",
        history_columns(body_names(assembler.model()), pair_names<D>(contacts), support_names<D>(assembler.model()),
                        free_names<D>(assembler.model()), own_statistics(contacts)));
  if (resume_time) last_time_ = *resume_time;
  add_bare_surfaces<D>(assembler.model(), surface_facets_, surface_body_);
  if (spec.vtu_every > 0) pvd_ = std::make_unique<io::PvdWriter>(directory / "solution.pvd");
  if (pvd_ && resume_time) pvd_->resume(*resume_time);
}

template <int D>
void OutputWriter<D>::write(const model::State& state, const StepFigures& figures, const Drifts& drift, bool last) {
  const time::Diagnostics& d = figures.diagnostics;
  std::vector<double> row = {static_cast<double>(state.step),
                             state.time,
                             d.kinetic,
                             d.strain,
                             d.potential,
                             d.total,
                             d.linear.x(),
                             d.linear.y(),
                             d.linear.z(),
                             d.angular.x(),
                             d.angular.y(),
                             d.angular.z()};
  for (double v : statistic_values(figures, own_statistics(contacts_))) row.push_back(v);
  row.insert(row.end(), {drift.energy, drift.linear, drift.angular});
  for (const Vec3& L : d.body_linear) row.insert(row.end(), {L.x(), L.y(), L.z()});
  if (contacts_) {
    // What each pair's master gave its slaves over the step, as mean
    // forces (the persistency impulses spread over the step).
    const double dt = state.time - last_time_;
    const double per_time = dt > 0.0 ? 1.0 / dt : 0.0;
    std::vector<Vec3> pair_force(contacts_->pairs().size(), Vec3::Zero());
    for (const auto& f : contacts_->contact_forces())
      pair_force.at(f.pair).template head<D>() += f.force + per_time * f.impulse;
    for (const Vec3& F : pair_force) row.insert(row.end(), {F.x(), F.y(), F.z()});
  }
  const auto& supports = assembler_.model().prescribed.supports;
  for (std::size_t s = 0; s < supports.size(); ++s) {
    const time::SupportReaction r =
        s < figures.record.supports.size() ? figures.record.supports[s] : time::SupportReaction{};
    row.insert(row.end(), {r.force.x(), r.force.y(), r.force.z(), r.moment.x(), r.moment.y(), r.moment.z()});
    const Vec3 u = mean_displacement<D>(assembler_.model(), supports[s], state.u);
    row.insert(row.end(), {u.x(), u.y(), u.z(), state.support_work.at(s)});
  }
  for (const model::RigidBodyState& b : state.rigid) row.insert(row.end(), {b.spin.x(), b.spin.y(), b.spin.z()});
  last_time_ = state.time;
  if (history_) history_->write_row(row);
  if (pvd_ && (state.step % vtu_every_ == 0 || last)) write_vtu(state);
}

template <int D>
void OutputWriter<D>::write_vtu(const model::State& state) {
  const auto& model = assembler_.model();
  io::VtuGrid grid;
  grid.points = model.X + state.u.reshaped(D, model.num_nodes());
  // On several ranks each writes the cells whose first node it owns (its
  // held cells are those with any corner among its nodes), and rank 0 the
  // bare surfaces.
  std::vector<int> written;
  written.reserve(static_cast<std::size_t>(model.num_cells()));
  for (int c = 0; c < model.num_cells(); ++c)
    if (ranks_ == 1 || model.owns(model.cells(0, c))) written.push_back(c);
  const auto cells = static_cast<Eigen::Index>(written.size());
  const auto facets = ranks_ == 1 || rank_ == 0 ? surface_facets_.cols() : Eigen::Index{0};
  const auto nodes = static_cast<int>(model.cells.rows());  // D + 1, or a quadratic cell's
  grid.cells = Eigen::MatrixXi::Zero(nodes, cells + facets);
  for (Eigen::Index k = 0; k < cells; ++k) grid.cells.col(k) = model.cells.col(written[static_cast<std::size_t>(k)]);
  grid.cells.block(0, cells, D, facets) = surface_facets_.leftCols(facets);
  if (facets > 0) {  // mixed: simplices of `nodes` nodes, then facets of D
    grid.nodes_per_cell.assign(static_cast<std::size_t>(cells), nodes);
    grid.nodes_per_cell.resize(static_cast<std::size_t>(cells + facets), D);
  }
  if (model.order != 1) {  // a quadratic cell's node count does not tell its type
    grid.types.assign(static_cast<std::size_t>(cells), io::vtk_cell_type(D, nodes));
    grid.types.resize(static_cast<std::size_t>(cells + facets), io::vtk_cell_type(D - 1, D));
  }
  auto point_vector = [&](const char* name, const Eigen::VectorXd& v) {
    io::VtuField f{name, 3, std::vector<double>(3 * model.num_nodes(), 0.0)};
    for (int n = 0; n < model.num_nodes(); ++n)
      for (int i = 0; i < D; ++i) f.values[3 * n + i] = v[n * D + i];
    grid.point_data.push_back(std::move(f));
  };
  point_vector("displacement", state.u);
  point_vector("velocity", state.v);
  if (contacts_) add_contact_fields(state, grid);
  // Cauchy stress as ParaView's symmetric tensor (xx, yy, zz, xy, yz, xz).
  io::VtuField stress{"stress", 6, {}, {"xx", "yy", "zz", "xy", "yz", "xz"}}, mises{"von_mises", 1, {}},
      energy{"strain_energy_density", 1, {}}, body{"body", 1, {}};
  for (const int c : written) {
    const material::Law& law = *model.bodies[model.cell_body[c]].law;
    Mat3 sigma;
    double W = 0.0;
    if (model.order == 1) {
      const fem::NodeMatrix<D> x = assembler_.cell_positions(c, state.u);
      sigma = fem::cauchy_stress<D>(model.geometry[c], law, x);
      W = fem::strain_energy<D>(model.geometry[c], law, x);
    } else {
      const auto x = assembler_.template positions<fem::Quadratic<D>::kNodes>(c, state.u);
      if (model.bodies[model.cell_body[c]].mean_dilatation) {
        sigma = fem::cauchy_stress_mean_dilatation<D>(model.quadratic[c], law, x);
        W = fem::strain_energy_mean_dilatation<D>(model.quadratic[c], law, x);
      } else {
        sigma = fem::cauchy_stress<D>(model.quadratic[c], law, x);
        W = fem::strain_energy<D>(model.quadratic[c], law, x);
      }
    }
    stress.values.insert(stress.values.end(),
                         {sigma(0, 0), sigma(1, 1), sigma(2, 2), sigma(0, 1), sigma(1, 2), sigma(0, 2)});
    const Mat3 deviator = sigma - sigma.trace() / 3.0 * Mat3::Identity();
    mises.values.push_back(std::sqrt(1.5 * deviator.squaredNorm()));
    energy.values.push_back(W / model.cell_volume(c));
    body.values.push_back(model.cell_body[c]);
  }
  // Bare surfaces have no stress or energy density (NaN: undefined).
  const auto surfaces = static_cast<std::size_t>(facets);
  stress.values.resize(stress.values.size() + 6 * surfaces, std::nan(""));
  mises.values.resize(mises.values.size() + surfaces, std::nan(""));
  energy.values.resize(energy.values.size() + surfaces, std::nan(""));
  body.values.insert(body.values.end(), surface_body_.begin(), surface_body_.begin() + facets);
  grid.cell_data = {std::move(stress), std::move(mises), std::move(energy), std::move(body)};
  ++frames_;
  if (ranks_ == 1) {
    const std::string name = fmt::format("vtu/step_{:06d}.vtu", state.step);
    frame_bytes_ += io::write_vtu(directory_ / name, grid, format_);
    pvd_->add(state.time, name);
  } else {
    const auto piece_name = [&](int r) { return fmt::format("step_{:06d}_{}.vtu", state.step, r); };
    frame_bytes_ +=
        io::write_vtu(directory_ / "vtu" / piece_name(rank_), io::piece(grid, 0, grid.cells.cols()), format_);
    if (rank_ == 0) {
      std::vector<std::string> pieces;
      for (int r = 0; r < ranks_; ++r) pieces.push_back(piece_name(r));
      const std::string name = fmt::format("vtu/step_{:06d}.pvtu", state.step);
      io::write_pvtu(directory_ / name, grid, format_, pieces);
      pvd_->add(state.time, name);
    }
  }
  if (contact_state_ && rank_ == 0) write_contact_state(state);
}

template <int D>
void OutputWriter<D>::add_contact_fields(const model::State& state, io::VtuGrid& grid) const {
  const auto& model = assembler_.model();
  const int n = model.num_nodes();
  const double nan = std::nan("");
  const contact::Positions<D> x = model.X + state.u.reshaped(D, n);
  const auto& pairs = contacts_->pairs();
  // Per slave node: its tributary area (its share of each of its slave
  // facets, now, tributary_area; 2D: × the body's thickness) and its signed gap to the
  // master facet the search finds (NaN out of reach).
  io::VtuField gap{"contact_gap", 1, std::vector<double>(n, nan)},
      status{"contact_status", 1, std::vector<double>(n, nan)};
  std::vector<double> area(n, 0.0);
  for (const auto& pair : pairs) {
    contact::ContactPair<D> moved = pair;  // the pair's own tree is at the last search's positions
    moved.refit(x);
    const std::vector<Vec<D>> normals = contact::node_normals<D>(moved.slave, x);
    const double thickness = D == 2 ? model.bodies[pair.slave.body].thickness : 1.0;
    for (std::size_t i = 0; i < moved.slave.nodes.size(); ++i) {
      const int s = moved.slave.nodes[i];
      double a = 0.0;
      for (int f : moved.slave.node_facets[i]) a += tributary_area<D>(moved.slave, f, s, facet_measure<D>(moved.slave, f, x));
      if (area[s] == 0.0) area[s] = a * thickness;
      const auto match =
          contact::find_master<D>(x.col(s), moved.master, moved.tree, x, moved.search, normals[i], &moved.frames);
      if (match && !(std::abs(gap.values[s]) <= std::abs(match->projection.gap))) gap.values[s] = match->projection.gap;
      if (std::isnan(status.values[s])) status.values[s] = 0.0;  // open
    }
  }
  // Normal contact force f_N on active slaves [N] and its pressure [Pa];
  // NaN elsewhere, so that ParaView shows the active set by colour. A
  // slave holding two constraints shows the magnitude of f₁n₁ + f₂n₂,
  // signed as their sum. Status: 1 slipping (frictionless, or Coulomb on
  // its cone), 2 sticking. The tangential traction [Pa]: the part of the
  // slave's contact force off its normals, per area (zero where open).
  io::VtuField force{"contact_normal_force", 1, std::vector<double>(n, nan)},
      pressure{"contact_pressure", 1, std::vector<double>(n, nan)},
      traction{"contact_tangential_traction", 3, std::vector<double>(3 * static_cast<std::size_t>(n), 0.0)};
  struct Sum {
    Vec<D> normal = Vec<D>::Zero(), whole = Vec<D>::Zero();
    double signed_normal = 0.0;
  };
  std::map<int, Sum> total;  // per slave
  for (const auto& c : contacts_->contact_forces()) {
    Sum& sum = total[c.slave];
    sum.normal += c.normal * c.direction;
    sum.whole += c.force;
    sum.signed_normal += c.normal;
    status.values[c.slave] = c.sticks ? 2.0 : 1.0;
  }
  for (const auto& [slave, t] : total) {
    force.values[slave] = std::copysign(t.normal.norm(), t.signed_normal);
    if (!(area[slave] > 0.0)) continue;
    pressure.values[slave] = force.values[slave] / area[slave];
    const Vec<D> n = t.normal.norm() > 0.0 ? Vec<D>(t.normal.normalized()) : Vec<D>::Zero();
    const Vec<D> tangential = (t.whole - n * n.dot(t.whole)) / area[slave];
    for (int i = 0; i < D; ++i) traction.values[3 * static_cast<std::size_t>(slave) + i] = tangential[i];
  }
  grid.point_data.push_back(std::move(force));
  grid.point_data.push_back(std::move(pressure));
  grid.point_data.push_back(std::move(traction));
  grid.point_data.push_back(std::move(gap));
  grid.point_data.push_back(std::move(status));
}

// The slaves' contact state as the search sees it now (debugging output).
template <int D>
void OutputWriter<D>::write_contact_state(const model::State& state) const {
  const auto& model = assembler_.model();
  const contact::Positions<D> x = model.X + state.u.reshaped(D, model.num_nodes());
  const auto& pairs = contacts_->pairs();
  for (std::size_t p = 0; p < pairs.size(); ++p) {
    // A copy moved to x: the pair's own tree is at the positions of the
    // last search, which need not be this state's.
    contact::ContactPair<D> pair = pairs[p];
    pair.refit(x);
    const std::vector<Vec<D>> normals = contact::node_normals<D>(pair.slave, x);
    std::vector<std::optional<contact::Match<D>>> matches;
    for (std::size_t i = 0; i < pair.slave.nodes.size(); ++i)
      matches.push_back(contact::find_master<D>(x.col(pair.slave.nodes[i]), pair.master, pair.tree, x, pair.search,
                                                normals[i], &pair.frames));
    contact::write_contact_state_vtu<D>(directory_ / fmt::format("vtu/contact_{:06d}_pair{}.vtu", state.step, p),
                                        pair.slave.nodes, x, matches);
  }
}

template class OutputWriter<2>;
template class OutputWriter<3>;

}  // namespace conserve::simulation
