#pragma once
/// Checks shared by the contact tests.
#include <gtest/gtest.h>

#include <cstdio>
#include <memory>
#include <optional>
#include <random>
#include <vector>

#include <Eigen/SparseLU>

#include "contact/elimination/method.hpp"
#include "support/contact_run.hpp"
#include "support/taylor.hpp"
#include "time/step_problem.hpp"

namespace conserve::test {

/// Steps until at least `min_active` constraints are active.
template <int D>
void run_until_contact(ContactRun<D>& run, std::size_t min_active, int max_steps) {
  for (int n = 0; n < max_steps && run.contacts->constraints().size() < min_active; ++n) run.step();
  ASSERT_GE(run.contacts->constraints().size(), min_active);
}

/// The reduced tangent by the Taylor test (support/taylor.hpp) of the
/// reduced residual r(q) = Tᵀ g after the full update by q (step 1, and for
/// frictionless slaves the mid-point projection and normal correction),
/// along three random q over every free, non-dummy unknown (or, given
/// `nodes`, those of these nodes only), with the dummy and prescribed rows
/// of both sides zeroed, at a non-converged iterate of the next step. The
/// steps are from 1e-6 of the model's size down (a larger step may move a
/// slave to another facet, a kink of r(q)). Prints each direction's test
/// and returns the worst.
template <int D>
TaylorOrder reduced_tangent_order(ContactRun<D>& run, const std::vector<int>* nodes = nullptr) {
  const auto& model = run.problem.model;
  const double dt = run.scenario.time.step;
  Eigen::VectorXd u = run.state.u + dt * run.state.v + 1e-4 * dt * run.state.v.cwiseAbs();  // off the solution
  model::apply_prescribed<D>(model.prescribed, model.X, run.state.time + dt, u);
  std::vector<contact::Constraint<D>> constraints = run.contacts->constraints();
  contact::Elimination<D> base(model.X, run.state.u, u, constraints, run.contacts->pairs());
  base.enforce(u);
  std::optional<typename contact::Elimination<D>::Saved> at_base;
  base.save(at_base);
  const assembly::DirichletMask mask(run.assembler->pattern().make_matrix(), model.prescribed.dofs);
  SparseMatrix K = run.assembler->pattern().make_matrix();
  contact::EliminationCoupling<D> coupling(base);
  Eigen::VectorXd u_base = u, r0;
  time::StepProblem<D> problem(*run.assembler, mask, fem::StressScheme::conserving, run.state, dt, u_base, K, &coupling);
  problem.residual(r0);
  const SparseMatrix Kr = problem.tangent();
  const std::size_t count = base.constraints().size();
  std::vector<char> skip(model.num_dofs(), 0);
  for (int d : model.prescribed.dofs) skip[d] = 1;
  // Dummy slots: a frictionless slave has D − (its constraints) slips,
  // stick none; a driven slave's constraint has them at the node holding it.
  std::vector<int> held(model.num_nodes(), 0);
  auto holder = [](const contact::Constraint<D>& c) { return c.eliminated >= 0 ? c.eliminated : c.slave; };
  for (const auto& c : at_base->constraints) ++held[holder(c)];
  for (const auto& c : at_base->constraints)
    for (int i = (c.kind == contact::Kind::frictionless ? D - held[holder(c)] : 0); i < D; ++i)
      skip[holder(c) * D + i] = 1;
  auto without_skipped = [&](Eigen::VectorXd v) {
    for (int i = 0; i < model.num_dofs(); ++i)
      if (skip[i]) v[i] = 0.0;
    return v;
  };
  auto residual_after = [&](const Eigen::VectorXd& q) {
    base.restore(*at_base);
    Eigen::VectorXd u_q = u, r;
    time::StepProblem<D> p(*run.assembler, mask, fem::StressScheme::conserving, run.state, dt, u_q, K, &coupling);
    p.update(q);
    p.residual(r);
    return without_skipped(r);
  };
  std::vector<char> moved(model.num_dofs(), nodes ? 0 : 1);
  if (nodes)
    for (int a : *nodes)
      for (int i = 0; i < D; ++i) moved[a * D + i] = 1;
  std::mt19937 rng(31);
  TaylorOrder worst;
  for (int k = 0; k < 3; ++k) {
    Eigen::VectorXd q = random_direction(rng, model.num_dofs());
    for (int i = 0; i < model.num_dofs(); ++i)
      if (skip[i] || !moved[i]) q[i] = 0.0;
    const TaylorOrder t = taylor_order(residual_after, Eigen::VectorXd::Zero(model.num_dofs()), q,
                                       without_skipped(Kr * q), 1e-6 * model.size());
    std::printf("[ measured ] reduced tangent (%zu constraints), direction %d: %s\n", count, k + 1,
                describe(t).c_str());
    worst = k == 0 ? t : worse(t, worst);
  }
  return worst;
}

/// The tangent of the Newton system the contact method's coupling forms
/// (the multipliers' [[K + ∂(Bλ)/∂u, B], [βC, 0]]) by the Taylor test of
/// its residual at the next step's solution (Newton from the prediction
/// until the residual is 1e-9 of its first, the multipliers away from
/// zero): the terms the multipliers' tangent leaves out (the variation of
/// their motion directions μ, scaled by the constraint rows' residual c)
/// vanish there. Along three random directions over the unknowns of
/// `nodes` (every free one if null) and the method's own unknowns;
/// prescribed rows left out. Steps from 1e-6 of the model's size, halved 7
/// times (the remainders stay above the forces' round-off). Prints each
/// direction's test and returns the worst.
template <int D>
TaylorOrder system_tangent_order(ContactRun<D>& run, const std::vector<int>* nodes = nullptr) {
  const auto& model = run.problem.model;
  const double dt = run.scenario.time.step;
  run.method->begin_step(run.state.step + 1, dt, run.state);
  Eigen::VectorXd u = run.state.u + dt * run.state.v;
  model::apply_prescribed<D>(model.prescribed, model.X, run.state.time + dt, u);
  const std::unique_ptr<contact::Coupling> coupling = run.method->coupling(run.state.u, u);
  coupling->start(u);
  const assembly::DirichletMask mask(run.assembler->pattern().make_matrix(), model.prescribed.dofs);
  SparseMatrix K = run.assembler->pattern().make_matrix();
  time::StepProblem<D> problem(*run.assembler, mask, fem::StressScheme::conserving, run.state, dt, u, K,
                               coupling.get());
  Eigen::VectorXd r;
  double first = -1.0;
  for (int k = 0; k < 10; ++k) {
    problem.residual(r);
    for (int d : model.prescribed.dofs) r[d] = 0.0;
    if (first < 0.0) first = r.norm();
    if (r.norm() <= 1e-9 * first) break;
    Eigen::SparseLU<SparseMatrix> lu(problem.tangent());
    problem.update(-lu.solve(r));
  }
  EXPECT_LE(r.norm(), 1e-9 * first) << "Newton did not converge";
  problem.residual(r);
  const SparseMatrix A = problem.tangent();
  const Eigen::Index n = r.size();
  std::vector<char> moved(static_cast<std::size_t>(n), 1);
  if (nodes) {
    std::fill(moved.begin(), moved.begin() + model.num_dofs(), 0);
    for (int a : *nodes)
      for (int i = 0; i < D; ++i) moved[static_cast<std::size_t>(a * D + i)] = 1;
  }
  for (int d : model.prescribed.dofs) moved[static_cast<std::size_t>(d)] = 0;
  auto without_prescribed = [&](Eigen::VectorXd v) {
    for (int d : model.prescribed.dofs) v[d] = 0.0;
    return v;
  };
  auto residual_after = [&](const Eigen::VectorXd& q) {
    problem.update(q);
    Eigen::VectorXd rq;
    problem.residual(rq);
    EXPECT_TRUE(problem.revert());
    return without_prescribed(rq);
  };
  std::mt19937 rng(37);
  TaylorOrder worst;
  for (int k = 0; k < 3; ++k) {
    Eigen::VectorXd q = random_direction(rng, n);
    for (Eigen::Index i = 0; i < n; ++i)
      if (!moved[static_cast<std::size_t>(i)]) q[i] = 0.0;
    const TaylorOrder t = taylor_order(residual_after, Eigen::VectorXd::Zero(n), q, without_prescribed(A * q),
                                       1e-6 * model.size(), 7);
    std::printf("[ measured ] system tangent (%lld equations), direction %d: %s\n", static_cast<long long>(n), k + 1,
                describe(t).c_str());
    worst = k == 0 ? t : worse(t, worst);
  }
  return worst;
}

/// The reduced tangent's Wᵀ K T + β (43)/(44), (58)/(59) against the plain
/// sparse products SparseMatrix(Wᵀ K T) + β at the constrained iterate of
/// the next step (g = 0, so V = 0; V is checked by reduced_tangent_order),
/// with K the element tangent. Also checks that a Newton update that moves
/// no constraint to another facet keeps K_r's pattern and storage.
/// Returns the relative difference.
template <int D>
double reduced_product_error(ContactRun<D>& run) {
  const auto& model = run.problem.model;
  const double dt = run.scenario.time.step;
  Eigen::VectorXd u = run.state.u + dt * run.state.v;
  model::apply_prescribed<D>(model.prescribed, model.X, run.state.time + dt, u);
  std::vector<contact::Constraint<D>> constraints = run.contacts->constraints();
  contact::Elimination<D> e(model.X, run.state.u, u, constraints, run.contacts->pairs());
  e.enforce(u);
  SparseMatrix K = run.assembler->pattern().make_matrix(), Kr;
  Eigen::VectorXd f;
  run.assembler->internal_force_tangent(run.state.u, u, fem::StressScheme::conserving, f, K);
  const Eigen::VectorXd g = Eigen::VectorXd::Zero(model.num_dofs());
  e.reduce_tangent(K, g, Kr);
  const SparseMatrix T = e.map(), W = e.test_map();
  std::vector<Eigen::Triplet<double>> beta;
  for (const auto& c : e.constraints()) {
    double trace = 0.0;
    for (int i = 0; i < D; ++i) trace += K.coeff(c.slave * D + i, c.slave * D + i);
    for (int j = (c.kind == contact::Kind::frictionless ? D - 1 : 0); j < D; ++j)
      beta.emplace_back(c.slave * D + j, c.slave * D + j, trace / D);
  }
  SparseMatrix reference(K.rows(), K.cols());
  reference.setFromTriplets(beta.begin(), beta.end());
  reference = SparseMatrix(W.transpose() * K * T) + reference;
  const double error = SparseMatrix(Kr - reference).norm() / reference.norm();
  std::printf(
      "[ measured ] reduced tangent vs SparseMatrix(Wᵀ K T) + β: %.1e relative (%zu constraints, %ld of "
      "%ld entries)\n",
      error, e.constraints().size(), static_cast<long>(Kr.nonZeros()), static_cast<long>(K.nonZeros()));
  EXPECT_GT(reference.norm(), 1.0);  // non-zero guard
  const int* storage = Kr.innerIndexPtr();
  const Eigen::Index entries = Kr.nonZeros();
  auto facets = [](const contact::Elimination<D>& el) {
    std::vector<int> out;
    for (const auto& c : el.constraints()) out.push_back(c.facet);
    return out;
  };
  const std::vector<int> before = facets(e);
  e.update(Eigen::VectorXd::Zero(model.num_dofs()), u);
  EXPECT_FALSE(e.reduce_tangent(K, g, Kr));
  EXPECT_EQ(facets(e), before);      // a zero update moves no slave to another facet …
  EXPECT_EQ(e.pattern_builds(), 1);  // … so K_r keeps its pattern and storage
  EXPECT_EQ(Kr.innerIndexPtr(), storage);
  EXPECT_EQ(Kr.nonZeros(), entries);
  return error;
}

/// The deepest slave behind its master at the end of the step, active or
/// not, by the activation search's rules [m].
template <int D>
double slave_penetration(ContactRun<D>& run) {
  return run.contacts->slave_penetration(run.state.u).depth;
}

}  // namespace conserve::test
