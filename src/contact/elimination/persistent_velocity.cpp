#include "contact/elimination/persistent_velocity.hpp"

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <optional>

#include "contact/elimination/zero_work.hpp"
#include "contact/search.hpp"

namespace conserve::contact {

namespace {

/// The largest change t of the energy-restoring scale accepted: beyond
/// it the motion left to carry the energy is too small to take it
/// without being distorted, and V* is kept for the step.
constexpr double kMaxScale = 0.25;

/// The root t nearest 0 of K + t b + ½ t² k = K + dK (b = wᵀMV, k = wᵀMw),
/// none if there is no real one or |t| > kMaxScale.
std::optional<double> energy_scale(double b, double k, double dK) {
  const double disc = b * b + 2.0 * k * dK;
  if (!(k > 0.0) || !(b > 0.0) || !(disc >= 0.0)) return std::nullopt;
  const double t = 2.0 * dK / (b + std::sqrt(disc));
  if (!(std::abs(t) <= kMaxScale)) return std::nullopt;
  return t;
}

}  // namespace

template <int D>
PersistentVelocity<D>::PersistentVelocity(const model::Model<D>& model, const SparseMatrix& mass)
    : model_(model),
      mass_(mass),
      nodal_(mass.rows() == model.num_nodes()),
      lumped_(Eigen::VectorXd::Zero(model.num_dofs())),
      prescribed_(static_cast<std::size_t>(model.num_dofs()), 0),
      free_body_(static_cast<std::size_t>(model.num_nodes()), 0) {
  // M_L: the row sums of M; where one is not positive (the vertices of
  // quadratic cells: 0 on a 6-node triangle, negative on a 10-node
  // tetrahedron), M's diagonal scaled to the same total (HRZ lumping) for
  // every dof instead, so that every dof of a free body stays free. M_L
  // is the metric of the corrections only; M keeps E, L and J.
  Eigen::VectorXd diagonal = Eigen::VectorXd::Zero(model.num_dofs());
  for (int k = 0; k < mass.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(mass, k); it; ++it) {
      if (nodal_) {
        lumped_.segment<D>(it.row() * D).array() += it.value();
        if (it.row() == it.col()) diagonal.segment<D>(it.row() * D).array() += it.value();
      } else {
        lumped_[it.row()] += it.value();
        if (it.row() == it.col()) diagonal[it.row()] += it.value();
      }
    }
  if ((lumped_.array() <= 0.0 && diagonal.array() > 0.0).any()) lumped_ = diagonal * (lumped_.sum() / diagonal.sum());
  for (int d : model.held_dofs()) prescribed_[d] = 1;
  for (const model::FreeBody& b : model.free_bodies)
    std::fill_n(free_body_.begin() + b.first_node, b.num_nodes, 1);
}

template <int D>
Eigen::VectorXd PersistentVelocity<D>::times_mass(const Eigen::VectorXd& x) const {
  if (!nodal_) return mass_ * x;
  const Eigen::Index nodes = mass_.rows();
  Eigen::VectorXd y(x.size());
  // M_AB symmetric: (M_AB Xᵀ)ᵀ = X M_AB with X the D × nodes view of x.
  Eigen::Map<Eigen::Matrix<double, D, Eigen::Dynamic>>(y.data(), D, nodes).noalias() =
      Eigen::Map<const Eigen::Matrix<double, D, Eigen::Dynamic>>(x.data(), D, nodes) * mass_;
  return y;
}

template <int D>
Eigen::MatrixXd PersistentVelocity<D>::times_mass(const Eigen::MatrixXd& x) const {
  if (!nodal_) return mass_ * x;
  Eigen::MatrixXd y(x.rows(), x.cols());
  for (Eigen::Index k = 0; k < x.cols(); ++k) y.col(k) = times_mass(Eigen::VectorXd(x.col(k)));
  return y;
}

template <int D>
Eigen::VectorXd PersistentVelocity<D>::free_inverse_mass() const {
  Eigen::VectorXd inv_mass(lumped_.size());
  for (Eigen::Index d = 0; d < inv_mass.size(); ++d)
    inv_mass[d] = prescribed_[d] || !(lumped_[d] > 0.0) ? 0.0 : 1.0 / lumped_[d];
  return inv_mass;
}

template <int D>
Eigen::MatrixXd PersistentVelocity<D>::rigid_modes(const Positions<D>& x) const {
  constexpr int kRotations = D == 3 ? 3 : 1;
  const Eigen::Index n = x.cols();
  Eigen::MatrixXd R = Eigen::MatrixXd::Zero(D * n, D + kRotations);
  const Vec<D> c = x.rowwise().mean();
  for (Eigen::Index a = 0; a < n; ++a) {
    for (int i = 0; i < D; ++i) R(D * a + i, i) = 1.0;
    const Vec<D> r = x.col(a) - c;
    if constexpr (D == 3) {
      for (int k = 0; k < 3; ++k) R.block<3, 1>(3 * a, D + k) = Vec3::Unit(k).cross(r);
    } else {
      R(2 * a, D) = -r(1);
      R(2 * a + 1, D) = r(0);
    }
  }
  return R;
}

template <int D>
VelocityUpdate PersistentVelocity<D>::apply(const std::vector<Constraint<D>>& constraints,
                                            const std::vector<ContactPair<D>>& pairs, const Positions<D>& x,
                                            Eigen::VectorXd& v, std::vector<SlaveImpulse<D>>* impulses) const {
  VelocityUpdate out;
  if (impulses) impulses->assign(constraints.size(), {});
  if (constraints.empty()) return out;
  std::vector<std::pair<std::size_t, Vec<D>>> row_of;  // per row of A: its constraint and the slave's direction
  // The rows of A: frictionless one per slave (the gap rate), stick D
  // (the velocity of the slave relative to its point of the facet's frame).
  std::vector<Eigen::Triplet<double>> rows;
  int m = 0;
  for (const Constraint<D>& c : constraints) {
    if (std::any_of(c.master.begin(), c.master.end(), [&](int m) { return free_body_[static_cast<std::size_t>(m)]; }))
      continue;
    const ContactPair<D>& pair = pairs[c.pair];
    const FacetNodes<D> xm = facet_nodes<D>(pair.master, c.facet, x);
    auto add = [&](int row, const Vec<D>& dir, const FacetWeights<D>& N) {
      row_of.emplace_back(static_cast<std::size_t>(&c - constraints.data()), dir);
      if (impulses) (*impulses)[row_of.back().first].weights = N;
      for (int i = 0; i < D; ++i) {
        rows.emplace_back(row, c.slave * D + i, dir(i));
        for (int b = 0; b < c.master.size(); ++b) rows.emplace_back(row, c.master[b] * D + i, -N(b) * dir(i));
      }
    };
    if (c.kind == Kind::frictionless) {  // ġ = n·(v_s − Σ N_b v_b), any facet
      const Projection<D> end = project_on<D>(x.col(c.slave), pair.master, c.facet, x);
      add(m++, end.normal, facet_weights<D>(c.master.size(), end.xi));
    } else {
      // The rate of x_s − F(x_m), F(x_m) = N(ξ̄) x_m + γ n(x_m): its rows
      // (1, −∂F/∂x_m) have no moment where x_s = F(x_m) (F is frame-
      // indifferent), also with γ ≠ 0, where (1, −N_b 1) would have γ n × P.
      const zero_work::FacetJacobian<D, double> dF = zero_work::stick_jacobian<D, double>(xm, c.xi, c.gap);
      for (int i = 0; i < D; ++i) {
        const int row = m++;
        row_of.emplace_back(static_cast<std::size_t>(&c - constraints.data()), Vec<D>::Unit(i));
        if (impulses) (*impulses)[row_of.back().first].weights = facet_shape<D>(c.xi);
        rows.emplace_back(row, c.slave * D + i, 1.0);
        for (int b = 0; b < D; ++b)
          for (int j = 0; j < D; ++j) rows.emplace_back(row, c.master[b] * D + j, -dF(i, b * D + j));
      }
    }
  }
  if (m == 0) return out;  // every constraint on a free rigid body's facets
  const Eigen::Index ndof = v.size();
  SparseMatrix A(m, ndof);
  A.setFromTriplets(rows.begin(), rows.end());
  const Eigen::VectorXd r = A * v;
  out.removed = r.cwiseAbs().maxCoeff();
  if (!(out.removed > 0.0)) return out;

  // Both parts move the free dofs by M_L⁻¹ (Aᵀα + M R β): impulses on the
  // constraints' nodes, and a rigid-mode force field that sets the change
  // of L and J. With S = A M_L⁻¹ Aᵀ (sparse, factorized once here),
  // E = A M_L⁻¹ M R and G = Rᵀ M M_L⁻¹ M R, the 6 (2D: 3) β follow from a
  // small Schur complement.
  const Eigen::VectorXd inv_mass = free_inverse_mass();
  // The prescribed dofs (a rigid master) leave explicit zeros in B; kept,
  // they would couple every slave on a master node in S's pattern and make
  // its factorization dense (0.26 s a step for 340 stuck slaves).
  SparseMatrix B = A * inv_mass.cwiseSqrt().asDiagonal();
  B.prune([](Eigen::Index, Eigen::Index, double value) { return value != 0.0; });
  const SparseMatrix S = B * B.transpose();
  Eigen::SimplicialLDLT<SparseMatrix> ldlt(S);
  if (ldlt.info() != Eigen::Success) {
    out.failure = "the constraints' system is singular";
    return out;
  }
  const Eigen::MatrixXd R = rigid_modes(x);
  const Eigen::MatrixXd MR = times_mass(R);
  const Eigen::MatrixXd LMR = inv_mass.asDiagonal() * MR;  // M_L⁻¹ M R
  const Eigen::MatrixXd E = A * LMR;
  const Eigen::MatrixXd G = MR.transpose() * LMR;
  const Eigen::MatrixXd SE = ldlt.solve(E);
  auto move = [&](const Eigen::VectorXd& alpha, const Eigen::VectorXd& beta) -> Eigen::VectorXd {
    return inv_mass.asDiagonal() * (A.transpose() * alpha) + LMR * beta;
  };

  // 1. Persistency, A (V* + δ) = 0, with δ's change of L and J that of
  // the impulses on the free dofs alone, Rᵀ M δ = Rᵀ A_fᵀ μ (no resultant
  // and no moment for frictionless constraints between free bodies):
  //   S μ + E β = −r,   Fᵀ μ + G β = 0,   F = E − A_f R.
  const SparseMatrix A_free = A * Eigen::VectorXd((inv_mass.array() > 0.0).cast<double>()).asDiagonal();
  const Eigen::MatrixXd F = E - A_free * R;
  const Eigen::VectorXd Sr = ldlt.solve(r);
  const Eigen::MatrixXd schur1 = G - F.transpose() * SE;
  const Eigen::VectorXd beta1 = schur1.partialPivLu().solve(F.transpose() * Sr);
  const Eigen::VectorXd mu = -Sr - SE * beta1;
  const Eigen::VectorXd v_p = v + move(mu, beta1);

  // 2. Energy: w = V_p − M_L⁻¹(Aᵀα + M R β) with A w = 0 and Rᵀ M w = 0,
  //   S α + E β = A V_p,   Eᵀ α + G β = Rᵀ M V_p,
  // then V = V_p + t w with K(V) = K*.
  const Eigen::VectorXd Av_p = A * v_p;
  const Eigen::VectorXd L_p = MR.transpose() * v_p;
  const Eigen::MatrixXd schur2 = G - E.transpose() * SE;
  const Eigen::VectorXd beta2 = schur2.ldlt().solve(L_p - SE.transpose() * Av_p);
  const Eigen::VectorXd alpha = ldlt.solve(Av_p) - SE * beta2;
  const Eigen::VectorXd w = v_p - move(alpha, beta2);
  if (!v_p.allFinite() || !w.allFinite()) {
    out.failure = "its velocities are not finite";
    return out;
  }

  const Eigen::VectorXd Mv = times_mass(v), Mvp = times_mass(v_p), Mw = times_mass(w);
  const double K_star = 0.5 * v.dot(Mv), K_p = 0.5 * v_p.dot(Mvp);
  const double dK = K_star - K_p;
  const std::optional<double> t = energy_scale(w.dot(Mvp), w.dot(Mw), dK);  // K(V_p + t w) = K*
  if (!t) {
    out.failure = "the bodies' motion could not take back the energy";
    return out;
  }
  v = v_p + *t * w;
  out.applied = true;
  out.energy_moved = dK;
  if (impulses)
    for (std::size_t row = 0; row < row_of.size(); ++row)
      (*impulses)[row_of[row].first].impulse += mu[static_cast<Eigen::Index>(row)] * row_of[row].second;
  return out;
}

template <int D>
bool PersistentVelocity<D>::restore_energy(const Positions<D>& x, double energy, Eigen::VectorXd& v) const {
  if (energy == 0.0) return true;
  const Eigen::VectorXd inv_mass = free_inverse_mass();
  const Eigen::VectorXd v_free = (inv_mass.array() > 0.0).select(v, 0.0);
  // w = V_f − M_L⁻¹ M R β with Rᵀ M w = 0: G β = Rᵀ M V_f.
  const Eigen::MatrixXd R = rigid_modes(x);
  const Eigen::MatrixXd MR = times_mass(R);
  const Eigen::MatrixXd LMR = inv_mass.asDiagonal() * MR;
  const Eigen::MatrixXd G = MR.transpose() * LMR;
  const Eigen::VectorXd beta = G.ldlt().solve(MR.transpose() * v_free);
  const Eigen::VectorXd w = v_free - LMR * beta;
  if (!w.allFinite()) return false;
  const std::optional<double> t =
      energy_scale(w.dot(times_mass(v)), w.dot(times_mass(w)), -energy);  // K(V + t w) = K − W
  if (!t) return false;
  v += *t * w;
  return true;
}

template class PersistentVelocity<2>;
template class PersistentVelocity<3>;

}  // namespace conserve::contact
