#include "assembly/assembler.hpp"

#include <algorithm>
#include <array>
#include <type_traits>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "assembly/threads.hpp"

namespace conserve::assembly {
namespace {

/// Calls part(p) for every part of the partition, each on its own thread
/// (part p on thread p, so that a part's buffers stay in one core's cache).
template <class Part>
void for_each_part(const NodePartition& partition, const Part& part) {
  const int parts = partition.num_parts();
#pragma omp parallel for schedule(static, 1) num_threads(parts) if (parts > 1)
  for (int p = 0; p < parts; ++p) part(p);
}

/// value(cell) for every cell, computed in parallel.
template <class Value>
std::vector<double> per_cell(int num_cells, const Value& value) {
  std::vector<double> v(num_cells);
#pragma omp parallel for schedule(dynamic, 256) if (num_cells >= kMinParallelCells)
  for (int c = 0; c < num_cells; ++c) v[c] = value(c);
  return v;
}

/// What the loops need of a cell of order P: its kernels (fem/element.hpp)
/// and the number of point starts (fem::CellStart) it keeps.
template <int D, int P>
struct Kind;

template <int D>
struct Kind<D, 1> {
  static constexpr int kNodes = D + 1, kPoints = 1;
  using Nodes = fem::NodeMatrix<D>;
  using Matrix = fem::ElementMatrix<D>;
  static const fem::SimplexGeometry<D>& geometry(const model::Model<D>& m, int c) { return m.geometry[c]; }
  static void start(const fem::SimplexGeometry<D>& g, const Nodes& x, fem::CellStart<D>* s) {
    *s = fem::cell_start<D>(g, x);
  }
  static Nodes force(const fem::SimplexGeometry<D>& g, const material::Law& law, const fem::CellStart<D>* s,
                     const Nodes& x, fem::StressScheme scheme, bool /*mean: order 2 only*/) {
    return fem::internal_force<D>(g, law, *s, x, scheme);
  }
  static void force_tangent(const fem::SimplexGeometry<D>& g, const material::Law& law, const fem::CellStart<D>* s,
                            const Nodes& x, fem::StressScheme scheme, bool /*mean*/, Nodes& f, Matrix& K) {
    fem::internal_force_tangent<D>(g, law, *s, x, scheme, f, K);
  }
  static double energy(const fem::SimplexGeometry<D>& g, const material::Law& law, const Nodes& x, bool /*mean*/) {
    return fem::strain_energy<D>(g, law, x);
  }
  static double min_det(const fem::CellStart<D>* s) { return s->F.determinant(); }
};

template <int D>
struct Kind<D, 2> {
  static constexpr int kNodes = fem::Quadratic<D>::kNodes, kPoints = fem::Quadratic<D>::kPoints;
  using Nodes = fem::QuadraticNodes<D>;
  using Matrix = fem::QuadraticMatrix<D>;
  static const fem::QuadraticGeometry<D>& geometry(const model::Model<D>& m, int c) { return m.quadratic[c]; }
  static void start(const fem::QuadraticGeometry<D>& g, const Nodes& x, fem::CellStart<D>* s) {
    fem::cell_start<D>(g, x, s);
  }
  /// `mean`: the body's cells take the cell's mean dilatation (model::Body).
  static Nodes force(const fem::QuadraticGeometry<D>& g, const material::Law& law, const fem::CellStart<D>* s,
                     const Nodes& x, fem::StressScheme scheme, bool mean) {
    return mean ? fem::internal_force_mean_dilatation<D>(g, law, s, x, scheme)
                : fem::internal_force<D>(g, law, s, x, scheme);
  }
  static void force_tangent(const fem::QuadraticGeometry<D>& g, const material::Law& law, const fem::CellStart<D>* s,
                            const Nodes& x, fem::StressScheme scheme, bool mean, Nodes& f, Matrix& K) {
    if (mean)
      fem::internal_force_tangent_mean_dilatation<D>(g, law, s, x, scheme, f, K);
    else
      fem::internal_force_tangent<D>(g, law, s, x, scheme, f, K);
  }
  static double energy(const fem::QuadraticGeometry<D>& g, const material::Law& law, const Nodes& x, bool mean) {
    return mean ? fem::strain_energy_mean_dilatation<D>(g, law, x) : fem::strain_energy<D>(g, law, x);
  }
  static double min_det(const fem::CellStart<D>* s) {
    double lowest = s[0].F.determinant();
    for (int q = 1; q < kPoints; ++q) lowest = std::min(lowest, s[q].F.determinant());
    return lowest;
  }
};

}  // namespace

template <int D>
template <class Body>
void Assembler<D>::by_order(const Body& body) const {
  if (model_.order == 1)
    body(std::integral_constant<int, 1>{});
  else
    body(std::integral_constant<int, 2>{});
}

template <int D>
int Assembler<D>::points_per_cell() const {
  return model_.order == 1 ? 1 : fem::Quadratic<D>::kPoints;
}

template <int D>
Assembler<D>::Assembler(const model::Model<D>& model, bool lumped_mass)
    : model_(model), pattern_(model.num_nodes(), model.cells, {}, model.first_owned(), model.end_owned()) {
  std::vector<Eigen::Triplet<double>> node_entries;
  const auto nodes = static_cast<int>(model.cells.rows());
  node_entries.reserve(static_cast<std::size_t>(model.num_cells()) * nodes * nodes);
  for (int c = 0; c < model.num_cells(); ++c) {
    const model::Body& body = model.bodies[model.cell_body[c]];
    const auto add = [&](const auto& Me) {
      for (int b = 0; b < nodes; ++b)
        for (int a = 0; a < nodes; ++a)
          if (Me(a, b) != 0.0) node_entries.emplace_back(model.cells(a, c), model.cells(b, c), Me(a, b));
    };
    if (model.order == 1) {
      add(fem::element_mass<D>(body.density, model.geometry[c].volume, lumped_mass));
    } else {
      fem::QuadraticNodes<D> X;
      for (int a = 0; a < nodes; ++a) X.col(a) = model.X.col(model.cells(a, c));
      add(fem::quadratic_mass<D>(X, body.density * body.thickness, lumped_mass));
    }
  }
  node_mass_.resize(model.num_nodes(), model.num_nodes());
  node_mass_.setFromTriplets(node_entries.begin(), node_entries.end());  // sums in cell order
  mean_dof_mass_ = model::mean_dof_mass<D>(node_mass_);
  Eigen::VectorXd g(model.num_dofs());
  for (int n = 0; n < model.num_nodes(); ++n) g.segment<D>(n * D) = model.gravity;
  gravity_force_ = mass_times(g);
  stiffness_scale_.setZero(model.num_dofs());
  displacement_stiffness_.setZero(model.num_dofs());
  for (int c = 0; c < model.num_cells(); ++c) {
    const material::Lame lame = law(c).small_strain();  // the law's stiffness at small strain
    const double modulus = lame.lambda + 2.0 * lame.mu;
    const auto add = [&](const auto& point) {
      for (int a = 0; a < nodes; ++a) {
        const double grad = point.grad.col(a).norm();
        stiffness_scale_.segment<D>(model.cells(a, c) * D).array() += point.volume * modulus * grad;
        displacement_stiffness_.segment<D>(model.cells(a, c) * D).array() += point.volume * modulus * grad * grad;
      }
    };
    if (model.order == 1)
      add(model.geometry[c]);
    else
      for (int q = 0; q < fem::Quadratic<D>::kPoints; ++q) add(model.quadratic[c].at(q));
  }
}

template <int D>
void Assembler<D>::add_mass(double c, SparseMatrix& K) const {
  pattern_.add_identity_blocks(c, node_mass_, K.valuePtr());
}

template <int D>
Eigen::VectorXd Assembler<D>::mass_times(const Eigen::VectorXd& x) const {
  const auto nodes = node_mass_.rows();
  Eigen::VectorXd y(x.size());
  // M symmetric: (M Xᵀ)ᵀ = X M, a dense D × nodes times the sparse M.
  Eigen::Map<Eigen::Matrix<double, D, Eigen::Dynamic>>(y.data(), D, nodes).noalias() =
      Eigen::Map<const Eigen::Matrix<double, D, Eigen::Dynamic>>(x.data(), D, nodes) * node_mass_;
  return y;
}

template <int D>
fem::NodeMatrix<D> Assembler<D>::cell_positions(int cell, const Eigen::VectorXd& u) const {
  return positions<D + 1>(cell, u);
}

template <int D>
template <int N>
Eigen::Matrix<double, D, N> Assembler<D>::positions(int cell, const Eigen::VectorXd& u) const {
  const int first = model_.cells(0, cell);
  Eigen::Matrix<double, D, N> x;
  x.col(0).setZero();
  for (int a = 1; a < N; ++a) {
    const int node = model_.cells(a, cell);
    x.col(a) = (model_.X.col(node) - model_.X.col(first)) + (u.segment<D>(node * D) - u.segment<D>(first * D));
  }
  return x;
}

template <int D>
typename Assembler<D>::StepStart Assembler<D>::step_start(const Eigen::VectorXd& u_n) const {
  const int Q = points_per_cell();
  StepStart start(static_cast<std::size_t>(pattern_.kept_cells()) * static_cast<std::size_t>(Q));
  by_order([&](auto order) {
    using K = Kind<D, decltype(order)::value>;
#pragma omp parallel for schedule(static) if (model_.num_cells() >= kMinParallelCells)
    for (int c = 0; c < model_.num_cells(); ++c)
      if (const int l = pattern_.local_cell(c); l >= 0)
        K::start(K::geometry(model_, c), positions<K::kNodes>(c, u_n), &start[static_cast<std::size_t>(l) * Q]);
  });
  return start;
}

template <int D>
void Assembler<D>::internal_force(const StepStart& start, const Eigen::VectorXd& u_np1, fem::StressScheme scheme,
                                  Eigen::VectorXd& f, Eigen::VectorXd* magnitude) const {
  f.setZero(model_.num_dofs());
  if (magnitude) magnitude->setZero(model_.num_dofs());
  add_internal_force(start, u_np1, scheme, f, magnitude);
}

template <int D>
const NodePartition& Assembler<D>::partition() const {
  const int parts = model_.num_cells() >= kMinParallelCells ? std::max(threads(), 1) : 1;
  if (partition_.num_parts() != parts) {
    partition_ = partition_nodes(model_.num_nodes(), model_.cells, parts);
    if (scratch_.size() < static_cast<std::size_t>(parts)) scratch_.resize(static_cast<std::size_t>(parts));
  }
  return partition_;
}

template <int D>
void Assembler<D>::share(RankShare share) {
  share_ = std::move(share);
}

template <int D>
void Assembler<D>::cells_kept() {
  pattern_.renumber_to_kept();
  partition_ = {};
  rank_partition_ = {};
  measures_ = {};
  measured_u_.resize(0);
}

template <int D>
std::vector<double> Assembler<D>::all(double value) const {
  if (model_.num_ranks() == 1) return {value};
  return share_.all(value);
}

template <int D>
const NodePartition& Assembler<D>::rank_partition() const {
  if (model_.num_ranks() <= 1) return partition();
  const auto [first, end] = rank_nodes();
  const int parts = model_.num_cells() >= kMinParallelCells * model_.num_ranks() ? std::max(threads(), 1) : 1;
  if (rank_partition_.num_parts() != parts) {
    rank_partition_ = partition_nodes(model_.num_nodes(), model_.cells, parts, first, end);
    if (static_cast<int>(scratch_.size()) < parts) scratch_.resize(static_cast<std::size_t>(parts));
  }
  return rank_partition_;
}

template <int D>
void Assembler<D>::gather(Eigen::VectorXd* f, Eigen::VectorXd* magnitude) const {
  const int ranks = model_.num_ranks();
  if (ranks <= 1) return;
  std::vector<int> counts(static_cast<std::size_t>(ranks));
  for (int r = 0; r < ranks; ++r) counts[r] = (model_.rank_nodes[r + 1] - model_.rank_nodes[r]) * D;
  if (f) share_.gather(f->data(), counts);
  if (magnitude) share_.gather(magnitude->data(), counts);
}

template <int D>
void Assembler<D>::add_internal_force(const StepStart& start, const Eigen::VectorXd& u_np1, fem::StressScheme scheme,
                                      Eigen::VectorXd& f, Eigen::VectorXd* magnitude) const {
  const NodePartition& parts = rank_partition();
  const int Q = points_per_cell();
  by_order([&](auto order) {
  using K = Kind<D, decltype(order)::value>;
  for_each_part(parts, [&](int p) {
    const int first = parts.first_node[p], size = (parts.first_node[p + 1] - first) * D;
    Eigen::VectorXd& local = scratch_[p].force;
    Eigen::VectorXd& local_magnitude = scratch_[p].magnitude;
    local.setZero(size);
    if (magnitude) local_magnitude.setZero(size);
    for (int v = parts.visit_start[p]; v < parts.visit_start[p + 1]; ++v) {
      const int c = parts.visit_cell[v];
      const typename K::Nodes fe =
          K::force(K::geometry(model_, c), law(c), &start[static_cast<std::size_t>(pattern_.local_cell(c)) * Q],
                   positions<K::kNodes>(c, u_np1), scheme, mean_dilatation(c));
      for (int a = 0; a < K::kNodes; ++a) {
        if (!(parts.visit_owned[v] >> a & 1u)) continue;
        const int at = (model_.cells(a, c) - first) * D;
        local.segment<D>(at) += fe.col(a);
        if (magnitude) local_magnitude.segment<D>(at) += fe.col(a).cwiseAbs();
      }
    }
    f.segment(first * D, size) += local;
    if (magnitude) magnitude->segment(first * D, size) += local_magnitude;
  });
  });
  gather(&f, magnitude);
}

template <int D>
void Assembler<D>::internal_force(const Eigen::VectorXd& u_n, const Eigen::VectorXd& u_np1, fem::StressScheme scheme,
                                  Eigen::VectorXd& f, Eigen::VectorXd* magnitude) const {
  internal_force(step_start(u_n), u_np1, scheme, f, magnitude);
}

template <int D>
void Assembler<D>::internal_force_tangent(const StepStart& start, const Eigen::VectorXd& u_np1,
                                          fem::StressScheme scheme, Eigen::VectorXd& f, SparseMatrix& K) const {
  f.setZero(model_.num_dofs());
  std::fill(K.valuePtr(), K.valuePtr() + K.nonZeros(), 0.0);
  add_tangent(start, u_np1, scheme, &f, nullptr, K);
}

template <int D>
void Assembler<D>::add_internal_force_derivative(const StepStart& start, const Eigen::VectorXd& u_np1,
                                                 fem::StressScheme scheme, SparseMatrix& K) const {
  add_tangent(start, u_np1, scheme, nullptr, nullptr, K);
}

template <int D>
void Assembler<D>::add_internal_force_and_derivative(const StepStart& start, const Eigen::VectorXd& u_np1,
                                                     fem::StressScheme scheme, Eigen::VectorXd& f,
                                                     Eigen::VectorXd& magnitude, SparseMatrix& K) const {
  add_tangent(start, u_np1, scheme, &f, &magnitude, K);
}

template <int D>
void Assembler<D>::add_tangent(const StepStart& start, const Eigen::VectorXd& u_np1, fem::StressScheme scheme,
                               Eigen::VectorXd* f, Eigen::VectorXd* magnitude, SparseMatrix& K) const {
  double* values = K.valuePtr();
  const NodePartition& parts = rank_partition();
  if (!f) magnitude = nullptr;
  const int Q = points_per_cell();
  by_order([&](auto order) {
  using Cell = Kind<D, decltype(order)::value>;
  for_each_part(parts, [&](int p) {
    const int first = parts.first_node[p], size = (parts.first_node[p + 1] - first) * D;
    Eigen::VectorXd& local = scratch_[p].force;
    Eigen::VectorXd& local_magnitude = scratch_[p].magnitude;
    if (f) local.setZero(size);
    if (magnitude) local_magnitude.setZero(size);
    typename Cell::Nodes fe;
    typename Cell::Matrix Ke;
    for (int v = parts.visit_start[p]; v < parts.visit_start[p + 1]; ++v) {
      const int c = parts.visit_cell[v];
      const CornerMask owned = parts.visit_owned[v];
      Cell::force_tangent(Cell::geometry(model_, c), law(c),
                          &start[static_cast<std::size_t>(pattern_.local_cell(c)) * Q],
                          positions<Cell::kNodes>(c, u_np1), scheme, mean_dilatation(c), fe, Ke);
      if (f)
        for (int a = 0; a < Cell::kNodes; ++a) {
          if (!(owned >> a & 1u)) continue;
          const int at = (model_.cells(a, c) - first) * D;
          local.segment<D>(at) += fe.col(a);
          if (magnitude) local_magnitude.segment<D>(at) += fe.col(a).cwiseAbs();
        }
      pattern_.template add_cell_matrix<Cell::kNodes>(c, Ke, values, owned);  // the owned nodes' block rows
    }
    if (f) f->segment(first * D, size) += local;
    if (magnitude) magnitude->segment(first * D, size) += local_magnitude;
  });
  });
  gather(f, magnitude);
}

template <int D>
void Assembler<D>::internal_force_tangent(const Eigen::VectorXd& u_n, const Eigen::VectorXd& u_np1,
                                          fem::StressScheme scheme, Eigen::VectorXd& f, SparseMatrix& K) const {
  internal_force_tangent(step_start(u_n), u_np1, scheme, f, K);
}

template <int D>
const typename Assembler<D>::StateMeasures& Assembler<D>::measures(const Eigen::VectorXd& u) const {
  if (measures_.cells && measured_u_.size() == u.size() &&
      std::memcmp(measured_u_.data(), u.data(), sizeof(double) * static_cast<std::size_t>(u.size())) == 0)
    return measures_;
  const int n = model_.num_cells();
  const int Q = points_per_cell();
  auto cells = std::make_shared<StepStart>(static_cast<std::size_t>(pattern_.kept_cells()) * static_cast<std::size_t>(Q));
  std::vector<double> W(static_cast<std::size_t>(n), 0.0), det(static_cast<std::size_t>(n));
  Eigen::VectorXd f = Eigen::VectorXd::Zero(model_.num_dofs());
  const NodePartition& parts = rank_partition();
  const auto [rank_first, rank_end] = rank_nodes();
  const bool ranked = model_.num_ranks() > 1;
  by_order([&](auto order) {
  using K = Kind<D, decltype(order)::value>;
  for_each_part(parts, [&](int p) {
    const int first = parts.first_node[p], size = (parts.first_node[p + 1] - first) * D;
    Eigen::VectorXd& local = scratch_[p].force;
    local.setZero(size);
    for (int v = parts.visit_start[p]; v < parts.visit_start[p + 1]; ++v) {
      const int c = parts.visit_cell[v];
      const CornerMask owned = parts.visit_owned[v];
      const auto& g = K::geometry(model_, c);
      const typename K::Nodes x = positions<K::kNodes>(c, u);
      std::array<fem::CellStart<D>, K::kPoints> start;
      K::start(g, x, start.data());
      const typename K::Nodes fe = K::force(g, law(c), start.data(), x, fem::StressScheme::conserving, mean_dilatation(c));
      for (int a = 0; a < K::kNodes; ++a)
        if (owned >> a & 1u) local.segment<D>((model_.cells(a, c) - first) * D) += fe.col(a);
      // The cell's start: by the part that owns its lowest corner on this
      // rank; its own figures: by the part (on the rank) that owns its first.
      int lowest = 0;
      if (ranked)
        while (model_.cells(lowest, c) < rank_first || model_.cells(lowest, c) >= rank_end) ++lowest;
      if (!(owned >> lowest & 1u)) continue;
      std::copy(start.begin(), start.end(), cells->begin() + static_cast<std::ptrdiff_t>(pattern_.local_cell(c)) * Q);
      if (lowest != 0) continue;
      W[static_cast<std::size_t>(c)] = K::energy(g, law(c), x, mean_dilatation(c));
      det[static_cast<std::size_t>(c)] = K::min_det(start.data());
    }
    f.segment(first * D, size) += local;
  });
  });
  gather(&f, nullptr);
  StateMeasures m;
  m.cells = std::move(cells);
  double energy = 0.0;
  for (const double w : W) energy += w;  // in cell order, as strain_energy()
  for (const double e : all(energy)) m.strain_energy += e;  // rank by rank
  Orientation o{std::numeric_limits<double>::infinity(), -1};
  for (int c = 0; c < n; ++c)
    if (model_.owns(model_.cells(0, c)) && det[static_cast<std::size_t>(c)] < o.det_F)
      o = {det[static_cast<std::size_t>(c)], model_.global_cell(c)};
  const std::vector<double> dets = all(o.det_F), at = all(static_cast<double>(o.cell));
  m.orientation = {std::numeric_limits<double>::infinity(), -1};
  for (std::size_t r = 0; r < dets.size(); ++r) {  // the lowest cell on ties
    const int cell = static_cast<int>(at[r]);
    if (dets[r] < m.orientation.det_F || (dets[r] == m.orientation.det_F && cell >= 0 && cell < m.orientation.cell))
      m.orientation = {dets[r], cell};
  }
  m.force_norm = f.norm();
  measures_ = std::move(m);
  measured_u_ = u;
  return measures_;
}

template <int D>
Orientation Assembler<D>::min_det_F(const Eigen::VectorXd& u) const {
  const std::vector<double> det = per_cell(model_.num_cells(), [&](int c) {
    if (model_.order == 2) return fem::min_det_F<D>(model_.quadratic[c], positions<Kind<D, 2>::kNodes>(c, u));
    return fem::deformation_gradient<D>(cell_positions(c, u), model_.geometry[c]).determinant();
  });
  Orientation o{std::numeric_limits<double>::infinity(), -1};
  for (int c = 0; c < model_.num_cells(); ++c)
    if (det[c] < o.det_F) o = {det[c], model_.global_cell(c)};
  return o;
}

template <int D>
double Assembler<D>::strain_energy(const Eigen::VectorXd& u) const {
  const std::vector<double> W = per_cell(model_.num_cells(), [&](int c) {
    if (model_.order == 2)
      return Kind<D, 2>::energy(model_.quadratic[c], law(c), positions<Kind<D, 2>::kNodes>(c, u), mean_dilatation(c));
    return fem::strain_energy<D>(model_.geometry[c], law(c), cell_positions(c, u));
  });
  double sum = 0.0;
  for (const double w : W) sum += w;  // in cell order, as a serial loop
  return sum;
}

template class Assembler<2>;
template class Assembler<3>;
template Eigen::Matrix<double, 2, 6> Assembler<2>::positions<6>(int, const Eigen::VectorXd&) const;
template Eigen::Matrix<double, 3, 10> Assembler<3>::positions<10>(int, const Eigen::VectorXd&) const;

}  // namespace conserve::assembly
