#pragma once
/// Runs a row of bars (validation_scenarios.hpp) and measures what 1D wave
/// theory predicts: contact duration 2L/c, exchange of velocities, interface
/// stress ρ c v0 / 2.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

#include "support/contact_run.hpp"
#include "validation_scenarios.hpp"

namespace conserve::test {

/// True when the long variants should run (CONSERVE_LONG_TESTS=1).
inline bool long_tests() {
  const char* v = std::getenv("CONSERVE_LONG_TESTS");
  return v != nullptr && std::string(v) == "1";
}

/// Per step: time at the end of the step (time[0] = 0: the start), L_x of
/// every bar, Σ f_N, active count. Steps may vary (impacts located).
struct BarHistory {
  std::vector<double> time, force;
  std::vector<std::vector<double>> momentum;  ///< [step][bar]
  std::vector<int> active;
  int activations = 0, releases = 0;
  double max_passes = 0;
};

template <int D>
BarHistory run_bars(const Bars& bars) {
  ContactRun<D> run(bars_scenario(bars));
  BarHistory h;
  h.time.push_back(run.state.time);
  h.force.push_back(0.0);
  h.active.push_back(0);
  {
    std::vector<double> l;
    for (const Vec3& b : run.diagnostics().body_linear) l.push_back(b.x());
    h.momentum.push_back(l);
  }
  while (run.state.time < bars.end - 1e-9 * bars.step) {
    run.step();
    const auto& stats = run.integrator->contact_stats();
    h.activations += stats.activations;
    h.releases += stats.releases;
    h.max_passes = std::max<double>(h.max_passes, stats.passes);
    double f = 0.0;
    for (double fn : run.contacts->normal_forces()) f += fn;
    std::vector<double> l;
    for (const Vec3& b : run.diagnostics().body_linear) l.push_back(b.x());
    h.time.push_back(run.state.time);
    h.force.push_back(f);
    h.momentum.push_back(l);
    h.active.push_back(static_cast<int>(run.contacts->constraints().size()));
  }
  return h;
}

/// What one impact between bar k and bar k+1 looked like, from the momentum
/// that bar k+1 received (robust against chatter: the active set flickers,
/// the momentum transfer does not).
struct Impact {
  double start = 0.0, end = 0.0;  ///< first and last step that moved momentum into bar k+1 [s]
  double momentum_stress = 0.0;   ///< plateau of (ΔL/Δt)/A over the middle half [Pa]
  double force_stress = 0.0;      ///< plateau of Σ f_N / A over the middle half [Pa]
  [[nodiscard]] double duration() const { return end - start; }
};

/// The first impact received by bar `k` (k ≥ 1) from the left: from the
/// first to the last step that moved momentum into it, before it starts to
/// pass momentum on to bar k+1 (a step without transfer inside the
/// contact, when chatter released every slave, does not end it; nor, for
/// the last bar, which has no one to pass momentum on to, does a step that
/// gives some back, as when slaves re-activated after a release are held
/// with a tensile force for that step). A pause longer than a tenth of
/// 2L/c (L the shorter bar) ends it: bars that part at rest side by side
/// (a short bar that has hit one twice its length) may touch again later.
inline Impact first_impact(const BarHistory& h, const Bars& bars, int k) {
  const double threshold = 1e-6 * bars.mass() * bars.v0;
  const double pause = 0.2 * std::min(bars.length_of(k - 1), bars.length_of(k)) / bars.wave_speed();
  const bool passes_on = k + 1 < bars.count;
  Impact imp;
  int first = -1, last = -1;
  for (std::size_t n = 1; n < h.time.size(); ++n) {
    const double dl = h.momentum[n][k] - h.momentum[n - 1][k];
    if (first >= 0 && passes_on && dl < -threshold) break;  // bar k hits bar k+1
    if (last >= 0 && h.time[n] - h.time[last] > pause) break;  // parted
    if (dl > threshold) {
      if (first < 0) first = static_cast<int>(n);
      last = static_cast<int>(n);
    }
  }
  if (first < 0) return imp;
  imp.start = h.time[first - 1];
  imp.end = h.time[last];
  const int lo = first + (last - first) / 4, hi = last - (last - first) / 4;
  for (int n = lo; n <= hi; ++n) {
    imp.momentum_stress += (h.momentum[n][k] - h.momentum[n - 1][k]) / (h.time[n] - h.time[n - 1]) / bars.area();
    imp.force_stress += h.force[n] / bars.area();
  }
  imp.momentum_stress /= (hi - lo + 1);
  imp.force_stress /= (hi - lo + 1);
  return imp;
}

/// How long bar k (k ≥ 1) took to receive `fraction` of the momentum bar
/// k−1 brought (m v0 if k = 1), from the start of its first impact: for 1D
/// waves the force is constant over 2L/c, so this is fraction × 2L/c; it
/// leaves out the mesh's dispersive tail and later touches of bars at rest
/// side by side, which the first-to-last-step duration of first_impact
/// takes in. NaN if it never does.
inline double transfer_time(const BarHistory& h, const Bars& bars, int k, double fraction) {
  const double target = fraction * bars.mass(k - 1) * bars.v0;
  const Impact imp = first_impact(h, bars, k);
  for (std::size_t n = 1; n < h.time.size(); ++n)
    if (h.momentum[n][k] - h.momentum[0][k] >= target) return h.time[n] - imp.start;
  return std::numeric_limits<double>::quiet_NaN();
}

/// Steps during which some constraint was active, from the first to the last.
inline double active_span(const BarHistory& h) {
  int first = -1, last = -1;
  for (std::size_t n = 1; n < h.active.size(); ++n)
    if (h.active[n] > 0) {
      if (first < 0) first = static_cast<int>(n);
      last = static_cast<int>(n);
    }
  return first < 0 ? 0.0 : h.time[last] - h.time[first - 1];
}

}  // namespace conserve::test
