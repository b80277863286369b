#include "contact/elimination/release.hpp"

#include <algorithm>

namespace conserve::contact {

template <int D>
std::vector<double> normal_forces(const std::vector<Constraint<D>>& active, const Eigen::VectorXd& g,
                                  std::vector<int>& slot) {
  const std::size_t n = active.size();
  std::vector<double> f(n);
  std::vector<int> partner(n, -1);
  for (std::size_t j = 0; j < n; ++j) {
    int& first = slot[static_cast<std::size_t>(active[j].slave)];
    if (first < 0) {
      first = static_cast<int>(j);
    } else {
      partner[j] = first;
      partner[static_cast<std::size_t>(first)] = static_cast<int>(j);
    }
  }
  for (std::size_t j = 0; j < n; ++j) {
    const Constraint<D>& c = active[j];
    slot[static_cast<std::size_t>(c.slave)] = -1;
    if (c.eliminated >= 0) {
      // A driven slave's constraint, held by its facet's node b: b's
      // residual carries N_b of the force, on the facet's side.
      int b = 0;
      while (c.master[b] != c.eliminated) ++b;
      f[j] = -g.template segment<D>(c.eliminated * D).dot(c.normal) / facet_weights<D>(c.master.size(), c.xi)(b);
      continue;
    }
    const Vec<D> g_s = g.template segment<D>(c.slave * D);
    if (partner[j] < 0) {
      f[j] = g_s.dot(c.normal);
      continue;
    }
    const Vec<D>& m = active[static_cast<std::size_t>(partner[j])].normal;
    // g_s = f n + f′ m in the least-squares sense: Gram system, f by Cramer.
    const double nm = c.normal.dot(m), det = 1.0 - nm * nm;
    f[j] = (g_s.dot(c.normal) - nm * g_s.dot(m)) / det;
  }
  return f;
}

// A step's normal force is its mean over the step, f(t) at about the
// step's middle. A slave lets go in the first step whose mean is
// tensile, and the force that measures its release (loaded_releases) is
// the mean of the step before, which is of order (rate of fall) × (that
// step). With f falling linearly at rate r from f_N at the middle of the
// last step (length h), the next step's mean stays ≥ 0 for steps up to
// 2 f_N / r − h. Where that is within kReleaseHorizon full steps, the next
// step is a kReleaseApproach part of it: the steps shrink geometrically
// towards the lift-off, which a step then meets with a force of about
// kReleaseUnloading × (the loaded threshold) left in the step before.
template <int D>
double release_step(const std::vector<Constraint<D>>& active, std::int64_t step, double full, double last,
                    double previous) {
  if (active.empty() || !(last > 0.0) || !(previous > 0.0)) return full;
  double sum = 0.0;
  for (const Constraint<D>& c : active) sum += c.normal_force;
  const double loaded = kLoadedFraction * sum / static_cast<double>(active.size());
  double next = full;
  for (const Constraint<D>& c : active) {
    if (c.activated_step >= step || !(c.normal_force > loaded)) continue;
    const double rate = (c.start_force - c.normal_force) / (0.5 * (previous + last));  // −df/dt
    if (!(rate > 0.0)) continue;
    const double ahead = 2.0 * c.normal_force / rate - last;
    if (ahead > kReleaseHorizon * full) continue;
    next = std::min({next, 2.0 * last, std::max(kReleaseApproach * ahead, kReleaseUnloading * loaded / rate)});
  }
  return std::max(next, full / kReleaseShortest);
}

#define CONSERVE_RELEASE(D)                                                                                     \
  template std::vector<double> normal_forces<D>(const std::vector<Constraint<D>>&, const Eigen::VectorXd&,      \
                                                std::vector<int>&);                                             \
  template double release_step<D>(const std::vector<Constraint<D>>&, std::int64_t, double, double, double);
CONSERVE_RELEASE(2)
CONSERVE_RELEASE(3)
#undef CONSERVE_RELEASE

}  // namespace conserve::contact
