#include "time/free_bodies.hpp"

#include <Eigen/LU>
#include <Eigen/SVD>
#include <cmath>

#include "model/initial_state.hpp"

namespace conserve::time {

namespace {

Mat3 skew(const Vec3& w) {
  Mat3 s;
  s << 0.0, -w.z(), w.y(), w.z(), 0.0, -w.x(), -w.y(), w.x(), 0.0;
  return s;
}

/// A D-vector as a 3-vector (z = 0 in 2D).
template <int D>
Vec3 lift(const Vec<D>& v) {
  Vec3 out = Vec3::Zero();
  out.head<D>() = v;
  return out;
}

}  // namespace

Mat3 cayley(const Vec3& w) {
  const Mat3 half = 0.5 * skew(w);
  return (Mat3::Identity() - half).inverse() * (Mat3::Identity() + half);
}

template <int D>
FreeBodies<D>::FreeBodies(const assembly::Assembler<D>& assembler)
    : assembler_(assembler), body_of_node_(static_cast<std::size_t>(assembler.model().num_nodes()), -1) {
  const auto& model = assembler.model();
  const SparseMatrix& M = assembler.node_mass();
  for (std::size_t b = 0; b < model.free_bodies.size(); ++b) {
    const model::FreeBody& fb = model.free_bodies[b];
    Body body;
    body.first_node = fb.first_node;
    body.num_nodes = fb.num_nodes;
    const Vec3 centre = lift<D>(model::body_centroid<D>(model, fb.body, Eigen::VectorXd::Zero(model.num_dofs())));
    for (int n = 0; n < fb.num_nodes; ++n) {
      body_of_node_[static_cast<std::size_t>(fb.first_node + n)] = static_cast<int>(b);
      body.arm.push_back(lift<D>(model.X.col(fb.first_node + n)) - centre);
    }
    body.mass_columns.resize(static_cast<std::size_t>(fb.num_nodes));
    for (int n = 0; n < fb.num_nodes; ++n) {
      for (SparseMatrix::InnerIterator it(M, fb.first_node + n); it; ++it) {
        const int a = static_cast<int>(it.row()) - fb.first_node;
        if (a < 0 || a >= fb.num_nodes) continue;
        body.mass_columns[static_cast<std::size_t>(n)].emplace_back(a, it.value());
        const Vec3& ra = body.arm[static_cast<std::size_t>(a)];
        const Vec3& rb = body.arm[static_cast<std::size_t>(n)];
        body.mass += it.value();
        body.inertia += it.value() * (ra.dot(rb) * Mat3::Identity() - 0.5 * (ra * rb.transpose() + rb * ra.transpose()));
      }
    }
    if constexpr (D == 3) {
      body.inverse = body.inertia.inverse();
    } else {
      body.inverse(2, 2) = 1.0 / body.inertia(2, 2);
    }
    body.length = std::sqrt(body.inertia.trace() / body.mass);
    bodies_.push_back(std::move(body));
  }
  q_ = saved_ = Eigen::VectorXd::Zero(unknowns());
}

template <int D>
void FreeBodies<D>::begin(const model::State& start, double dt) {
  dt_ = dt;
  start_.assign(bodies_.size(), {});
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    const Body& body = bodies_[b];
    Start& s = start_[b];
    s.state = start.rigid.at(b);
    s.momentum = body.inertia * (s.state.rotation.transpose() * s.state.spin);
    if constexpr (D == 2) s.momentum.template head<2>().setZero();
    for (int n = 0; n < body.num_nodes; ++n) {
      const int node = body.first_node + n;
      s.x.push_back(s.state.center + s.state.rotation * body.arm[static_cast<std::size_t>(n)]);
      s.velocity.push_back(lift<D>(start.v.template segment<D>(node * D)));
    }
  }
  q_.setZero(unknowns());
}

template <int D>
Vec3 FreeBodies<D>::translation(std::size_t b) const {
  return lift<D>(q_.template segment<D>(static_cast<Eigen::Index>(b) * kUnknowns));
}

template <int D>
Vec3 FreeBodies<D>::rotation_vector(std::size_t b) const {
  const Eigen::Index at = static_cast<Eigen::Index>(b) * kUnknowns + D;
  const double length = bodies_[b].length;
  if constexpr (D == 3) return q_.template segment<3>(at) / length;
  return Vec3(0.0, 0.0, q_[at] / length);
}

template <int D>
typename FreeBodies<D>::Motion FreeBodies<D>::motion(std::size_t b) const {
  const Vec3 w = rotation_vector(b);
  Motion m;
  const Mat3 half = 0.5 * skew(w);
  m.lever = (Mat3::Identity() - half).inverse();
  m.cayley = m.lever * (Mat3::Identity() + half);
  const Body& body = bodies_[b];
  for (int n = 0; n < body.num_nodes; ++n) {
    const Vec3 r_n = start_[b].state.rotation * body.arm[static_cast<std::size_t>(n)];
    m.end.push_back(m.cayley * r_n);
    m.mid.push_back(0.5 * (r_n + m.end.back()));
  }
  return m;
}

template <int D>
void FreeBodies<D>::predict(Eigen::VectorXd& u) {
  const Vec3 g = lift<D>(assembler_.model().gravity);
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    const model::RigidBodyState& s = start_[b].state;
    const Vec3 dc = dt_ * s.velocity + 0.5 * dt_ * dt_ * g;
    const Vec3 w = dt_ * bodies_[b].length * s.spin;  // the unknowns are L W
    const Eigen::Index at = static_cast<Eigen::Index>(b) * kUnknowns;
    q_.template segment<D>(at) = dc.head<D>();
    if constexpr (D == 3) {
      q_.template segment<3>(at + D) = w;
    } else {
      q_[at + D] = w.z();
    }
  }
  place(u);
}

template <int D>
void FreeBodies<D>::place(Eigen::VectorXd& u) const {
  const auto& X = assembler_.model().X;
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    const Motion m = motion(b);
    const Vec3 c = start_[b].state.center + translation(b);
    for (int n = 0; n < bodies_[b].num_nodes; ++n) {
      const int node = bodies_[b].first_node + n;
      u.template segment<D>(node * D) = (c + m.end[static_cast<std::size_t>(n)]).template head<D>() - X.col(node);
    }
  }
}

template <int D>
void FreeBodies<D>::residual(const Eigen::VectorXd&, const Eigen::VectorXd& r, Eigen::VectorXd& out) {
  out.setZero(unknowns());
  magnitude_.setZero(unknowns());
  const double c2 = 2.0 / (dt_ * dt_), c1 = 2.0 / dt_;
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    const Body& body = bodies_[b];
    const Start& s = start_[b];
    const Motion m = motion(b);
    const Vec3 dc = translation(b), w = rotation_vector(b);
    // The nodal inertia of the step at each node, (2/Δt²) M Δx − (2/Δt) M V_n,
    // taken out of the system's residual: h_A = −f_A.
    Vec3 force = Vec3::Zero(), moment = Vec3::Zero(), force_size = Vec3::Zero(), moment_size = Vec3::Zero();
    std::vector<Vec3> inertia(static_cast<std::size_t>(body.num_nodes), Vec3::Zero());
    for (int n = 0; n < body.num_nodes; ++n) {
      const Vec3 dx = dc + m.end[static_cast<std::size_t>(n)] - s.state.rotation * body.arm[static_cast<std::size_t>(n)];
      for (const auto& [a, mass] : body.mass_columns[static_cast<std::size_t>(n)])
        inertia[static_cast<std::size_t>(a)] += mass * (c2 * dx - c1 * s.velocity[static_cast<std::size_t>(n)]);
    }
    for (int a = 0; a < body.num_nodes; ++a) {
      const int node = body.first_node + a;
      const Vec3 h = lift<D>(r.template segment<D>(node * D)) - inertia[static_cast<std::size_t>(a)];
      force += h;
      moment += m.mid[static_cast<std::size_t>(a)].cross(h);
      force_size += h.cwiseAbs() + inertia[static_cast<std::size_t>(a)].cwiseAbs();
      moment_size += m.mid[static_cast<std::size_t>(a)].norm() * Vec3::Constant(force_size.norm());
    }
    const Vec3 translational = body.mass * c2 * (dc - dt_ * s.state.velocity) + force;
    const Vec3 omega_mid = s.state.rotation.transpose() * w / dt_;
    const Vec3 y = s.state.rotation * (2.0 * body.inertia * omega_mid - s.momentum);
    const Vec3 rotational = ((m.cayley * y - s.state.rotation * s.momentum) / dt_ + moment) / body.length;
    const Eigen::Index at = static_cast<Eigen::Index>(b) * kUnknowns;
    out.template segment<D>(at) = translational.head<D>();
    const Vec3 translation_size =
        force_size + body.mass * c2 * (dc.cwiseAbs() + dt_ * s.state.velocity.cwiseAbs());
    const Vec3 rotation_size =
        (moment_size + Vec3::Constant((y.norm() + s.momentum.norm()) / dt_)) / body.length;
    magnitude_.template segment<D>(at) = translation_size.head<D>();
    if constexpr (D == 3) {
      out.template segment<3>(at + D) = rotational;
      magnitude_.template segment<3>(at + D) = rotation_size;
    } else {
      out[at + D] = rotational.z();
      magnitude_[at + D] = rotation_size.z();
    }
  }
}

template <int D>
void FreeBodies<D>::tangent(const SparseMatrix& K, const SparseMatrix& masked, SparseMatrix& A) const {
  const auto n = static_cast<int>(K.rows());
  const int nodal = assembler_.model().num_dofs();
  const int nq = unknowns();
  const double c2 = 2.0 / (dt_ * dt_);
  // Per body and node: T_A = ∂x_A/∂q (D × kUnknowns) and R_A, the test of
  // the body's equations (kUnknowns × D): translation 1, rotation r_n+½ ×.
  std::vector<std::vector<Eigen::Matrix<double, D, kUnknowns>>> trial(bodies_.size());
  std::vector<std::vector<Eigen::Matrix<double, kUnknowns, D>>> test(bodies_.size());
  std::vector<Motion> motions;
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    motions.push_back(motion(b));
    const Motion& m = motions.back();
    for (int a = 0; a < bodies_[b].num_nodes; ++a) {
      const Vec3& mid = m.mid[static_cast<std::size_t>(a)];
      const Mat3 turn = -m.lever * skew(mid);  // ∂(cay(Ŵ) r_n)/∂W
      Eigen::Matrix<double, D, kUnknowns> t = Eigen::Matrix<double, D, kUnknowns>::Zero();
      Eigen::Matrix<double, kUnknowns, D> r = Eigen::Matrix<double, kUnknowns, D>::Zero();
      t.template leftCols<D>().setIdentity();
      r.template topRows<D>().setIdentity();
      if constexpr (D == 3) {
        t.template rightCols<3>() = turn;
        r.template bottomRows<3>() = skew(mid);
      } else {
        t.col(D) = turn.col(2).head<2>();
        r.row(D) = skew(mid).row(2).head<2>();
      }
      t.template rightCols<kRotations>() /= bodies_[b].length;  // ∂x/∂(L W)
      r.template bottomRows<kRotations>() /= bodies_[b].length;  // the moments over L
      trial[b].push_back(t);
      test[b].push_back(r);
    }
  }
  const auto locate = [&](int dof, int& body, int& local, int& component) {
    body = -1;
    if (dof >= nodal) return;
    const int node = dof / D;
    body = body_of_node_[static_cast<std::size_t>(node)];
    if (body < 0) return;
    local = node - bodies_[static_cast<std::size_t>(body)].first_node;
    component = dof % D;
  };
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(static_cast<std::size_t>(masked.nonZeros()) + static_cast<std::size_t>(nq) * 64);
  for (int col = 0; col < masked.outerSize(); ++col)
    for (SparseMatrix::InnerIterator it(masked, col); it; ++it) t.emplace_back(it.row(), col, it.value());
  Eigen::MatrixXd qq = Eigen::MatrixXd::Zero(nq, nq);
  for (int col = 0; col < K.outerSize(); ++col) {
    int bj = -1, lj = 0, cj = 0;
    locate(col, bj, lj, cj);
    for (SparseMatrix::InnerIterator it(K, col); it; ++it) {
      const int row = static_cast<int>(it.row());
      int bi = -1, li = 0, ci = 0;
      locate(row, bi, li, ci);
      if (bi < 0 && bj < 0) continue;
      const double k = it.value();
      if (bi < 0) {  // a free row, a body's column: K_fq = K_fp T
        const auto& tj = trial[static_cast<std::size_t>(bj)][static_cast<std::size_t>(lj)];
        for (int s = 0; s < kUnknowns; ++s) t.emplace_back(row, n + bj * kUnknowns + s, k * tj(cj, s));
      } else if (bj < 0) {  // a body's row, a free column: K_qf = R K_pf
        const auto& ri = test[static_cast<std::size_t>(bi)][static_cast<std::size_t>(li)];
        for (int s = 0; s < kUnknowns; ++s) t.emplace_back(n + bi * kUnknowns + s, col, ri(s, ci) * k);
      } else {
        const auto& ri = test[static_cast<std::size_t>(bi)][static_cast<std::size_t>(li)];
        const auto& tj = trial[static_cast<std::size_t>(bj)][static_cast<std::size_t>(lj)];
        qq.block<kUnknowns, kUnknowns>(bi * kUnknowns, bj * kUnknowns) += ri.col(ci) * k * tj.row(cj);
      }
    }
  }
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    const Body& body = bodies_[b];
    const Start& s = start_[b];
    const Motion& m = motions[b];
    auto block = qq.block<kUnknowns, kUnknowns>(static_cast<Eigen::Index>(b) * kUnknowns,
                                                static_cast<Eigen::Index>(b) * kUnknowns);
    // The nodal inertia is not the body's: its part of K_pp out (from the
    // rows this rank holds), the body's in (by the rank of the body's rows).
    for (int bn = 0; bn < body.num_nodes; ++bn)
      for (const auto& [a, mass] : body.mass_columns[static_cast<std::size_t>(bn)])
        if (assembler_.model().owns(body.first_node + a))
          block -= test[b][static_cast<std::size_t>(a)] * (c2 * mass) * trial[b][static_cast<std::size_t>(bn)];
    if (!assembler_.model().owns_extra_rows()) continue;
    block.template topLeftCorner<D, D>() += body.mass * c2 * Eigen::Matrix<double, D, D>::Identity();
    // ∂/∂W of (cay(Ŵ) y(W) − π_n)/Δt, y = R_n (2 I₀ R_nᵀ W/Δt − Π_n), and of
    // Σ r_n+½ × h through r_n+½ (h, the nodal forces, held).
    const Vec3 w = rotation_vector(b);
    const Vec3 y = s.state.rotation * (2.0 * body.inertia * (s.state.rotation.transpose() * w / dt_) - s.momentum);
    Mat3 rot = (-m.lever * skew(0.5 * (y + m.cayley * y)) +
                m.cayley * s.state.rotation * (2.0 / dt_) * body.inertia * s.state.rotation.transpose()) /
               dt_;
    const double scale = 1.0 / (body.length * body.length);  // (1/L) ∂/∂(L W)
    if constexpr (D == 3) {
      block.template bottomRightCorner<3, 3>() += scale * rot;
    } else {
      block(D, D) += scale * rot(2, 2);
    }
  }
  for (int i = 0; i < nq; ++i)
    for (int j = 0; j < nq; ++j) t.emplace_back(n + i, n + j, qq(i, j));
  A.resize(n + nq, n + nq);
  A.setFromTriplets(t.begin(), t.end());
}

template <int D>
void FreeBodies<D>::update(const Eigen::VectorXd& dq, Eigen::VectorXd& increment) {
  Eigen::VectorXd before = Eigen::VectorXd::Zero(assembler_.model().num_dofs()), after = before;
  place(before);
  q_ += dq;
  place(after);
  for (const Body& body : bodies_)
    for (int d = body.first_node * D; d < (body.first_node + body.num_nodes) * D; ++d)
      increment[d] = after[d] - before[d];
}

template <int D>
void FreeBodies<D>::finish(std::vector<model::RigidBodyState>& rigid, Eigen::VectorXd& v) const {
  rigid.resize(bodies_.size());
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    const Body& body = bodies_[b];
    const Start& s = start_[b];
    const Motion m = motion(b);
    const Vec3 dc = translation(b), w = rotation_vector(b);
    model::RigidBodyState& e = rigid[b];
    e.center = s.state.center + dc;
    e.velocity = (2.0 / dt_) * dc - s.state.velocity;
    e.rotation = m.cayley * s.state.rotation;
    // Orthogonal to round-off: the products of Cayley maps would drift from it.
    const Eigen::JacobiSVD<Mat3> svd(e.rotation, Eigen::ComputeFullU | Eigen::ComputeFullV);
    e.rotation = svd.matrixU() * svd.matrixV().transpose();
    Vec3 momentum = 2.0 * body.inertia * (s.state.rotation.transpose() * w / dt_) - s.momentum;  // Π_{n+1}
    if constexpr (D == 2) momentum.template head<2>().setZero();
    e.spin = e.rotation * (body.inverse * momentum);
    for (int n = 0; n < body.num_nodes; ++n) {
      const int node = body.first_node + n;
      v.template segment<D>(node * D) = (e.velocity + e.spin.cross(m.end[static_cast<std::size_t>(n)])).template head<D>();
    }
  }
}

template <int D>
void FreeBodies<D>::set_velocities(const model::State& state, Eigen::VectorXd& v) const {
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    const Body& body = bodies_[b];
    const model::RigidBodyState& s = state.rigid.at(b);
    for (int n = 0; n < body.num_nodes; ++n) {
      const int node = body.first_node + n;
      const Vec3 r = s.rotation * body.arm[static_cast<std::size_t>(n)];
      v.template segment<D>(node * D) = (s.velocity + s.spin.cross(r)).template head<D>();
    }
  }
}

template class FreeBodies<2>;
template class FreeBodies<3>;

}  // namespace conserve::time
