#pragma once
/// Global assembly: the only code that maps cells to global dofs. Vectors
/// are flat and node-major (dof A·D + i), displacements relative to the
/// model's reference coordinates. Loops over cells run on OpenMP threads
/// (assembly/threads.hpp) and give the same bits for any number of them:
/// each global entry sums its cells' terms in ascending cell order, in the
/// part of the nodes that owns it (assembly/partition.hpp), and sums and
/// minima over cells go in cell order. An Assembler serves one caller at a
/// time: its loops keep per-part buffers between calls.
#include <functional>
#include <memory>
#include <utility>
#include <vector>

#include "assembly/block_pattern.hpp"
#include "assembly/partition.hpp"
#include "fem/element.hpp"
#include "model/model.hpp"

namespace conserve::assembly {

/// The most compressed cell of a configuration.
struct Orientation {
  double det_F = 0.0;  ///< smallest det F over the cells (≤ 0: inverted)
  int cell = -1;       ///< global cell (model::Model::global_cell), −1 if there are no cells
};

/// How the ranks of a run share the assembly's work (solver/ranks.hpp):
/// each rank (Model::rank, of Model::rank_nodes) computes the force
/// entries of its own nodes and the tangent's rows of them, which are all
/// it holds of the tangent (BlockPattern's kept rows). `gather` gives every
/// rank the others' force entries: gather(data, counts) replaces each
/// rank's segment of `data` (counts[r] values, in rank order) by that
/// rank's; `all` gives every rank's value of a figure in rank order. The
/// entries are the bits one process computes (each sums its cells in
/// ascending order, assembly/partition.hpp); sums and minima over the
/// cells are summed rank by rank.
struct RankShare {
  std::function<void(double* data, const std::vector<int>& counts)> gather;
  std::function<std::vector<double>(double value)> all;
};

template <int D>
class Assembler {
 public:
  /// Builds the pattern (the rows of this rank's nodes, Model::rank_nodes)
  /// and the constant mass matrix (consistent or lumped).
  Assembler(const model::Model<D>& model, bool lumped_mass);

  [[nodiscard]] const model::Model<D>& model() const { return model_; }
  [[nodiscard]] const BlockPattern<D>& pattern() const { return pattern_; }
  /// Which part adds into which nodes' entries, for the present number of
  /// threads (one part below kMinParallelCells cells); remade when that
  /// number changes.
  [[nodiscard]] const NodePartition& partition() const;
  /// The ranks' exchanges for a model of several ranks (Model::rank_nodes):
  /// needed before the first force or measure on more than one rank.
  void share(RankShare share);
  /// The model now holds the pattern's kept cells alone
  /// (model::keep_cells(model, pattern().kept_cell_ids())): the cells'
  /// numbering changes to theirs.
  void cells_kept();
  /// This rank's nodes [first, end) (all nodes on one rank).
  [[nodiscard]] std::pair<int, int> rank_nodes() const { return {model_.first_owned(), model_.end_owned()}; }
  /// The nodes' scalar mass matrix M_AB [kg], nodes × nodes: the dofs'
  /// mass matrix is M_AB ⊗ I_D, which is not stored.
  [[nodiscard]] const SparseMatrix& node_mass() const { return node_mass_; }
  /// M x for a node-major vector x: M_AB applied to each of the D components.
  [[nodiscard]] Eigen::VectorXd mass_times(const Eigen::VectorXd& x) const;
  /// K += c M for K with the pattern's layout.
  void add_mass(double c, SparseMatrix& K) const;
  /// The mean of the diagonal of the dofs' mass matrix [kg] (model::mean_dof_mass).
  [[nodiscard]] double mean_dof_mass() const { return mean_dof_mass_; }
  /// Constant external force from gravity, f_A = Σ_B M_AB g [N].
  [[nodiscard]] const Eigen::VectorXd& gravity_force() const { return gravity_force_; }

  /// Each cell's F_n at the start u_n of a step: what every
  /// residual and tangent of the step shares, for the cells with a corner
  /// among this rank's nodes (all on one rank), in cell order: cell c's is
  /// at pattern().local_cell(c) (a quadratic cell's points' at
  /// points_per_cell() × that, one per point).
  using StepStart = std::vector<fem::CellStart<D>>;
  [[nodiscard]] StepStart step_start(const Eigen::VectorXd& u_n) const;
  /// The point starts a cell keeps: 1 (linear) or its rule's points.
  [[nodiscard]] int points_per_cell() const;

  /// Internal force of the step u_n → u_{n+1} [N]; with `magnitude`, also
  /// Σ_cells |f_cell| per dof (what the sum cancelled, for round-off bounds).
  void internal_force(const StepStart& start, const Eigen::VectorXd& u_np1, fem::StressScheme scheme,
                      Eigen::VectorXd& f, Eigen::VectorXd* magnitude = nullptr) const;
  /// Adds the internal force to f (and Σ_cells |f_cell| to `magnitude`):
  /// what internal_force() computes into zeroed vectors.
  void add_internal_force(const StepStart& start, const Eigen::VectorXd& u_np1, fem::StressScheme scheme,
                          Eigen::VectorXd& f, Eigen::VectorXd* magnitude = nullptr) const;
  /// The same from u_n (step_start(u_n) made for this call): the same bits.
  void internal_force(const Eigen::VectorXd& u_n, const Eigen::VectorXd& u_np1, fem::StressScheme scheme,
                      Eigen::VectorXd& f, Eigen::VectorXd* magnitude = nullptr) const;

  /// Per dof, Σ_cells V (λ + 2μ) |∇N_A| [N]: the internal force of a unit
  /// strain. The strain E = ½(FᵀF − 1) of a nearly rigid cell is computed
  /// with an absolute error of round-off ε, so ε times this bounds the
  /// round-off of the internal force however small the strains.
  [[nodiscard]] const Eigen::VectorXd& stiffness_scale() const { return stiffness_scale_; }
  /// Per dof, Σ_cells V (λ + 2μ) |∇N_A|² [N/m]: the internal force of a
  /// unit displacement of the node. A displacement u is stored to ε|u|
  /// (each Newton update rounds it there), which moves F by ε|u| |∇N|:
  /// ε|u| times this bounds that part of the round-off, which grows with
  /// how far a stiff body has travelled.
  [[nodiscard]] const Eigen::VectorXd& displacement_stiffness() const { return displacement_stiffness_; }

  /// Internal force and K = ∂f/∂u_{n+1}; K must have the pattern's layout.
  void internal_force_tangent(const StepStart& start, const Eigen::VectorXd& u_np1, fem::StressScheme scheme,
                              Eigen::VectorXd& f, SparseMatrix& K) const;
  void internal_force_tangent(const Eigen::VectorXd& u_n, const Eigen::VectorXd& u_np1, fem::StressScheme scheme,
                              Eigen::VectorXd& f, SparseMatrix& K) const;
  /// Adds ∂f/∂u_{n+1} to K (the pattern's layout) and nothing else.
  void add_internal_force_derivative(const StepStart& start, const Eigen::VectorXd& u_np1, fem::StressScheme scheme,
                                     SparseMatrix& K) const;
  /// add_internal_force() and add_internal_force_derivative() in one pass
  /// over the cells (each cell's state computed once): the same bits as the
  /// two calls.
  void add_internal_force_and_derivative(const StepStart& start, const Eigen::VectorXd& u_np1, fem::StressScheme scheme,
                                         Eigen::VectorXd& f, Eigen::VectorXd& magnitude, SparseMatrix& K) const;

  /// What a run needs of a state u besides its steps' residuals, from one
  /// pass over the cells: the same bits as step_start(u), strain_energy(u),
  /// min_det_F(u) and |internal_force(step_start(u), u, conserving)|, the
  /// force of a step that does not move (on several ranks collective: each
  /// rank measures its cells, step_start's of the cells it visits, and the
  /// energy is summed rank by rank). The last state's are kept: asked
  /// again for the same u (bit for bit), they are not computed again (a
  /// step's end is checked, reported and starts the next step).
  struct StateMeasures {
    std::shared_ptr<const StepStart> cells;  ///< each cell's F and E at u
    double strain_energy = 0.0;              ///< W(u) [J]
    Orientation orientation;                 ///< the smallest det F at u
    double force_norm = 0.0;                 ///< |f(u)| [N]
  };
  [[nodiscard]] const StateMeasures& measures(const Eigen::VectorXd& u) const;

  /// The smallest det F over the cells at displacements u, and its cell
  /// (the lowest such cell on ties): every cell the model holds.
  [[nodiscard]] Orientation min_det_F(const Eigen::VectorXd& u) const;

  /// Stored energy W(u) = Σ_cells V ρ0Ψ [J] of every cell the model holds.
  [[nodiscard]] double strain_energy(const Eigen::VectorXd& u) const;

  /// Current positions of a cell's nodes relative to its first node,
  /// x_A − x_0 = (X_A − X_0) + (u_A − u_0): a translation of the positions,
  /// which the kernels (F, E, S, W, σ) do not see. Formed from differences,
  /// they carry the round-off ε|x_A − x_0| of an edge, not ε|x| of where the
  /// body lies: F = Σ x_A ⊗ ∇N_A from absolute positions errs by ε|x|/h,
  /// which on a stiff body far from the origin puts the Newton residual
  /// (K ε|x|) above any tolerance. Linear cells (positions<N> for others).
  [[nodiscard]] fem::NodeMatrix<D> cell_positions(int cell, const Eigen::VectorXd& u) const;
  /// cell_positions() of a cell of N nodes (N = D+1 or fem::Quadratic<D>::kNodes).
  template <int N>
  [[nodiscard]] Eigen::Matrix<double, D, N> positions(int cell, const Eigen::VectorXd& u) const;

 private:
  [[nodiscard]] const material::Law& law(int cell) const { return *model_.bodies[model_.cell_body[cell]].law; }
  [[nodiscard]] bool mean_dilatation(int cell) const { return model_.bodies[model_.cell_body[cell]].mean_dilatation; }
  /// body(std::integral_constant<int, order>) for the model's cell order.
  template <class Body>
  void by_order(const Body& body) const;
  /// K += ∂f/∂u_{n+1} and, if given, f += the internal force (and
  /// magnitude += Σ_cells |f_cell|, if given too).
  void add_tangent(const StepStart& start, const Eigen::VectorXd& u_np1, fem::StressScheme scheme, Eigen::VectorXd* f,
                   Eigen::VectorXd* magnitude, SparseMatrix& K) const;
  const model::Model<D>& model_;
  BlockPattern<D> pattern_;
  /// A part's sums before they go into the result, kept between calls so
  /// that each stays in the cache of the core that fills it.
  struct Scratch {
    Eigen::VectorXd force, magnitude;
  };
  /// The parts of this rank's nodes (partition() on one rank).
  [[nodiscard]] const NodePartition& rank_partition() const;
  /// Every rank's segments of f and magnitude (may be null) from that rank
  /// (nothing on one rank).
  void gather(Eigen::VectorXd* f, Eigen::VectorXd* magnitude) const;
  /// The ranks' values of a figure, in rank order (this rank's alone on one).
  [[nodiscard]] std::vector<double> all(double value) const;
  RankShare share_;
  mutable NodePartition rank_partition_;
  mutable NodePartition partition_;
  mutable StateMeasures measures_;  ///< measures() of measured_u_
  mutable Eigen::VectorXd measured_u_;
  mutable std::vector<Scratch> scratch_;
  SparseMatrix node_mass_;  ///< M_AB, nodes × nodes
  double mean_dof_mass_ = 0.0;
  Eigen::VectorXd gravity_force_;
  Eigen::VectorXd stiffness_scale_;
  Eigen::VectorXd displacement_stiffness_;
};

}  // namespace conserve::assembly
