#include "simulation/drift.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace conserve::simulation {
namespace {

/// Adds `reason` to quantity q's list (once).
void breaks(Conservation& c, int q, std::string_view reason) {
  std::string& w = c.why_not[q];
  if (w.find(reason) != std::string::npos) return;
  w += (w.empty() ? "" : ", ") + std::string(reason);
}

void breaks_momenta(Conservation& c, std::string_view reason) {
  for (int q = 1; q < kQuantities; ++q) breaks(c, q, reason);
}

/// change / scale, with 0 for no change (a scale of zero then means that
/// nothing has moved yet).
double relative(double change, double scale) { return change == 0.0 ? 0.0 : change / scale; }

}  // namespace

Conservation conservation(const io::Scenario& scenario) {
  Conservation c;
  c.present.fill(true);
  if (scenario.dimension == 2) c.present[3] = c.present[4] = c.present[5] = false;
  if (scenario.time.scheme == io::StressScheme::midpoint) breaks(c, 0, "the mid-point stress");
  for (const auto& contact : scenario.contacts)
    if (contact.method == "penalty" && contact.penalty_force == io::PenaltyForce::midpoint)
      breaks(c, 0, "the mid-point penalty force");
  // Gravity g: L_i changes where g_i ≠ 0; J_i keeps only about g's axis
  // (the moment of Σ m g about the origin is (Σ m x) × g).
  const Vec3 g = scenario.gravity;
  for (int i = 0; i < 3; ++i) {
    if (g[i] != 0.0) breaks(c, 1 + i, "gravity");
    if (g[(i + 1) % 3] != 0.0 || g[(i + 2) % 3] != 0.0) breaks(c, 4 + i, "gravity");
  }
  if (!scenario.loads.empty()) breaks_momenta(c, "surface loads");
  // A support holding component i takes L_i, and moments about any axis.
  for (const auto& b : scenario.boundaries) {
    for (int k : b.components) breaks(c, 1 + k, "supports");
    for (int q = 4; q < kQuantities; ++q) breaks(c, q, "supports");
  }
  // A rigid body moves as prescribed: it takes what it touches (or, with
  // mass, what its motion needs).
  for (std::size_t i = 0; i < scenario.bodies.size(); ++i) {
    if (!scenario.bodies[i].rigid || scenario.bodies[i].free) continue;
    bool touches = scenario.bodies[i].material.density > 0.0;
    for (const auto& contact : scenario.contacts)
      touches = touches || contact.slave_body == scenario.bodies[i].name || contact.master_body == scenario.bodies[i].name;
    if (touches) breaks_momenta(c, "rigid bodies");
  }
  // Contact of every kind and method keeps E (with what it dissipates or
  // lets go), L and J: stick too (docs/theory.md (S2)).
  return c;
}

Drifts DriftTracker::add(const time::Diagnostics& d, DriftState& s) const {
  s.energy_reference = std::max(s.energy_reference, d.kinetic + d.strain + d.contact);
  s.momentum_reference = std::max(s.momentum_reference, d.momentum_magnitude);
  const double e = d.total + d.released + d.dissipated, e0 = d0_.total + d0_.released + d0_.dissipated;
  s.deviation[0] = std::max(s.deviation[0], std::abs(e - e0));
  for (int i = 0; i < 3; ++i) {
    s.deviation[1 + i] = std::max(s.deviation[1 + i], std::abs(d.linear[i] - d0_.linear[i]));
    s.deviation[4 + i] = std::max(s.deviation[4 + i], std::abs(d.angular[i] - d0_.angular[i]));
  }
  Drifts out{drift(0, s), std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
  for (int q = 1; q < kQuantities; ++q) {
    if (!conservation_.conserved(q)) continue;
    double& row = q < 4 ? out.linear : out.angular;
    row = std::isnan(row) ? drift(q, s) : std::max(row, drift(q, s));
  }
  return out;
}

double DriftTracker::reference(int q, const DriftState& s) const {
  return q == 0 ? s.energy_reference : q < 4 ? s.momentum_reference : s.momentum_reference * size_;
}

double DriftTracker::drift(int q, const DriftState& s) const {
  if (!conservation_.conserved(q)) return std::numeric_limits<double>::quiet_NaN();
  return relative(s.deviation[q], reference(q, s));
}

}  // namespace conserve::simulation
