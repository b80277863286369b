#include "simulation/drift.hpp"

#include <algorithm>

namespace conserve::simulation {
namespace {

/// change / scale, with 0 for no change (a scale of zero then means that
/// nothing has moved yet).
double relative(double change, double scale) { return change == 0.0 ? 0.0 : change / scale; }

}  // namespace

Drifts DriftTracker::add(const time::Diagnostics& d, RunTotals& totals) const {
  totals.energy_reference = std::max(totals.energy_reference, d.kinetic + d.strain);
  totals.momentum_reference = std::max(totals.momentum_reference, d.momentum_magnitude);
  const double angular_reference = totals.momentum_reference * size_;
  const Vec3 dl = (d.linear - d0_.linear).cwiseAbs(), dj = (d.angular - d0_.angular).cwiseAbs();
  const Drifts drifts{relative(std::abs(d.total - d0_.total), totals.energy_reference),
                      relative(dl.norm(), totals.momentum_reference), relative(dj.norm(), angular_reference)};
  totals.energy_drift = std::max(totals.energy_drift, drifts.energy);
  for (int i = 0; i < 3; ++i) {
    totals.linear_drift[i] = std::max(totals.linear_drift[i], relative(dl[i], totals.momentum_reference));
    totals.angular_drift[i] = std::max(totals.angular_drift[i], relative(dj[i], angular_reference));
  }
  return drifts;
}

}  // namespace conserve::simulation
