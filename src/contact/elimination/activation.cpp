#include "contact/elimination/activation.hpp"

#include <cmath>

#include "contact/elimination/zero_work.hpp"

namespace conserve::contact {

// The facet the slave was found behind at the end of the step; its gap
// γ and, for stick, its frozen ξ̄ are those of the slave's position at the
// START of the step on that facet, so that the constraint holds what the
// slave had: for stick F(x_m,n) = x_s,n exactly (no work, whatever the
// facet); for frictionless its start gap too, even when it is negative (a
// slave that was over a neighbouring facet across a convex edge, or that
// sank beyond the surface's border unseen, starts behind this facet's
// plane). Pushing it out to γ = 0 within the step at zero work needs other
// non-rigid motion of the constraint's nodes as large as the push-out: a
// push-out alone is met by a force direction ā with ā_s·n = 0 exactly
// (contact/elimination/zero_work.hpp), a tangential force Newton cannot balance
// (docs/validation.md, §6.2). Otherwise the paper's force pushes it out
// (Constraint::push), unless a push-out of it was given up
// (ActiveSet::hold_pushes): then, as a slave's second constraint, it is
// held as far behind as it started; the history's min_active_gap shows it.
template <int D>
Constraint<D> make_constraint(const ContactPair<D>& pr, int p, int s, const Match<D>& end, const Positions<D>& x_n,
                              const Positions<D>& x_np1, const ActivationContext& context) {
  const Positions<D> x_mid = 0.5 * (x_n + x_np1);
  const Projection<D> start = project_on<D>(x_n.col(s), pr.master, end.facet, x_n);
  const Projection<D> mid = project_on<D>(x_mid.col(s), pr.master, end.facet, x_mid);
  Constraint<D> c;
  c.pair = p;
  c.slave = s;
  c.kind = context.kind.value_or(pr.kind);
  c.facet = end.facet;
  c.master = FacetIndex<D>(pr.master.facets, c.facet);
  c.xi = c.kind == Kind::stick ? start.xi : mid.xi;
  c.normal = mid.normal;
  c.tangents = mid.tangents;
  c.gap = start.gap;
  // A slave behind by no more than the search's penetration tolerance (the
  // round-off of the positions: a face met exactly at a step's end) is on
  // its facet: held at γ = 0.
  if (c.kind == Kind::frictionless && start.gap < 0.0 && start.gap >= -pr.search.penetration_tolerance) {
    c.gap = 0.0;
  } else if (c.kind == Kind::frictionless && start.gap < 0.0) {
    if (-start.gap <= push_out(c, x_n, x_np1)) {
      c.gap = 0.0;
    } else if (context.given_up) {
      c.hold = true;
    } else if (context.first) {
      c.gap = push_target(start.gap, context.facet_size);
      c.push = true;
    }
  }
  c.activated_step = context.step;
  return c;
}

template <int D>
bool forms_crease(const ContactPair<D>& pr, const Constraint<D>& held, const Match<D>& end) {
  // Two passes hold the crease's node out of the slave's facets instead.
  if (held.facet == end.facet || held.push || held.rate || pr.kind != Kind::frictionless || pr.passes > 1)
    return false;
  const auto& facets = pr.master.facets;
  bool shared = false;
  for (int a = 0; a < D; ++a)  // a shared vertex
    for (int b = 0; b < D; ++b) shared = shared || facets(a, end.facet) == held.master[b];
  const double cosine = held.normal.dot(end.projection.normal);
  return shared && cosine > 0.0 && !(1.0 - cosine * cosine < kCreaseSine * kCreaseSine);
}

namespace {

/// push_out on a facet of NF nodes.
template <int D, int NF>
double push_out_of(const Constraint<D>& c, const Positions<D>& x_a, const Positions<D>& x_b) {
  zero_work::Nodes<D, double, NF> y, d;
  auto put = [&](int column, int node) {
    y.col(column) = 0.5 * (x_a.col(node) + x_b.col(node));
    d.col(column) = x_b.col(node) - x_a.col(node);
  };
  put(0, c.slave);
  for (int b = 0; b < NF; ++b) put(b + 1, c.master[b]);
  // A push-out alone is met by ā_s·n = 0 (see make_constraint): only the
  // other non-rigid motion, slip and the facet's strain, can take it.
  const Eigen::Matrix<double, NF, 1> N = facet_weights<D>(NF, c.xi);
  d.col(0) -= c.normal * c.normal.dot(d.col(0) - d.template rightCols<NF>() * N);
  return kPushOut * zero_work::non_rigid_part<D, NF + 1, double>(y, d).norm();
}

}  // namespace

template <int D>
double push_out(const Constraint<D>& c, const Positions<D>& x_a, const Positions<D>& x_b) {
  if (c.master.size() == D) return push_out_of<D, D>(c, x_a, x_b);
  return push_out_of<D, kMaxFacetNodes<D>>(c, x_a, x_b);
}

template <int D>
bool repeats(const Constraint<D>& a, const Constraint<D>& b, const Positions<D>& x) {
  // The weight of c's slave at `node` on its facet, and the facet's normal.
  auto weight = [&](const Constraint<D>& c, int node, Vec<D>& normal) {
    for (int k = 0; k < c.master.size(); ++k) {
      if (c.master[k] != node) continue;
      if (c.master.size() != D) {
        typename CurvedFacet<D>::Nodes facet;
        for (int j = 0; j < c.master.size(); ++j) facet.col(j) = x.col(c.master[j]);
        const Projection<D> p = project_curved<D>(x.col(c.slave), facet).projection;
        normal = p.normal;
        return facet_weights<D>(c.master.size(), p.xi)(k);
      }
      FacetNodes<D> facet;
      for (int j = 0; j < D; ++j) facet.col(j) = x.col(c.master[j]);
      const Projection<D> p = project<D>(x.col(c.slave), facet);
      normal = p.normal;
      return facet_shape<D>(p.xi)(k);
    }
    return 0.0;
  };
  Vec<D> na = Vec<D>::Zero(), nb = Vec<D>::Zero();
  const double wa = weight(a, b.slave, na);
  if (wa == 0.0) return false;
  const double wb = weight(b, a.slave, nb);
  const double cosine = na.dot(nb);
  return std::abs(1.0 - wa * wb * cosine * cosine) < kRepeatPivot;
}

#define CONSERVE_ACTIVATION(D)                                                                                   \
  template Constraint<D> make_constraint<D>(const ContactPair<D>&, int, int, const Match<D>&, const Positions<D>&, \
                                            const Positions<D>&, const ActivationContext&);                      \
  template bool forms_crease<D>(const ContactPair<D>&, const Constraint<D>&, const Match<D>&);                  \
  template double push_out<D>(const Constraint<D>&, const Positions<D>&, const Positions<D>&);                  \
  template bool repeats<D>(const Constraint<D>&, const Constraint<D>&, const Positions<D>&);
CONSERVE_ACTIVATION(2)
CONSERVE_ACTIVATION(3)
#undef CONSERVE_ACTIVATION

}  // namespace conserve::contact
