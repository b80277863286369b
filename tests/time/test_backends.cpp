// Conservation does not depend on the linear solver: Newton judges the
// nonlinear residual alone. The contact conservation cases run with each
// back end of [solver] (UMFPACK LU; GMRES with ILU(0) or GAMG, inexact
// Newton), through the same wiring as `conserve run`.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "support/contact_run.hpp"
#include "support/contact_scenarios.hpp"

namespace conserve::time {
namespace {

using test::ContactRun;

struct Backend {
  const char* name;
  const char* table;  ///< the [solver] table appended to the scenario
};

const Backend kBackends[] = {
    {"Direct", "\n[solver]\nmethod = \"direct\"\n"},
    {"Ilu", "\n[solver]\nmethod = \"krylov\"\npreconditioner = \"ilu\"\n"},
    {"Gamg", "\n[solver]\nmethod = \"krylov\"\npreconditioner = \"gamg\"\n"},
};

struct Drifts {
  double energy = 0.0, linear = 0.0, angular = 0.0, iterations = 0.0;
  int contact_steps = 0;
  std::string solver;
};

template <int D>
Drifts run(const std::string& toml) {
  ContactRun<D> run(toml);
  const Diagnostics d0 = run.diagnostics();
  const int steps = static_cast<int>(std::round(run.scenario.time.end / run.scenario.time.step));
  Drifts r;
  r.solver = run.integrator->linear_solver().name();
  for (int n = 0; n < steps; ++n) {
    r.iterations += run.step().iterations / static_cast<double>(steps);
    const Diagnostics d = run.diagnostics();
    r.energy = std::max(r.energy, std::abs(d.total - d0.total) / std::abs(d0.total));
    r.linear = std::max(r.linear, (d.linear - d0.linear).norm() / d0.linear.norm());
    r.angular = std::max(r.angular, (d.angular - d0.angular).norm() / d0.angular.norm());
    if (!run.contacts->constraints().empty()) ++r.contact_steps;
  }
  return r;
}

class ConservationByBackend : public ::testing::TestWithParam<Backend> {
 public:
  void report(const char* name, const Drifts& r) const {
    std::printf("[ measured ] %s, %s: E %.2e  L %.2e  J %.2e  %d contact steps  %.2f Newton it/step\n", name,
                r.solver.c_str(), r.energy, r.linear, r.angular, r.contact_steps, r.iterations);
  }
};

/// Frictionless conserves E, L and J (paper §4.3.2).
template <int D>
void check_frictionless(const char* name, const Backend& backend, const ConservationByBackend& test) {
  const Drifts r = run<D>(test::glancing_spheres(D, "frictionless", 0.1) + backend.table);
  test.report(name, r);
  EXPECT_GT(r.contact_steps, 5);
  EXPECT_LT(r.energy, 1e-10);
  EXPECT_LT(r.linear, 1e-10);
  EXPECT_LT(r.angular, 1e-10);
}

TEST_P(ConservationByBackend, FrictionlessGlancingImpact3d) {
  check_frictionless<3>("frictionless glancing 3D", GetParam(), *this);
}

TEST_P(ConservationByBackend, FrictionlessGlancingImpact2d) {
  check_frictionless<2>("frictionless glancing 2D", GetParam(), *this);
}

TEST_P(ConservationByBackend, StickBoxes3d) {  // stick conserves E and L, not J (paper §4.3.1)
  const Drifts r = run<3>(test::two_boxes("stick", 0.2) + GetParam().table);
  report("stick boxes 3D", r);
  EXPECT_GT(r.contact_steps, 3);
  EXPECT_LT(r.energy, 1e-10);
  EXPECT_LT(r.linear, 1e-10);
}

INSTANTIATE_TEST_SUITE_P(Backends, ConservationByBackend, ::testing::ValuesIn(kBackends),
                         [](const auto& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace conserve::time
