#include "time/integrator.hpp"

#include <fmt/format.h>

#include <cmath>
#include <optional>

#include "core/bytes.hpp"
#include "core/error.hpp"
#include "time/step_problem.hpp"

namespace conserve::time {

template <int D>
Integrator<D>::Integrator(const assembly::Assembler<D>& assembler, fem::StressScheme scheme,
                          solver::NewtonSettings newton, contact::Method<D>* contact, int max_passes,
                          const solver::LinearSolverSettings& linear)
    : assembler_(assembler),
      newton_(newton),
      K_(assembler.pattern().make_matrix()),
      terms_(elastodynamic_terms(assembler, scheme)),
      contact_(contact && !contact->collisions().empty() ? contact : nullptr),
      bodies_(assembler),
      max_passes_(max_passes),
      solver_(solver::make_linear_solver(linear, assembler.model().num_dofs())) {
  const model::Model<D>& model = assembler.model();
  mask_ = assembly::DirichletMask(K_, model.held_dofs(), {model.first_owned() * D, model.end_owned() * D});
  solver_->set_timings(&timings_);
  solver_->set_coordinates(model.X);
  solver_->set_layout(model.rank_nodes);
}

template <int D>
void Integrator<D>::set_predictor(Predictor predictor) {
  if (predictor == Predictor::rigid) {
    const auto& model = assembler_.model();
    const Eigen::VectorXd row_sums = assembler_.mass_times(Eigen::VectorXd::Ones(model.num_dofs()));
    Eigen::VectorXd masses = row_sums(Eigen::seq(0, Eigen::last, D));
    if (model.order != 1) {  // a quadratic consistent mass's row sums are not positive: its diagonal scaled to
                             // each body's mass (fem::quadratic_mass, lumped)
      const Eigen::VectorXd diagonal = assembler_.node_mass().diagonal();
      for (const model::Body& b : model.bodies) {
        const double total = masses.segment(b.first_node, b.num_nodes).sum();
        const double sum = diagonal.segment(b.first_node, b.num_nodes).sum();
        if (sum > 0.0) masses.segment(b.first_node, b.num_nodes) = diagonal.segment(b.first_node, b.num_nodes) * (total / sum);
      }
    }
    rigid_.emplace(model, std::move(masses));
  } else {
    rigid_.reset();
  }
}

template <int D>
solver::NewtonReport Integrator<D>::step(model::State& state, double dt) {
  const double t_np1 = state.time + dt;
  Eigen::VectorXd u_np1 = predictor(state, dt);
  const Eigen::VectorXd predicted = u_np1;
  // The same step again, shorter, after it met an impact: Newton's
  // correction to the predictor in the longer attempt, scaled by the ratio
  // of the steps, starts it (the body's response to the forces of the
  // step, which the predictor leaves out). Scaled by the ratio squared,
  // as a constant force's response would be, it starts further off: the
  // peer benchmark's split steps then took 1.7 % more solves, where this
  // takes 3 % fewer than the predictor alone (bench/results/speed.md).
  const bool retry = interrupted_.step == state.step && dt < interrupted_.dt;
  if (retry) u_np1 += (dt / interrupted_.dt) * interrupted_.correction;
  interrupted_.step = -1;
  model::apply_prescribed<D>(assembler_.model().prescribed, assembler_.model().X, t_np1, u_np1);
  bodies_.begin(state, dt);
  bodies_.predict(u_np1);
  const Eigen::VectorXd start = u_np1;  // with the prescribed dofs' values
  stats_ = {};
  for (const auto& term : terms_) term->begin(state, dt);
  if (contact_) contact_->begin_step(state.step + 1, dt, state);
  solver::NewtonReport total;
  Eigen::VectorXd v_np1;  // set by the method if it changes the step's velocity
  for (bool again = true; again;) {
    std::unique_ptr<contact::Coupling> coupling;
    if (contact_) {
      solver::ScopedTimer timer(timings_.elimination);
      coupling = contact_->coupling(state.u, u_np1);
      coupling->start(u_np1);
    }
    // A system with free bodies' unknowns is no plain one: its appended
    // rows change with the bodies' motion.
    const bool plain = (!coupling || coupling->plain()) && bodies_.empty();
    StepProblem<D> problem(assembler_, mask_, terms_, state, dt, u_np1, K_, coupling.get());
    problem.add_bodies(&bodies_);
    problem.set_timings(&timings_);
    // A solve that will end in a split need not converge: abandoned once
    // its iterate shows the impact (the fraction then comes from it).
    double early_split = 1.0;
    if (contact_)
      problem.check_iterate(
          [&](const Eigen::VectorXd& u) {
            solver::ScopedTimer timer(timings_.contact_search);
            early_split = contact_->split_fraction(state.u, u);
            return early_split < 1.0;
          },
          retry ? kSearchRetry : kSearchFirst);
    // A factorization of the plain system stays usable while no contact
    // couples it; a reduced system's T changes from pass to pass.
    std::optional<Origin> first, last;  // of this solve's plain tangents
    problem.observe_tangents([&](const Eigen::VectorXd& iterate) {
      if (!plain) return;
      last = Origin{state.u, state.v, iterate, state.time, dt};
      if (!first) first = last;
    });
    const int setups = timings_.linear_setups, lu_first = timings_.lu_first;
    const solver::NewtonReport report =
        solver::solve_newton(problem, *solver_, newton_, plain && plain_factorization_, &memory_);
    if (timings_.linear_setups != setups || timings_.lu_first != lu_first) {
      plain_factorization_ = plain;
      kept_ = std::move(last);
      // A new generation starts at the solve's first matrix (its pattern
      // is new, or the solver was reset).
      if (solver_->generation() != generation_) source_ = std::move(first);
    }
    generation_ = solver_->generation();
    if (report.abandoned) {  // not taken: the caller ends it earlier
      interrupted_ = {state.step, dt, u_np1 - predicted};
      ++stats_.passes;
      stats_.split_fraction = early_split;
      total.converged = false;
      return total;
    }
    if (!report.converged) {
      // The method may change its set so that the step converges at this
      // Δt (Method::recover); solved again from the prediction.
      if (!contact_ || !contact_->recover(state.u)) throw SolverError(not_converged(report, state.step + 1, t_np1));
      u_np1 = start;
      bodies_.predict(u_np1);  // the free bodies' unknowns too
      ++stats_.passes;
      continue;
    }
    total.converged = true;
    total.iterations += report.iterations;
    total.linear_iterations += report.linear_iterations;
    total.backtracks += report.backtracks;
    total.residual_norms = report.residual_norms;
    total.tolerance = report.tolerance;
    total.floor = report.floor;
    stats_.equations = problem.equations();
    reaction_ = problem.reactions();
    contact::Verdict verdict = contact::Verdict::accept;
    if (contact_) {
      solver::ScopedTimer timer(timings_.contact_search);
      v_np1.resize(0);
      verdict = contact_->settle(state, dt, u_np1, problem.full_residual(), v_np1, stats_);
    }
    if (verdict == contact::Verdict::split) {  // not taken: the caller ends it earlier
      interrupted_ = {state.step, dt, u_np1 - predicted};
      total.converged = false;
      return total;
    }
    again = verdict == contact::Verdict::changed;
    if (again && stats_.passes >= max_passes_)
      throw SolverError(fmt::format(
          "the contact active set did not settle in step {} (t = {:.6g} s) after {} passes "
          "({} activations, {} releases); raise [active_set].max_passes or reduce the time step",
          state.step + 1, t_np1, stats_.passes, stats_.activations, stats_.releases));
  }
  check_orientation(u_np1, state.step + 1, t_np1);
  if (v_np1.size() == 0) v_np1 = (2.0 / dt) * (u_np1 - state.u) - state.v;  // (19)
  std::vector<model::RigidBodyState> rigid;
  bodies_.finish(rigid, v_np1);  // the free bodies' own velocities, rigid fields
  // The work of the prescribed motion: its forces over its dofs' step,
  // Δu·R, which (26) makes the step's change of K + W + Π ...
  const model::Model<D>& m = assembler_.model();
  Eigen::VectorXd work = (u_np1 - state.u).cwiseProduct(reaction_);
  // Prescribed dofs move as prescribed, with their exact velocity (for a
  // turning or curve-driven motion (19) would oscillate about it) ...
  if (!m.prescribed.rigid.empty() || !m.prescribed.curves.empty()) {
    const Eigen::VectorXd v_19 = v_np1;
    model::apply_prescribed<D>(m.prescribed, m.X, t_np1, u_np1, &v_np1);
    // ... and the kinetic energy that setting them changes, (V − V_19)·M V̄
    // dof by dof (V̄ the mean of the two; non-zero on prescribed dofs only).
    const Eigen::VectorXd change = v_np1 - v_19;
    if (change.any()) work += change.cwiseProduct(assembler_.mass_times(0.5 * (v_np1 + v_19)));
  }
  if (contact_) {
    solver::ScopedTimer timer(timings_.contact_search);
    contact_->finish_step(state.u, u_np1, v_np1, stats_);
    add_impulses(dt);
  } else {
    impulse_.resize(0);
  }
  sum_supports(state, u_np1, work);
  for (const auto& term : terms_) state.load_work += term->external_work(u_np1);
  state.released += stats_.contact_released;
  state.dissipated += stats_.dissipated;
  state.v = std::move(v_np1);
  state.u = std::move(u_np1);
  state.rigid = std::move(rigid);
  state.time = t_np1;
  ++state.step;
  return total;
}

// Persistent contact's impulses at the step's end on slaves of a
// prescribed master: the master's nodes take their opposite, which the
// prescribed motion must supply, N_b P over the step (impulses do no work
// here: the update keeps the step's energy).
template <int D>
void Integrator<D>::add_impulses(double dt) {
  impulse_.resize(0);
  for (const contact::ContactForce<D>& f : contact_->contact_forces()) {
    if (f.impulse.isZero()) continue;
    if (impulse_.size() == 0) impulse_.setZero(reaction_.size());
    for (int b = 0; b < f.master.size(); ++b)
      for (int i = 0; i < D; ++i)
        if (mask_.masked(f.master[b] * D + i)) impulse_[f.master[b] * D + i] += f.weights[b] * f.impulse[i] / dt;
    // A prescribed slave (a driven body's node in a second pass) takes the
    // impulse itself: its motion supplies the opposite.
    for (int i = 0; i < D; ++i)
      if (mask_.masked(f.slave * D + i)) impulse_[f.slave * D + i] -= f.impulse[i] / dt;
  }
}

namespace {

void write_origin(ByteWriter& w, const auto& o) {
  w.value(o.time);
  w.value(o.dt);
  w.doubles(o.u.data(), static_cast<std::size_t>(o.u.size()));
  w.doubles(o.v.data(), static_cast<std::size_t>(o.v.size()));
  w.doubles(o.iterate.data(), static_cast<std::size_t>(o.iterate.size()));
}

template <class Origin>
std::optional<Origin> read_origin(ByteReader& r, Eigen::Index dofs) {
  if (r.value<std::uint8_t>() == 0) return std::nullopt;
  Origin o;
  o.time = r.value<double>();
  o.dt = r.value<double>();
  for (Eigen::VectorXd* v : {&o.u, &o.v, &o.iterate}) {
    v->resize(dofs);
    r.doubles(v->data(), static_cast<std::size_t>(dofs), "a kept tangent's state");
  }
  if (!(o.dt > 0.0) || !std::isfinite(o.time)) r.fail("a kept tangent's step is malformed");
  return o;
}

}  // namespace

template <int D>
std::string Integrator<D>::save() const {
  ByteWriter w;
  w.value(static_cast<std::uint8_t>(plain_factorization_));
  w.value(memory_.nonlinearity);
  w.value(memory_.kept_ratio);
  for (const std::optional<Origin>* o : {&source_, &kept_}) {
    w.value(static_cast<std::uint8_t>(o->has_value()));
    if (*o) write_origin(w, **o);
  }
  w.text(solver_->save_state());
  return w.bytes();
}

template <int D>
void Integrator<D>::load(const std::string& bytes, const std::string& what) {
  ByteReader r(bytes, what);
  const bool plain = r.value<std::uint8_t>() != 0;
  solver::NewtonMemory memory;
  memory.nonlinearity = r.value<double>();
  memory.kept_ratio = r.value<double>();
  const Eigen::Index dofs = assembler_.model().num_dofs();
  std::optional<Origin> source = read_origin<Origin>(r, dofs), kept = read_origin<Origin>(r, dofs);
  const std::string solver_state = r.text(1024, true);
  if (!r.at_end()) r.fail("trailing bytes after the integrator's state");
  drop_factorization();
  // The solver's generation from its first matrix, then its present one.
  if (source && kept) set_again(*source);
  if (kept) set_again(*kept);
  solver_->load_state(solver_state);
  plain_factorization_ = plain && kept.has_value();
  memory_ = memory;
  source_ = std::move(source);
  kept_ = std::move(kept);
  generation_ = solver_->generation();
}

template <int D>
void Integrator<D>::set_again(const Origin& origin) {
  model::State start;
  start.u = origin.u;
  start.v = origin.v;
  start.time = origin.time;
  for (const auto& term : terms_) term->begin(start, origin.dt);
  Eigen::VectorXd iterate = origin.iterate;
  StepProblem<D> problem(assembler_, mask_, terms_, start, origin.dt, iterate, K_);
  solver_->set_operator(problem.tangent());
}

template <int D>
void Integrator<D>::sum_supports(model::State& state, const Eigen::VectorXd& u_np1, const Eigen::VectorXd& work) {
  const model::Model<D>& m = assembler_.model();
  const auto& supports = m.prescribed.supports;
  state.support_work.resize(supports.size(), 0.0);
  supports_.assign(supports.size(), {});
  for (std::size_t s = 0; s < supports.size(); ++s)
    for (int e : supports[s].entries) {
      const int d = m.prescribed.dofs[static_cast<std::size_t>(e)], node = d / D, i = d % D;
      state.support_work[s] += work[d];
      // The step's force acts at the mid-point positions, an impulse at the end ones.
      Vec3 mid = Vec3::Zero(), end = Vec3::Zero(), f = Vec3::Zero(), p = Vec3::Zero();
      end.head<D>() = m.X.col(node) + u_np1.segment<D>(node * D);
      mid.head<D>() = 0.5 * (end.head<D>() + m.X.col(node) + state.u.segment<D>(node * D));
      f[i] = reaction_[d];
      if (impulse_.size() > 0) p[i] = impulse_[d];
      supports_[s].force += f + p;
      supports_[s].moment += mid.cross(f) + end.cross(p);
    }
  if (impulse_.size() > 0) reaction_ += impulse_;
}

// The step (17) of a body on which only the body force acts (rigid
// flight under gravity, f_int = 0) is u_{n+1} = u_n + Δt V_n + ½Δt² g:
// M⁻¹ of the gravity force is g at every dof, consistent mass or lumped.
// Predicting with it leaves the elastic part of the step to Newton, so a
// body in flight starts at a residual of its vibration alone; the rigid
// predictor also leaves out the vibration's velocity (time/predictor.hpp).
// Internal and contact forces are left out of the prediction:
// extrapolating them overshoots modes with ωΔt ≫ 1 and carries an
// impact's reversal into the next step (bench/README.md, "Predictors").
template <int D>
Eigen::VectorXd Integrator<D>::predictor(const model::State& state, double dt) const {
  Eigen::VectorXd u;
  if (rigid_) {
    Eigen::VectorXd v = state.v;
    rigid_->project(state.u, v);
    u = state.u + dt * v;
  } else {
    u = state.u + dt * state.v;
  }
  const Vec<D> drop = (0.5 * dt * dt) * assembler_.model().gravity;
  if (drop.squaredNorm() > 0.0)
    for (Eigen::Index n = 0; n < u.size() / D; ++n) u.segment<D>(n * D) += drop;
  return u;
}

template <int D>
std::string Integrator<D>::not_converged(const solver::NewtonReport& report, std::int64_t step, double t) const {
  std::string tail;  // the last residuals show stagnation or divergence
  const auto& norms = report.residual_norms;
  for (std::size_t k = norms.size() > 6 ? norms.size() - 6 : 0; k < norms.size(); ++k)
    tail += fmt::format(" {:.2e}", norms[k]);
  return fmt::format(
      "Newton did not converge in step {} (t = {:.6g} s): {}; after {} iterations the last residuals are{} N "
      "(tolerance {:.2e} N, round-off floor {:.2e} N) (try a smaller time step or more [newton].max_iterations)",
      step, t, report.failure, report.iterations, tail, report.tolerance, report.floor);
}

// A converged step must not turn a cell inside out: SVK's energy does not
// stop it (it stays finite through det F = 0), so the step is refused and
// retried smaller.
template <int D>
void Integrator<D>::check_orientation(const Eigen::VectorXd& u, std::int64_t step, double t) const {
  const assembly::Orientation o = assembler_.measures(u).orientation;  // kept for the report and the next step
  if (o.cell < 0 || o.det_F > 0.0) return;
  const auto& model = assembler_.model();
  const auto& body = model.bodies[static_cast<std::size_t>(model.body_of_cell(o.cell))];
  throw SolverError(fmt::format("cell {} of body '{}' is inverted at the end of step {} (t = {:.6g} s): det F = {:.3g}",
                                o.cell - body.first_cell, body.name, step, t, o.det_F));
}

template class Integrator<2>;
template class Integrator<3>;

}  // namespace conserve::time
