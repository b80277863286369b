#include "contact/elimination/friction.hpp"

#include <cmath>

#include "contact/elimination/zero_work.hpp"

namespace conserve::contact {

template <int D>
bool leaves_cone(const Constraint<D>& c, const Vec<D>& force, double mu) {
  const double f_n = c.normal_force;
  if (!(f_n > 0.0)) return false;
  return (force - f_n * c.normal).norm() > mu * f_n * (1.0 + kConeTolerance);
}

template <int D>
Constraint<D> to_slip(Constraint<D> c, double mu, double facet_size) {
  c.kind = Kind::frictionless;
  c.friction = mu;
  c.slip_scale = kSlipScale * facet_size;
  return c;
}

template <int D>
Constraint<D> to_stick(Constraint<D> c, const ContactPair<D>& pr, const Positions<D>& x_n) {
  const Projection<D> start = project<D>(x_n.col(c.slave), facet_nodes<D>(pr.master, c.facet, x_n));
  c.kind = Kind::stick;
  c.xi = start.xi;
  c.gap = start.gap;
  c.friction = 0.0;
  c.slip_scale = 0.0;
  c.rate = c.push = false;
  return c;
}

template <int D>
FrictionStep friction_step(const Constraint<D>& c, const Positions<D>& x_n, const Positions<D>& x_np1) {
  zero_work::Nodes<D, double> x, dx;
  x.col(0) = x_np1.col(c.slave);
  dx.col(0) = x_np1.col(c.slave) - x_n.col(c.slave);
  for (int b = 0; b < D; ++b) {
    x.col(b + 1) = x_np1.col(c.master[b]);
    dx.col(b + 1) = x_np1.col(c.master[b]) - x_n.col(c.master[b]);
  }
  FrictionStep step;
  const zero_work::Nodes<D, double> phi = zero_work::friction_direction<D, double>(x, dx, c.slip_scale, step.slip);
  step.dissipated = -c.friction * c.normal_force * phi.cwiseProduct(dx).sum();
  return step;
}

#define CONSERVE_FRICTION(D)                                                                               \
  template bool leaves_cone<D>(const Constraint<D>&, const Vec<D>&, double);                              \
  template Constraint<D> to_slip<D>(Constraint<D>, double, double);                                        \
  template Constraint<D> to_stick<D>(Constraint<D>, const ContactPair<D>&, const Positions<D>&);           \
  template FrictionStep friction_step<D>(const Constraint<D>&, const Positions<D>&, const Positions<D>&);
CONSERVE_FRICTION(2)
CONSERVE_FRICTION(3)
#undef CONSERVE_FRICTION

}  // namespace conserve::contact
