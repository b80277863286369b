#pragma once
/// Free rigid bodies in the conserving step (docs/theory.md, "Free rigid
/// bodies"): a body's nodes move as x_A = c + R X̄_A (X̄ from its centre of
/// mass), its motion the unknowns q = (Δc, W) of the step, appended to the
/// Newton system. The rotation is updated by the Cayley map,
/// R_{n+1} = cay(W) R_n, so that the nodes' step is a rigid motion about
/// the mid-point configuration, Δx_A = Δc + W × r_A,n+½, and the body's
/// equations are the energy–momentum conserving mid-point rule of Simo &
/// Wong (1991, IJNME 31:19) in its Cayley (Lie–Poisson) form:
///   m (v_{n+1} − v_n) = Δt F,          Δc = Δt (v_n + v_{n+1}) / 2,
///   Π_{n+1} = cay(Ŵ_b)ᵀ (Π_n + Δt R_nᵀ M),   W_b = Δt I₀⁻¹ (Π_n + Π_{n+1}) / 2 = R_nᵀ W,
/// Π = Rᵀ π the convected angular momentum, F and M = Σ r_n+½ × f the
/// force and moment (about the mid-point centre) the body receives at its
/// nodes over the step. Then π_{n+1} − π_n = Δt M and
/// K_{n+1} − K_n = F·Δc + W·M, the work of the nodal forces over the nodes'
/// step: with zero-work contact forces, E, L and J are kept to round-off.
/// m, the centre and I₀ come from the model's mass matrix, so that the
/// nodes' kinetic energy and momenta are the body's.
/// The forces come from the system residual r on the body's (held) dofs:
/// f_A = −(r_A − the nodal inertia of the step at A).
#include <vector>

#include "assembly/assembler.hpp"
#include "model/state.hpp"

namespace conserve::time {

template <int D>
class FreeBodies {
 public:
  /// Rotational unknowns per body: 3 in 3D, 1 (about z) in 2D.
  static constexpr int kRotations = D == 3 ? 3 : 1;
  static constexpr int kUnknowns = D + kRotations;

  /// The model's free bodies with their mass properties from the
  /// assembler's mass matrix; the assembler must outlive it.
  explicit FreeBodies(const assembly::Assembler<D>& assembler);

  [[nodiscard]] bool empty() const { return bodies_.empty(); }
  /// Body b's mass [kg] and inertia I₀ about its centre in its reference
  /// orientation [kg m²].
  [[nodiscard]] double mass(std::size_t b) const { return bodies_[b].mass; }
  [[nodiscard]] const Mat3& inertia(std::size_t b) const { return bodies_[b].inertia; }
  /// Unknowns appended to the Newton system.
  [[nodiscard]] int unknowns() const { return kUnknowns * static_cast<int>(bodies_.size()); }

  /// Starts the step from `start` (its RigidBodyState per body, its u and
  /// V at the bodies' nodes) with Δt; gravity g for the predictor.
  void begin(const model::State& start, double dt);
  /// Newton's start: Δc = Δt v_n + ½Δt² g, W = Δt ω_n; the nodes placed in u.
  void predict(Eigen::VectorXd& u);
  /// The bodies' nodes placed in u at the present unknowns.
  void place(Eigen::VectorXd& u) const;

  /// The bodies' equations at the present unknowns, from the system's
  /// residual `r` (unmasked, the nodal ones first) and the iterate `u`,
  /// into `out` (unknowns() values).
  void residual(const Eigen::VectorXd& u, const Eigen::VectorXd& r, Eigen::VectorXd& out);
  /// The magnitudes of the terms the last residual() summed into each of
  /// the bodies' equations (ε times them bounds its round-off) [N].
  [[nodiscard]] const Eigen::VectorXd& magnitude() const { return magnitude_; }
  /// The tangent of the system with the bodies' unknowns appended: from
  /// the unmasked system tangent K (its held dofs' rows and columns are
  /// read) and the same matrix masked, `masked`, into A.
  void tangent(const SparseMatrix& K, const SparseMatrix& masked, SparseMatrix& A) const;
  /// The unknowns advanced by dq (unknowns() values); the bodies' nodes'
  /// change of position written into `increment` at their dofs (so that
  /// what follows the nodes, a constrained slave, moves with them).
  void update(const Eigen::VectorXd& dq, Eigen::VectorXd& increment);
  /// Keeps, then takes back, the unknowns (a line search's revert).
  void save() { saved_ = q_; }
  void restore() { q_ = saved_; }

  /// The step is taken: the end states into `state.rigid`, and the
  /// bodies' nodal velocities in v the rigid fields v + ω × r.
  void finish(std::vector<model::RigidBodyState>& rigid, Eigen::VectorXd& v) const;
  /// The initial nodal velocities of the bodies from `state.rigid`.
  void set_velocities(const model::State& state, Eigen::VectorXd& v) const;

 private:
  struct Body {
    int first_node = 0, num_nodes = 0;
    double mass = 0.0;
    /// Its radius of gyration √(tr I₀ / m) [m]: the rotational unknowns are
    /// L W (a length) and their equations the moments over L (forces), so
    /// that Newton's one tolerance on |r| weighs a moment's error by the
    /// work it can do over the body's size.
    double length = 1.0;
    Mat3 inertia = Mat3::Zero();  ///< I₀ about the centre, in the reference orientation [kg m²]
    Mat3 inverse = Mat3::Zero();  ///< I₀⁻¹ (2D: of its zz entry)
    std::vector<Vec3> arm;        ///< X̄_A = X_A − the reference centre
    /// M_AB over the body's nodes (local numbering), by columns.
    std::vector<std::vector<std::pair<int, double>>> mass_columns;
  };
  /// What a step starts from, per body.
  struct Start {
    model::RigidBodyState state;
    Vec3 momentum = Vec3::Zero();  ///< Π_n, convected [kg m²/s]
    std::vector<Vec3> x, velocity;  ///< the nodes' positions and velocities
  };
  /// The unknowns' consequences, per body.
  struct Motion {
    Mat3 cayley = Mat3::Identity();  ///< A = cay(Ŵ)
    Mat3 lever = Mat3::Identity();   ///< (I − Ŵ/2)⁻¹
    std::vector<Vec3> mid, end;      ///< r_n+½ and r_{n+1} per node
  };
  [[nodiscard]] Motion motion(std::size_t b) const;
  [[nodiscard]] Vec3 rotation_vector(std::size_t b) const;  ///< W (2D: along z)
  [[nodiscard]] Vec3 translation(std::size_t b) const;      ///< Δc (2D: z = 0)

  const assembly::Assembler<D>& assembler_;
  std::vector<Body> bodies_;
  std::vector<int> body_of_node_;  ///< per node: its free body, −1
  std::vector<Start> start_;
  double dt_ = 0.0;
  Eigen::VectorXd q_, saved_;
  Eigen::VectorXd magnitude_;
};

/// Cayley map cay(Ŵ) = (I − Ŵ/2)⁻¹ (I + Ŵ/2) of a rotation vector W.
Mat3 cayley(const Vec3& w);

}  // namespace conserve::time
