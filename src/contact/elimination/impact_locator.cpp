#include "contact/elimination/impact_locator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace conserve::contact {

template <int D>
ImpactLocator<D>::ImpactLocator(int num_nodes, int num_pairs)
    : released_at_(static_cast<std::size_t>(num_nodes), -std::numeric_limits<double>::infinity()),
      activated_at_(static_cast<std::size_t>(num_pairs), -std::numeric_limits<double>::infinity()),
      released_(static_cast<std::size_t>(num_nodes), 0),
      activated_(static_cast<std::size_t>(num_pairs), 0),
      in_contact_(static_cast<std::size_t>(num_pairs), 0) {}

template <int D>
void ImpactLocator<D>::configure(const ImpactLocation& location) {
  location_ = location;
  if (!(location_.onset > 0.0)) location_ = {};
  location_.cluster = std::max(location_.cluster, location_.onset);
}

template <int D>
void ImpactLocator<D>::begin_step(double time, double dt, const Eigen::VectorXd& v_n,
                                  const std::vector<Constraint<D>>& active) {
  if (located()) dt_ = dt, v_n_ = v_n;
  time_ = time;
  std::fill(released_.begin(), released_.end(), 0);
  std::fill(activated_.begin(), activated_.end(), 0);
  std::fill(in_contact_.begin(), in_contact_.end(), 0);
  for (const Constraint<D>& c : active) in_contact_[static_cast<std::size_t>(c.pair)] = 1;
}

template <int D>
void ImpactLocator<D>::end_step(double time) {
  for (std::size_t node = 0; node < released_.size(); ++node)
    if (released_[node]) released_at_[node] = time;
  for (std::size_t p = 0; p < activated_.size(); ++p)
    if (activated_[p]) activated_at_[p] = time;
}

template <int D>
void ImpactLocator<D>::set_event_times(std::vector<double> releases, std::vector<double> activations) {
  released_at_ = std::move(releases);
  activated_at_ = std::move(activations);
}

template <int D>
double ImpactLocator<D>::gap_tolerance(int p, int s, double facet_size) const {
  if (!located()) return std::numeric_limits<double>::infinity();
  const auto k = static_cast<std::size_t>(p);
  const bool follows = in_contact_[k] || time_ - activated_at_[k] <= location_.window ||
                       time_ - released_at_[static_cast<std::size_t>(s)] <= location_.window;
  return (follows ? location_.cluster : location_.onset) * facet_size;
}

// The path within the step that the mid-point scheme implies is the
// quadratic through x_n with slope V_n that ends at x_{n+1} (its end slope
// is then V_{n+1} of (19)); on it the gap is, to first order in the
// facet's rotation, g(s) = γ + s Δt ġ_n + s² (g_{n+1} − γ − Δt ġ_n), with ġ_n
// the slave's normal velocity relative to its facet point at the start.
// The step should end at the first s where g = δ/2.
template <int D>
double ImpactLocator<D>::split_at(const Constraint<D>& c, const Match<D>& end, const ContactSurface& master,
                                  const Positions<D>& x_n, double tolerance) const {
  if (!(c.gap > tolerance)) return 1.0;
  const double target = c.gap - 0.5 * tolerance;  // > 0: the drop of the gap to reach δ/2
  const double drop = c.gap - end.projection.gap;  // > target
  double fraction = target / drop;                 // the straight path's estimate
  if (v_n_.size() > 0) {
    const Projection<D> start = project_on<D>(x_n.col(c.slave), master, c.facet, x_n);
    const FacetWeights<D> N = facet_weights<D>(c.master.size(), start.xi);
    Vec<D> relative = v_n_.template segment<D>(c.slave * D);
    for (int b = 0; b < c.master.size(); ++b) relative -= N(b) * v_n_.template segment<D>(c.master[b] * D);
    const double slope = dt_ * relative.dot(start.normal);  // dg/ds at s = 0
    const double curve = -drop - slope;                     // g(s) = γ + slope s + curve s²
    // Smallest root in (0, 1] of curve s² + slope s + target = 0, written
    // to avoid cancellation; g(0) > δ/2 > g(1), so there is one.
    const double disc = slope * slope - 4.0 * curve * target;
    if (std::abs(curve) > 1e-12 * drop && disc >= 0.0) {
      const double q = -0.5 * (slope + std::copysign(std::sqrt(disc), slope));
      double best = 2.0;
      for (double s : {q / curve, q != 0.0 ? target / q : 2.0})
        if (s > 0.0 && s <= 1.0) best = std::min(best, s);
      if (best <= 1.0) fraction = best;
    }
  }
  return std::clamp(fraction, 0.0, 1.0);
}

template class ImpactLocator<2>;
template class ImpactLocator<3>;

}  // namespace conserve::contact
