#include "contact/penalty/penalty.hpp"

#include <fmt/format.h>

#include <unsupported/Eigen/AutoDiff>

#include <algorithm>
#include <cmath>
#include <limits>

#include "contact/penalty/penalty_force.hpp"
#include "core/bytes.hpp"
#include "fem/simplex.hpp"

namespace conserve::contact {
namespace {

/// Out-of-plane thickness of a 2D body (1 in 3D) [m]: a cell's volume over
/// its area.
template <int D>
double thickness(const model::Model<D>& model, int body) {
  if constexpr (D == 3) {
    return 1.0;
  } else {
    const model::Body& b = model.bodies[static_cast<std::size_t>(body)];
    if (b.num_cells == 0) return 1.0;
    if (model.order != 1) return b.thickness;
    fem::NodeMatrix<2> X;
    for (int a = 0; a < 3; ++a) X.col(a) = model.X.col(model.cells(a, b.first_cell));
    return model.geometry[static_cast<std::size_t>(b.first_cell)].volume / std::abs(fem::signed_measure<2>(X));
  }
}

/// Measure of facet f of `surface` in the reference configuration [m²]
/// (2D: length × thickness).
template <int D>
double facet_measure(const model::Model<D>& model, const ContactSurface& surface, int f) {
  const FacetNodes<D> x = facet_nodes<D>(surface, f, model.X);
  if constexpr (D == 2) {
    return (x.col(1) - x.col(0)).norm() * thickness<D>(model, surface.body);
  } else {
    return 0.5 * (x.col(1) - x.col(0)).cross(x.col(2) - x.col(0)).norm();
  }
}

double young_modulus(const material::Law& law) {
  const material::Lame l = law.small_strain();
  return l.mu * (3.0 * l.lambda + 2.0 * l.mu) / (l.lambda + l.mu);
}

/// A coupling's anchor as the force's argument (null: frictionless).
template <int D>
struct AnchorOf {
  explicit AnchorOf(const PenaltyCoupling& c) {
    for (int i = 0; i + 1 < D; ++i) xi(i) = c.anchor[static_cast<std::size_t>(i)];
    ptr = c.stick ? &xi : nullptr;
  }
  Eigen::Matrix<double, D - 1, 1> xi;
  penalty::Anchor<D> ptr;
};

/// A slave whose projection lies this far (in isoparametric units) off a
/// facet is over its face: round-off of a slave over a shared edge.
constexpr double kOnFace = 1e-12;

}  // namespace

template <int D>
double automatic_penalty(const model::Model<D>& model, const ContactPair<D>& pair) {
  const auto stiffness = [&](const ContactSurface& side) {
    std::vector<double> h = facet_sizes<D>(side, model.X);
    std::nth_element(h.begin(), h.begin() + static_cast<std::ptrdiff_t>(h.size() / 2), h.end());
    return young_modulus(*model.bodies[static_cast<std::size_t>(side.body)].law) / h[h.size() / 2];
  };
  if (pair.slave.rigid) return stiffness(pair.master);  // a driven body's nodes in a second pass
  const double slave = stiffness(pair.slave);
  return pair.master.rigid ? slave : std::min(slave, stiffness(pair.master));
}

template <int D>
PenaltyMethod<D>::PenaltyMethod(const model::Model<D>& model, std::vector<ContactPair<D>> pairs,
                                const std::vector<double>& penalty, bool conserving)
    : model_(model), collisions_(model, std::move(pairs)), conserving_(conserving) {
  for (int p = 0; p < collisions_.size(); ++p) {
    const ContactPair<D>& pair = collisions_.pair(p);
    const auto given = static_cast<std::size_t>(p) < penalty.size() ? penalty[static_cast<std::size_t>(p)] : 0.0;
    epsilon_.push_back(given > 0.0 ? given : automatic_penalty<D>(model, pair));
    std::map<int, double> area;
    for (int f = 0; f < pair.slave.num_facets(); ++f) {
      const double share = facet_measure<D>(model, pair.slave, f) / D;
      for (int a = 0; a < D; ++a) area[pair.slave.facets(a, f)] += share;
    }
    area_.push_back(std::move(area));
  }
  extra_.resize(static_cast<std::size_t>(model.num_nodes()));
}

template <int D>
Eigen::Matrix<double, D, D + 1> PenaltyMethod<D>::nodes(const PenaltyCoupling& c, const Positions<D>& x) const {
  Eigen::Matrix<double, D, D + 1> y;
  y.col(0) = x.col(c.slave);
  y.template rightCols<D>() = facet_nodes<D>(collisions_.pair(c.pair).master, c.facet, x);
  return y;
}

template <int D>
std::vector<PenaltyCoupling> PenaltyMethod<D>::behind_at(const Eigen::VectorXd& u) {
  std::vector<PenaltyCoupling> found;
  const Positions<D> x = positions(u);
  collisions_.for_each_match(
      x,
      [&](int p, std::size_t, int s, const Match<D>& m) {
        PenaltyCoupling c{p, s, m.facet, epsilon_[static_cast<std::size_t>(p)] * area_[static_cast<std::size_t>(p)].at(s)};
        if (collisions_.pair(p).kind != Kind::stick) {
          // Behind the surface where the search put it (the nearest part
          // around the facet it found, in front or behind), on that part's
          // facet: the same test as the potential's.
          const Feature<D> f = nearest(p, s, m.facet, x);
          if (!f.behind) return;
          c.facet = f.facet;
        } else {  // caught where it was at the step's start, behind its facet
          if (!(m.projection.gap < 0.0)) return;
          c.stick = true;
          const Eigen::Matrix<double, D - 1, 1> xi = penalty::projected_xi<D>(nodes(c, x_n_));
          for (int i = 0; i + 1 < D; ++i) c.anchor[static_cast<std::size_t>(i)] = xi(i);
        }
        found.push_back(c);
      },
      &x_n_);
  return found;
}

template <int D>
void PenaltyMethod<D>::begin_step(std::int64_t, double, const model::State& start) {
  u_n_ = start.u;
  x_n_ = positions(start.u);
  pairing_.clear();
}

template <int D>
std::vector<int> PenaltyMethod<D>::around(int p, int f) const {
  const ContactSurface& master = collisions_.pair(p).master;
  std::vector<int> facets{f};
  for (int a = 0; a < D; ++a)
    for (int g : master.node_facets[static_cast<std::size_t>(master.local_node(master.facets(a, f)))])
      if (std::find(facets.begin(), facets.end(), g) == facets.end()) facets.push_back(g);
  return facets;
}

template <int D>
Feature<D> PenaltyMethod<D>::nearest(int p, int s, int f, const Positions<D>& x) const {
  const ContactSurface& master = collisions_.pair(p).master;
  const Vec<D> x_s = x.col(s);
  Feature<D> best;
  double best_distance = std::numeric_limits<double>::infinity();
  Projection<D> best_projection;
  Xi<D> best_xi = Xi<D>::Zero();
  for (int g : around(p, f)) {
    const FacetNodes<D> xg = facet_nodes<D>(master, g, x);
    const Projection<D> pr = project<D>(x_s, xg);
    // Over a facet's face up to round-off (a slave over the edge two
    // facets share), the face: its potential is the plane's.
    const bool face = pr.inside(kOnFace);
    const auto [xi, distance] =
        face ? std::pair<Xi<D>, double>{pr.xi, std::abs(pr.gap)} : closest_point_on_facet<D>(x_s, xg, pr);
    if (distance < best_distance) {
      best_distance = distance;
      best.facet = g;
      best_projection = pr;
      best_xi = xi;
    }
  }
  const FacetNodes<D> xf = facet_nodes<D>(master, best.facet, x);
  const Vec<D> N = facet_shape<D>(best_xi);
  best.point = best_projection.inside(kOnFace) ? best_projection.point : Vec<D>(xf * N);
  // The pseudo-normal of the nearest part (Bærentzen & Aanæs 2005): its
  // facet's normal, the sum over the facets at an edge, angle-weighted
  // over those at a vertex. x_s is behind the surface where
  // (x_s − point)·n < 0: it turns only where the distance is 0.
  std::vector<int> on;  // the feature's nodes (local to the facet)
  if (best_projection.inside(kOnFace)) {
    best.kind = penalty::FeatureKind::face;
    best.normal = best_projection.normal;
  } else {
    for (int a = 0; a < D; ++a)
      if (N(a) > 0.0) on.push_back(a);
    best.kind = on.size() == 1 ? penalty::FeatureKind::vertex : penalty::FeatureKind::edge;
    for (std::size_t i = 0; i < on.size(); ++i) best.node[i] = master.facets(on[i], best.facet);
    best.normal.setZero();
    const int first = best.node[0];
    for (int g : master.node_facets[static_cast<std::size_t>(master.local_node(first))]) {
      int with_second = best.kind == penalty::FeatureKind::vertex ? 1 : 0;
      for (int a = 0; a < D; ++a) with_second += master.facets(a, g) == best.node[1];
      if (with_second == 0) continue;
      const FacetNodes<D> xg = facet_nodes<D>(master, g, x);
      double weight = 1.0;
      if constexpr (D == 3) {
        if (best.kind == penalty::FeatureKind::vertex) {  // the facet's angle at the vertex
          int at = 0;
          while (master.facets(at, g) != first) ++at;
          const Vec<D> e1 = (xg.col((at + 1) % 3) - xg.col(at)).normalized();
          const Vec<D> e2 = (xg.col((at + 2) % 3) - xg.col(at)).normalized();
          weight = std::acos(std::clamp(e1.dot(e2), -1.0, 1.0));
        }
      }
      best.normal += weight * facet_normal<D>(xg);
    }
  }
  best.distance = best_distance;
  best.behind = (x_s - best.point).dot(best.normal) < 0.0;
  return best;
}

template <int D>
double PenaltyMethod<D>::potential(const PenaltyCoupling& c, const Feature<D>& feature, const Positions<D>& x) const {
  if (!feature.behind) return 0.0;
  PenaltyCoupling on = c;
  on.facet = feature.facet;
  if (feature.kind == penalty::FeatureKind::face) return penalty::penalty_energy<D>(nodes(on, x), c.k);
  const Vec<D> x_s = x.col(c.slave), x_a = x.col(feature.node[0]);
  if (feature.kind == penalty::FeatureKind::vertex) return penalty::point_potential<D, double>(x_s, x_a, nullptr, c.k);
  const Vec<D> x_b = x.col(feature.node[1]);
  return penalty::point_potential<D, double>(x_s, x_a, &x_b, c.k);
}

template <int D>
bool PenaltyMethod<D>::move_anchor(PenaltyCoupling& c, const Positions<D>& x) const {
  const ContactSurface& master = collisions_.pair(c.pair).master;
  const Vec<D> x_s = x.col(c.slave);
  if (project<D>(x_s, facet_nodes<D>(master, c.facet, x)).inside(kOnFace)) return false;
  for (int g : around(c.pair, c.facet)) {
    const FacetNodes<D> xg = facet_nodes<D>(master, g, x);
    const Projection<D> pr = project<D>(x_s, xg);
    if (g == c.facet || !pr.inside(0.0) || !(pr.gap < 0.0)) continue;
    // The spring's stretch A (ξ − ξ₀) on the old facet, turned into the
    // new one's plane at its length.
    const Eigen::Matrix<double, D, D + 1> y = nodes(c, x);
    const Eigen::Matrix<double, D, D> V = penalty::relative_vectors<D, double>(y);
    Eigen::Matrix<double, D - 1, 1> xi0;
    for (int i = 0; i + 1 < D; ++i) xi0(i) = c.anchor[static_cast<std::size_t>(i)];
    const Vec<D> stretch = V.template leftCols<D - 1>() * (penalty::projected_xi<D>(y) - xi0);
    Vec<D> turned = stretch - stretch.dot(pr.normal) * pr.normal;
    if (turned.norm() > 0.0) turned *= stretch.norm() / turned.norm();
    PenaltyCoupling moved = c;
    moved.facet = g;
    const Eigen::Matrix<double, D, D + 1> y_g = nodes(moved, x);
    const Eigen::Matrix<double, D, D - 1> A = penalty::relative_vectors<D, double>(y_g).template leftCols<D - 1>();
    const Eigen::Matrix<double, D - 1, 1> anchor =
        penalty::projected_xi<D>(y_g) - (A.transpose() * A).ldlt().solve(A.transpose() * turned);
    for (int i = 0; i + 1 < D; ++i) moved.anchor[static_cast<std::size_t>(i)] = anchor(i);
    c = moved;
    return true;
  }
  return false;
}

template <int D>
StepPlan<D> PenaltyMethod<D>::plan(const PenaltyCoupling& c, const Positions<D>& x_n, const Positions<D>& x) const {
  StepPlan<D> plan;
  const AnchorOf<D> anchor(c);
  if (c.stick) {  // on its facet's plane throughout, with its spring
    plan.same = true;
    plan.phi_n = penalty::penalty_energy<D>(nodes(c, x_n), c.k, anchor.ptr);
    return plan;
  }
  const Positions<D> x_mid = 0.5 * (x_n + x);
  plan.start = nearest(c.pair, c.slave, c.start_facet < 0 ? c.facet : c.start_facet, x_n);
  plan.end = nearest(c.pair, c.slave, c.facet, x);
  plan.mid = nearest(c.pair, c.slave, c.facet, x_mid);
  // The energy the step starts from: what the last step ended with (a
  // slave coupled in this step brings its own in, counted at the step's end).
  plan.phi_n = potential(c, plan.start, x_n);
  const bool faces = plan.start.kind == penalty::FeatureKind::face && plan.end.kind == penalty::FeatureKind::face &&
                     plan.mid.kind == penalty::FeatureKind::face;
  plan.same = faces && plan.start.facet == plan.end.facet && plan.mid.facet == plan.end.facet;
  if (faces && !plan.same) {
    // Faces of facets in one plane (a slave sliding over a flat master):
    // the end facet's potential is the start's, so its discrete gradient
    // in invariants holds the step.
    PenaltyCoupling on = c;
    on.facet = plan.end.facet;
    const double end_at_start = penalty::penalty_energy<D>(nodes(on, x_n), c.k);
    on.facet = plan.mid.facet;
    const double mid_at_start = penalty::penalty_energy<D>(nodes(on, x_n), c.k);
    const double tolerance = 64 * std::numeric_limits<double>::epsilon() * std::max(plan.phi_n, 1e-300);
    plan.same = std::abs(end_at_start - plan.phi_n) <= tolerance && std::abs(mid_at_start - plan.phi_n) <= tolerance;
    if (plan.same) plan.mid.facet = plan.start.facet = plan.end.facet;
  }
  return plan;
}

template <int D>
void PenaltyMethod<D>::add_force(const std::vector<PenaltyCoupling>& couplings, const Eigen::VectorXd& u_n,
                                 const Eigen::VectorXd& u, Eigen::VectorXd& g, Eigen::VectorXd* magnitude,
                                 SparseMatrix* K) const {
  const Positions<D> x_n = positions(u_n), x = positions(u);
  for (const PenaltyCoupling& c : couplings) {
    const AnchorOf<D> anchor(c);
    const StepPlan<D> step = plan(c, x_n, x);
    const ContactSurface& master = collisions_.pair(c.pair).master;
    // The coupling's nodes: the slave and the facet(s) its potential is
    // measured on at the end and at the mid-point.
    PenaltyCoupling on = c;
    if (!c.stick) on.facet = step.end.facet;
    std::vector<int> node{c.slave};
    for (int a = 0; a < D; ++a) node.push_back(master.facets(a, on.facet));
    if (!step.same)
      for (int a = 0; a < D; ++a)
        if (std::find(node.begin(), node.end(), master.facets(a, step.mid.facet)) == node.end())
          node.push_back(master.facets(a, step.mid.facet));
    const auto M = static_cast<Eigen::Index>(node.size());
    const auto column = [&](int global) {
      return static_cast<Eigen::Index>(std::find(node.begin(), node.end(), global) - node.begin());
    };
    penalty::StepNodes<double, D> X_n(D, M), X_1(D, M);
    for (Eigen::Index a = 0; a < M; ++a) X_n.col(a) = x_n.col(node[a]), X_1.col(a) = x.col(node[a]);
    penalty::StepNodes<double, D> f(D, M);
    const auto add_derivatives = [&](const auto& f_ad) {
      for (Eigen::Index a = 0; a < M; ++a)
        for (int i = 0; i < D; ++i) {
          f(i, a) = f_ad(i, a).value();
          const auto& row = f_ad(i, a).derivatives();
          if (row.size() == 0) continue;  // a constant (no force)
          for (Eigen::Index b = 0; b < M; ++b)
            for (int j = 0; j < D; ++j)
              if (row[b * D + j] != 0.0) K->coeffRef(node[a] * D + i, node[b] * D + j) += row[b * D + j];
        }
    };
    if (step.same) {  // one facet's face throughout: the discrete gradient in invariants
      const Eigen::Matrix<double, D, D + 1> y_n = X_n.template leftCols<D + 1>(), y = X_1.template leftCols<D + 1>();
      if (K) {
        constexpr int N = D * (D + 1);
        using Ad = Eigen::AutoDiffScalar<Eigen::Matrix<double, N, 1>>;
        penalty::CouplingNodes<D, Ad> y_ad;
        for (int a = 0; a <= D; ++a)
          for (int i = 0; i < D; ++i) y_ad(i, a) = Ad(y(i, a), N, a * D + i);
        add_derivatives(penalty::penalty_force<D, Ad>(y_n, y_ad, c.k, conserving_, anchor.ptr, friction(c)));
      } else {
        f = penalty::penalty_force<D, double>(y_n, y, c.k, conserving_, anchor.ptr, friction(c));
      }
    } else {
      // The nearest part changes in the step: the switching discrete
      // gradient of the potential, which is continuous across the change
      // (the mid-point gradient alone for the negative control).
      const auto potential_at = [&](const auto& X, const Feature<D>& feature, auto* grad) {
        using T = typename std::decay_t<decltype(X)>::Scalar;
        using Vt = Eigen::Matrix<T, D, 1>;
        if (!feature.behind) return T(0);
        if (feature.kind == penalty::FeatureKind::face) {
          penalty::CouplingNodes<D, T> y;
          y.col(0) = X.col(0);
          for (int a = 0; a < D; ++a) y.col(a + 1) = X.col(column(master.facets(a, feature.facet)));
          if (grad) {
            const penalty::CouplingNodes<D, T> gy = penalty::penalty_gradient<D, T>(y, c.k);
            grad->col(0) += gy.col(0);
            for (int a = 0; a < D; ++a) grad->col(column(master.facets(a, feature.facet))) += gy.col(a + 1);
          }
          return penalty::penalty_potential<D, T>(y, c.k);
        }
        const Vt x_s = X.col(0), x_a = X.col(column(feature.node[0]));
        const bool edge = feature.kind == penalty::FeatureKind::edge;
        const Vt x_b = edge ? Vt(X.col(column(feature.node[1]))) : x_a;
        Eigen::Matrix<T, D, 3> gp;
        const T phi = penalty::point_potential<D, T>(x_s, x_a, edge ? &x_b : nullptr, c.k, &gp);
        if (grad) {
          grad->col(0) += gp.col(0);
          grad->col(column(feature.node[0])) += gp.col(1);
          if (edge) grad->col(column(feature.node[1])) += gp.col(2);
        }
        return phi;
      };
      const auto switching = [&](const auto& X) {
        using T = typename std::decay_t<decltype(X)>::Scalar;
        const penalty::StepNodes<T, D> X_mid = T(0.5) * (X + X_n.template cast<T>());
        penalty::StepNodes<T, D> grad = penalty::StepNodes<T, D>::Zero(D, M);
        potential_at(X_mid, step.mid, &grad);
        if (!conserving_) return grad;
        const T phi_1 = potential_at(X, step.end, static_cast<penalty::StepNodes<T, D>*>(nullptr));
        return penalty::switching_gradient<D, T>(X_n, X, step.phi_n, phi_1, grad);
      };
      if (K) {
        using Ad = Eigen::AutoDiffScalar<Eigen::VectorXd>;
        penalty::StepNodes<Ad, D> X_ad(D, M);
        for (Eigen::Index a = 0; a < M; ++a)
          for (int i = 0; i < D; ++i) X_ad(i, a) = Ad(X_1(i, a), D * M, a * D + i);
        add_derivatives(switching(X_ad));
      } else {
        f = switching(X_1);
      }
    }
    for (Eigen::Index a = 0; a < M; ++a) {
      g.template segment<D>(node[a] * D) += f.col(a);
      if (magnitude) magnitude->template segment<D>(node[a] * D) += f.col(a).cwiseAbs();
    }
  }
}

template <int D>
const SparseMatrix& PenaltyMethod<D>::pattern(const SparseMatrix& K, const std::vector<PenaltyCoupling>& couplings,
                                              const std::vector<int>*& from_K, int& builds) {
  // Block (i, j) is in K's pattern if dof (i·D, j·D) is (node blocks).
  const auto in_K = [&](int i, int j) {
    const int col = j * D, row = i * D;
    const auto* begin = K.innerIndexPtr() + K.outerIndexPtr()[col];
    const auto* end = K.innerIndexPtr() + K.outerIndexPtr()[col + 1];
    return std::binary_search(begin, end, row);
  };
  bool grown = K.nonZeros() != K_nonzeros_;
  for (const PenaltyCoupling& c : couplings) {
    // The slave and the nodes of the facets around its facet: the parts
    // its potential may be measured on in the pass.
    std::vector<int> node{c.slave};
    for (int f : c.stick ? std::vector<int>{c.facet} : around(c.pair, c.facet))
      for (int a = 0; a < D; ++a) {
        const int n = collisions_.pair(c.pair).master.facets(a, f);
        if (std::find(node.begin(), node.end(), n) == node.end()) node.push_back(n);
      }
    for (int i : node)
      for (int j : node) {
        auto& extra = extra_[static_cast<std::size_t>(i)];
        if (std::find(extra.begin(), extra.end(), j) != extra.end() || in_K(i, j)) continue;  // (i, i) too: another rank's row
        extra.push_back(j);
        grown = true;
      }
  }
  if (grown) {
    ++builds;
    std::vector<Eigen::Triplet<double>> entries;
    entries.reserve(static_cast<std::size_t>(K.nonZeros()));
    for (int col = 0; col < K.outerSize(); ++col)
      for (SparseMatrix::InnerIterator it(K, col); it; ++it) entries.emplace_back(it.row(), col, 0.0);
    for (std::size_t i = 0; i < extra_.size(); ++i)
      for (int j : extra_[i])
        for (int a = 0; a < D; ++a)
          for (int b = 0; b < D; ++b) entries.emplace_back(static_cast<int>(i) * D + a, j * D + b, 0.0);
    pattern_ = SparseMatrix(K.rows(), K.cols());
    pattern_.setFromTriplets(entries.begin(), entries.end());
    pattern_.makeCompressed();
    from_K_.assign(static_cast<std::size_t>(K.nonZeros()), -1);
    for (int col = 0; col < K.outerSize(); ++col) {
      const auto* begin = pattern_.innerIndexPtr() + pattern_.outerIndexPtr()[col];
      const auto* end = pattern_.innerIndexPtr() + pattern_.outerIndexPtr()[col + 1];
      for (auto k = K.outerIndexPtr()[col]; k < K.outerIndexPtr()[col + 1]; ++k)
        from_K_[static_cast<std::size_t>(k)] =
            static_cast<int>(std::lower_bound(begin, end, K.innerIndexPtr()[k]) - pattern_.innerIndexPtr());
    }
    K_nonzeros_ = K.nonZeros();
  }
  from_K = &from_K_;
  return pattern_;
}

namespace {

/// One solve's penalty: r = g + ∂Φ/∂u, tangent K + ∂²Φ/∂u² in the kept
/// pattern; the unknowns are the bodies'.
template <int D>
class PenaltySystem final : public Coupling {
 public:
  PenaltySystem(PenaltyMethod<D>& method, std::vector<PenaltyCoupling> couplings, const Eigen::VectorXd& u_n)
      : method_(method), couplings_(std::move(couplings)), u_n_(u_n) {}
  [[nodiscard]] bool plain() const override { return couplings_.empty(); }
  [[nodiscard]] int equations(int dofs) const override { return dofs; }
  void start(Eigen::VectorXd&) override {}
  void residual(const Eigen::VectorXd& u, Eigen::VectorXd& g, Eigen::VectorXd& magnitude, Eigen::VectorXd& r) override {
    method_.add_force(couplings_, u_n_, u, g, &magnitude, nullptr);
    r = g;
  }
  bool tangent(const Eigen::VectorXd& u, const SparseMatrix& K, const Eigen::VectorXd&, SparseMatrix& A) override {
    // Each coupling's tangent is added by the rank that owns its slave.
    std::vector<PenaltyCoupling> mine;
    for (const PenaltyCoupling& c : couplings_)
      if (method_.owns(c.slave)) mine.push_back(c);
    const std::vector<int>* from_K = nullptr;
    int builds = 0;
    const SparseMatrix& pattern = method_.pattern(K, mine, from_K, builds);
    const bool fresh = builds > 0 || A.nonZeros() != pattern.nonZeros() || A.rows() != pattern.rows();
    if (fresh) A = pattern;
    std::fill(A.valuePtr(), A.valuePtr() + A.nonZeros(), 0.0);
    for (std::size_t k = 0; k < from_K->size(); ++k) A.valuePtr()[(*from_K)[k]] += K.valuePtr()[k];
    Eigen::VectorXd unused = Eigen::VectorXd::Zero(u.size());
    method_.add_force(mine, u_n_, u, unused, nullptr, &A);
    return fresh;
  }
  void update(const Eigen::VectorXd& increment, Eigen::VectorXd& u) override { u += increment; }
  void save() override {}
  bool restore() override { return true; }

 private:
  PenaltyMethod<D>& method_;
  std::vector<PenaltyCoupling> couplings_;
  const Eigen::VectorXd& u_n_;
};

}  // namespace

template <int D>
std::unique_ptr<Coupling> PenaltyMethod<D>::coupling(const Eigen::VectorXd&, const Eigen::VectorXd& u_np1) {
  if (pairing_.empty()) {
    // The first solve: the slaves the last step ended behind a facet (on
    // that facet, a stuck one at its anchor: the energy the step starts
    // from is theirs), then the others behind a facet at the predictor.
    pairing_ = end_;
    for (PenaltyCoupling& c : pairing_) c.start_facet = c.facet;
    for (const PenaltyCoupling& c : behind_at(u_np1))
      if (std::none_of(pairing_.begin(), pairing_.end(),
                       [&](const PenaltyCoupling& o) { return o.slave == c.slave && o.pair == c.pair; }))
        pairing_.push_back(c);
  }
  return std::make_unique<PenaltySystem<D>>(*this, pairing_, u_n_);
}

template <int D>
Verdict PenaltyMethod<D>::settle(const model::State&, double, const Eigen::VectorXd& u_np1, const Eigen::VectorXd&,
                                 Eigen::VectorXd&, StepContactStats& stats) {
  ++stats.passes;
  // A slave behind the master at the end must be in the pairing. A
  // frictionless one's potential is measured on the facets around its
  // facet, so a pairing whose facet is near the end's nearest one is
  // right; one found further away is moved there for a few passes, then
  // kept (its step conserves either way). A stuck slave keeps its facet
  // and anchor.
  constexpr int kFollowFacets = 3;
  bool changed = false;
  for (const PenaltyCoupling& c : behind_at(u_np1)) {
    auto it = std::find_if(pairing_.begin(), pairing_.end(),
                           [&](const PenaltyCoupling& o) { return o.slave == c.slave && o.pair == c.pair; });
    if (it == pairing_.end()) {
      pairing_.push_back(c);
      changed = true;
    } else if (!it->stick && it->facet != c.facet && stats.passes <= kFollowFacets) {
      const std::vector<int> near = around(it->pair, it->facet);
      if (std::find(near.begin(), near.end(), c.facet) == near.end()) {
        it->facet = c.facet;
        changed = true;
      }
    }
  }
  return changed ? Verdict::changed : Verdict::accept;
}

template <int D>
void PenaltyMethod<D>::finish_step(const Eigen::VectorXd& u_n, const Eigen::VectorXd& u_np1, Eigen::VectorXd&,
                                   StepContactStats& stats) {
  const Positions<D> x = positions(u_np1);
  std::vector<PenaltyCoupling> end;
  forces_.clear();
  stored_ = 0.0;
  double min_gap = std::numeric_limits<double>::quiet_NaN(), max_gap = min_gap;
  int releases = 0, activations = 0;
  const auto was_behind = [&](int slave) {
    return std::any_of(end_.begin(), end_.end(), [&](const PenaltyCoupling& o) { return o.slave == slave; });
  };
  double released = 0.0, dissipated = 0.0;
  int sticking = 0, slipping = 0;
  for (PenaltyCoupling c : pairing_) {
    const StepPlan<D> step = plan(c, x_n_, x);
    // A slave coupled in this step that started it behind the master
    // brings that potential in (the last step ended without it).
    if (c.start_facet < 0) released -= step.phi_n;
    double normal = 0.0, energy = 0.0;
    Vec<D> direction;
    if (c.stick) {
      if (std::isfinite(friction(c))) {  // Coulomb: where the step's return map left the anchor
        penalty::CoulombStep<D, double> slip;
        penalty::penalty_force<D, double>(nodes(c, x_n_), nodes(c, x), c.k, conserving_, AnchorOf<D>(c).ptr,
                                          friction(c), &slip);
        for (int i = 0; i + 1 < D; ++i) c.anchor[static_cast<std::size_t>(i)] = slip.anchor(i);
        c.slipped = slip.slips;
        dissipated += slip.dissipated;
      }
      Eigen::Matrix<double, D, D + 1> y = nodes(c, x);
      normal = penalty::penalty_energy<D>(y, c.k);
      energy = penalty::penalty_energy<D>(y, c.k, AnchorOf<D>(c).ptr);
      if (!(normal > 0.0)) {
        released += energy;  // in front: let go, with the spring's energy
      } else if (std::isfinite(friction(c)) && move_anchor(c, x)) {
        // Slipped off its facet: on the next, the spring's energy kept, the
        // normal potential's change counted.
        y = nodes(c, x);
        const double moved = penalty::penalty_energy<D>(y, c.k, AnchorOf<D>(c).ptr);
        released += energy - moved;
        energy = moved;
        normal = penalty::penalty_energy<D>(y, c.k);
      }
      direction = facet_normal<D>(y.template rightCols<D>());
    } else {
      normal = energy = potential(c, step.end, x);
      // The next step measures its start around this facet: if a part
      // nearer still lies there, its potential is the one stored, and the
      // difference is counted.
      const Feature<D> next = nearest(c.pair, c.slave, step.end.facet, x);
      c.facet = next.facet;
      if (next.facet != step.end.facet || next.kind != step.end.kind) {
        const double e = potential(c, next, x);
        released += energy - e;
        normal = energy = e;
      }
      direction = next.normal.normalized();
    }
    if (!(normal > 0.0)) {
      releases += was_behind(c.slave);
      continue;
    }
    activations += !was_behind(c.slave);
    if (c.stick && std::isfinite(friction(c))) ++(c.slipped ? slipping : sticking);
    stored_ += energy;
    end.push_back(c);
    const double gap = -std::sqrt(2.0 * normal / c.k);
    min_gap = std::isnan(min_gap) ? gap : std::min(min_gap, gap);
    max_gap = std::isnan(max_gap) ? gap : std::max(max_gap, gap);
    // The contact force on the slave at the step's end along the
    // surface's normal there: k |g|.
    // The whole force, −∂Φ/∂x_s at the end (stick: with the spring's pull).
    Vec<D> force = c.k * -gap * direction;
    if (c.stick) force = -penalty::penalty_gradient<D, double>(nodes(c, x), c.k, AnchorOf<D>(c).ptr).col(0);
    // (The force at the step's end: the reactions it gives a prescribed
    // master are approximate, unlike elimination's step forces.)
    const Vec<D> moved = (u_np1 - u_n).template segment<D>(c.slave * D);
    forces_.push_back({.slave = c.slave,
                       .normal = c.k * -gap,
                       .direction = direction,
                       .pair = c.pair,
                       .sticks = c.stick && !c.slipped,
                       .force = force,
                       .moment = moment_of<D>(x.col(c.slave), force),
                       .work = force.dot(moved)});
  }
  stats.releases = releases;
  stats.activations = activations;
  stats.contact_released = released;
  stats.dissipated = dissipated;
  stats.sticking = sticking;
  stats.slipping = slipping;
  end_ = std::move(end);
  stats.contact_energy = stored_;
  stats.min_active_gap = min_gap;
  stats.max_active_gap = max_gap;
  stats.slave_penetration = collisions_.slave_penetration(x, &x_n_).depth;
  stats.master_penetration = collisions_.master_penetration(x, positions(u_n)).depth;
}

template <int D>
std::vector<std::pair<std::string, double>> PenaltyMethod<D>::settings() const {
  std::vector<std::pair<std::string, double>> s;
  for (std::size_t p = 0; p < epsilon_.size(); ++p) s.emplace_back(fmt::format("penalty[{}]", p), epsilon_[p]);
  return s;
}

template <int D>
std::string PenaltyMethod<D>::save() const {
  ByteWriter w;
  w.value(stored_);
  w.value(static_cast<std::uint64_t>(end_.size()));
  for (const PenaltyCoupling& c : end_) {
    w.value(static_cast<std::int32_t>(c.pair));
    w.value(static_cast<std::int32_t>(c.slave));
    w.value(static_cast<std::int32_t>(c.facet));
    w.value(c.k);
    w.value(static_cast<std::int32_t>(c.stick ? (c.slipped ? 2 : 1) : 0));
    w.doubles(c.anchor.data(), c.anchor.size());
  }
  w.value(static_cast<std::uint64_t>(forces_.size()));
  for (const ContactForce<D>& f : forces_) {
    w.value(static_cast<std::int32_t>(f.slave));
    w.value(f.normal);
    w.doubles(f.direction.data(), D);
    w.value(static_cast<std::int32_t>(f.pair));
    w.doubles(f.force.data(), D);
  }
  return w.bytes();
}

template <int D>
void PenaltyMethod<D>::load(const std::string& bytes, const std::string& what) {
  ByteReader r(bytes, what);
  const double stored = r.value<double>();
  const auto count = r.value<std::uint64_t>();
  if (count > static_cast<std::uint64_t>(model_.num_nodes())) r.fail("more penalty couplings than nodes");
  std::vector<PenaltyCoupling> end;
  for (std::uint64_t i = 0; i < count; ++i) {
    PenaltyCoupling c;
    c.pair = r.value<std::int32_t>();
    c.slave = r.value<std::int32_t>();
    c.facet = r.value<std::int32_t>();
    c.k = r.value<double>();
    const auto stick = r.value<std::int32_t>();
    r.doubles(c.anchor.data(), c.anchor.size(), "a stick spring's anchor");
    c.stick = stick != 0;
    c.slipped = stick == 2;
    if ((stick < 0 || stick > 2) || c.pair < 0 || c.pair >= collisions_.size() || c.facet < 0 ||
        c.facet >= collisions_.pair(c.pair).master.num_facets() || c.slave < 0 || c.slave >= model_.num_nodes())
      r.fail("a penalty coupling is malformed (a pair, facet or node out of range)");
    end.push_back(c);
  }
  const auto forces = r.value<std::uint64_t>();
  if (forces != count) r.fail("a penalty force is missing");
  std::vector<ContactForce<D>> f(forces);
  for (std::size_t i = 0; i < f.size(); ++i) {
    ContactForce<D>& x = f[i];
    x.slave = r.value<std::int32_t>();
    x.normal = r.value<double>();
    r.doubles(x.direction.data(), D, "a penalty force's direction");
    x.pair = r.value<std::int32_t>();
    r.doubles(x.force.data(), D, "a penalty force");
    if (x.pair < 0 || x.pair >= collisions_.size()) r.fail("a penalty force's pair is out of range");
    x.sticks = end[i].stick && !end[i].slipped;
  }
  if (!r.at_end()) r.fail("trailing bytes after the penalty couplings");
  stored_ = stored;
  end_ = std::move(end);
  forces_ = std::move(f);
}

template double automatic_penalty<2>(const model::Model<2>&, const ContactPair<2>&);
template double automatic_penalty<3>(const model::Model<3>&, const ContactPair<3>&);
template class PenaltyMethod<2>;
template class PenaltyMethod<3>;

}  // namespace conserve::contact
