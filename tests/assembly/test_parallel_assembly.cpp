// Assembly gives the same bits with 1, 2 and 3 threads, and the same bits
// as a plain serial loop over the cells in ascending order.
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <limits>
#include <random>

#include "assembly/assembler.hpp"
#include "assembly/partition.hpp"
#include "assembly/threads.hpp"
#include "material/svk_law.hpp"
#include "support/grid_mesh.hpp"

namespace conserve::assembly {
namespace {

/// Two bodies of different materials, each large enough on its own to be
/// assembled in parallel.
template <int D>
model::Model<D> large_model() {
  model::Model<D> m;
  const auto mesh = D == 3 ? test::box_mesh(8, 8, 7, 0.8, 0.8, 0.7) : test::rectangle_mesh(48, 40, 1.2, 1.0);
  model::add_body<D>(m, mesh, "a", std::make_shared<const material::Svk>(material::Lame::from_young_poisson(1e5, 0.3)),
                     1200.0, 0.5);
  model::add_body<D>(m, mesh, "b", std::make_shared<const material::Svk>(material::Lame::from_young_poisson(3e5, 0.2)),
                     800.0, 0.5);
  return m;
}

std::uint64_t bits(double x) { return std::bit_cast<std::uint64_t>(x); }

bool same_bits(const double* a, const double* b, Eigen::Index n) {
  for (Eigen::Index i = 0; i < n; ++i)
    if (bits(a[i]) != bits(b[i])) return false;
  return true;
}
bool same_bits(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return a.size() == b.size() && same_bits(a.data(), b.data(), a.size());
}

/// Everything the assembler computes for one step.
struct Assembled {
  Eigen::VectorXd f, magnitude, f_tangent;
  SparseMatrix K;
  Orientation orientation;
  double energy = 0.0;
};

template <int D>
Assembled assemble(const Assembler<D>& assembler, const Eigen::VectorXd& u_n, const Eigen::VectorXd& u_np1) {
  Assembled r;
  assembler.internal_force(u_n, u_np1, fem::StressScheme::conserving, r.f, &r.magnitude);
  r.K = assembler.pattern().make_matrix();
  assembler.internal_force_tangent(u_n, u_np1, fem::StressScheme::conserving, r.f_tangent, r.K);
  r.orientation = assembler.min_det_F(u_np1);
  r.energy = assembler.strain_energy(u_np1);
  return r;
}

/// The same quantities by plain serial loops over the cells in ascending
/// order, adding into zeroed vectors and matrix.
template <int D>
Assembled serial_reference(const Assembler<D>& assembler, const Eigen::VectorXd& u_n, const Eigen::VectorXd& u_np1) {
  const model::Model<D>& m = assembler.model();
  Assembled r;
  r.f.setZero(m.num_dofs());
  r.magnitude.setZero(m.num_dofs());
  r.f_tangent.setZero(m.num_dofs());
  r.K = assembler.pattern().make_matrix();
  for (int c = 0; c < m.num_cells(); ++c) {
    const auto& lame = *m.bodies[m.cell_body[c]].law;
    const fem::StepPositions<D> x{assembler.cell_positions(c, u_n), assembler.cell_positions(c, u_np1)};
    const fem::NodeMatrix<D> fe = fem::internal_force<D>(m.geometry[c], lame, x, fem::StressScheme::conserving);
    fem::NodeMatrix<D> fe_t;
    fem::ElementMatrix<D> Ke;
    fem::internal_force_tangent<D>(m.geometry[c], lame, x, fem::StressScheme::conserving, fe_t, Ke);
    for (int a = 0; a <= D; ++a) {
      const int dof = m.cells(a, c) * D;
      r.f.segment<D>(dof) += fe.col(a);
      r.magnitude.segment<D>(dof) += fe.col(a).cwiseAbs();
      r.f_tangent.segment<D>(dof) += fe_t.col(a);
    }
    for (int b = 0; b <= D; ++b)
      for (int k = 0; k < D; ++k)
        for (int a = 0; a <= D; ++a)
          for (int i = 0; i < D; ++i)
            r.K.valuePtr()[assembler.pattern().position(c, a, b, i, k)] += Ke(a * D + i, b * D + k);
  }
  r.orientation = {std::numeric_limits<double>::infinity(), -1};
  for (int c = 0; c < m.num_cells(); ++c) {
    const auto x = assembler.cell_positions(c, u_np1);
    const double det = fem::deformation_gradient<D>(x, m.geometry[c]).determinant();
    if (det < r.orientation.det_F) r.orientation = {det, c};
    r.energy += fem::strain_energy<D>(m.geometry[c], *m.bodies[m.cell_body[c]].law, x);
  }
  return r;
}

void expect_same_bits(const Assembled& a, const Assembled& b, const std::string& what) {
  EXPECT_TRUE(same_bits(a.f, b.f)) << what << ": f, max |Δ| " << (a.f - b.f).cwiseAbs().maxCoeff();
  EXPECT_TRUE(same_bits(a.magnitude, b.magnitude))
      << what << ": magnitude, max |Δ| " << (a.magnitude - b.magnitude).cwiseAbs().maxCoeff();
  EXPECT_TRUE(same_bits(a.f_tangent, b.f_tangent))
      << what << ": f of the tangent call, max |Δ| " << (a.f_tangent - b.f_tangent).cwiseAbs().maxCoeff();
  ASSERT_EQ(a.K.nonZeros(), b.K.nonZeros());
  EXPECT_TRUE(same_bits(a.K.valuePtr(), b.K.valuePtr(), a.K.nonZeros()))
      << what << ": K, max |Δ| " << (Eigen::MatrixXd(a.K) - Eigen::MatrixXd(b.K)).cwiseAbs().maxCoeff();
  EXPECT_EQ(bits(a.orientation.det_F), bits(b.orientation.det_F)) << what << ": min det F";
  EXPECT_EQ(a.orientation.cell, b.orientation.cell) << what << ": cell of min det F";
  EXPECT_EQ(bits(a.energy), bits(b.energy)) << what << ": strain energy";
}

template <int D>
void check_thread_independence() {
  const model::Model<D> model = large_model<D>();
  ASSERT_GE(model.num_cells(), kMinParallelCells);  // the parallel path runs
  const Assembler<D> assembler(model, false);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.02, 0.02);
  Eigen::VectorXd u_n(model.num_dofs()), u_np1(model.num_dofs());
  for (int i = 0; i < model.num_dofs(); ++i) u_n[i] = u(rng), u_np1[i] = u(rng);

  const int threads_before = threads();
  set_threads(1);
  const Assembled one = assemble(assembler, u_n, u_np1);
  ASSERT_GT(one.f.norm(), 0.0);  // non-zero guards
  ASSERT_GT(Eigen::MatrixXd(one.K).norm(), 0.0);
  ASSERT_GT(one.energy, 0.0);
  expect_same_bits(one, serial_reference(assembler, u_n, u_np1), "serial reference vs 1 thread");
  for (int n : {2, 3}) {
    if (!set_threads(n)) GTEST_SKIP() << "built without OpenMP: one thread only";
    ASSERT_EQ(threads(), n);
    ASSERT_EQ(assembler.partition().num_parts(), n);  // n parts, each on its own thread
    expect_same_bits(assemble(assembler, u_n, u_np1), one, std::to_string(n) + " threads vs 1");
  }
  set_threads(threads_before);
}

TEST(ParallelAssembly, SameBitsForAnyThreadCount2d) { check_thread_independence<2>(); }
TEST(ParallelAssembly, SameBitsForAnyThreadCount3d) { check_thread_independence<3>(); }

/// What the terms of a step rely on: adding the force into a vector that
/// holds other terms gives that vector plus the force, bit for bit, on any
/// number of threads (each node's cell sum is formed first, then added).
TEST(ParallelAssembly, AddsTheForceOntoWhatIsThere) {
  const model::Model<3> model = large_model<3>();
  const Assembler<3> assembler(model, false);
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> u(-0.02, 0.02);
  Eigen::VectorXd u_n(model.num_dofs()), u_np1(model.num_dofs()), other(model.num_dofs());
  for (int i = 0; i < model.num_dofs(); ++i) u_n[i] = u(rng), u_np1[i] = u(rng), other[i] = 1e3 * u(rng);
  const auto start = assembler.step_start(u_n);
  const int threads_before = threads();
  for (int n : {1, 2}) {
    if (!set_threads(n) && n > 1) GTEST_SKIP() << "built without OpenMP: one thread only";
    Eigen::VectorXd f, g = other;
    assembler.internal_force(start, u_np1, fem::StressScheme::conserving, f);
    assembler.add_internal_force(start, u_np1, fem::StressScheme::conserving, g);
    ASSERT_GT(f.norm(), 0.0);
    EXPECT_TRUE(same_bits(g, Eigen::VectorXd(other + f))) << n << " threads";
  }
  set_threads(threads_before);
}

/// Assembler::measures: one pass gives the same bits as step_start,
/// strain_energy, min_det_F and the force at rest, on any number of
/// threads; asked again for the same u it is not computed again, for
/// another u it is.
TEST(ParallelAssembly, MeasuresOfAStateAreTheSeparatePassesBits) {
  const model::Model<3> model = large_model<3>();
  const Assembler<3> assembler(model, false);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> dist(-0.02, 0.02);
  Eigen::VectorXd u(model.num_dofs()), v(model.num_dofs());
  for (int i = 0; i < model.num_dofs(); ++i) u[i] = dist(rng), v[i] = dist(rng);
  const int threads_before = threads();
  for (int n : {1, 2}) {
    if (!set_threads(n) && n > 1) GTEST_SKIP() << "built without OpenMP: one thread only";
    const auto& m = assembler.measures(u);
    const auto start = assembler.step_start(u);
    Eigen::VectorXd f;
    assembler.internal_force(start, u, fem::StressScheme::conserving, f);
    ASSERT_GT(f.norm(), 0.0);
    EXPECT_EQ(bits(m.force_norm), bits(f.norm())) << n << " threads";
    EXPECT_EQ(bits(m.strain_energy), bits(assembler.strain_energy(u))) << n << " threads";
    const Orientation o = assembler.min_det_F(u);
    EXPECT_EQ(bits(m.orientation.det_F), bits(o.det_F)) << n << " threads";
    EXPECT_EQ(m.orientation.cell, o.cell);
    ASSERT_EQ(m.cells->size(), start.size());
    for (std::size_t c = 0; c < start.size(); ++c) {
      ASSERT_TRUE(same_bits((*m.cells)[c].F.data(), start[c].F.data(), 9)) << "cell " << c;
    }
    const auto kept = m.cells;
    EXPECT_EQ(assembler.measures(u).cells, kept);  // the same u: kept
    EXPECT_NE(assembler.measures(v).cells, kept);  // another: computed
    EXPECT_EQ(bits(assembler.measures(v).strain_energy), bits(assembler.strain_energy(v)));
  }
  set_threads(threads_before);
}

/// Ranks that each assemble their own nodes and gather the others' give
/// the one process's bits (RankShare): the gathered forces whole, and the
/// tangent's rows each rank holds (its nodes' rows, no other) entry for
/// entry; the ranks' rows together are the whole tangent's. The ranks are
/// simulated in one process: rank r's gather takes the lower ranks'
/// segments from what they computed before it, so the last rank ends with
/// every segment; its measures add the lower ranks' energies.
template <int D>
void check_rank_share(int ranks) {
  const model::Model<D> model = large_model<D>();
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-0.02, 0.02);
  Eigen::VectorXd u_n(model.num_dofs()), u_np1(model.num_dofs());
  for (int i = 0; i < model.num_dofs(); ++i) u_n[i] = u(rng), u_np1[i] = u(rng);
  const Assembler<D> whole(model, false);
  const Assembled one = assemble(whole, u_n, u_np1);
  const auto& measured = whole.measures(u_np1);
  const std::vector<int> rank_nodes = partition_nodes(model.num_nodes(), model.cells, ranks).first_node;
  // The gathered arrays and the figures in call order.
  std::vector<std::vector<double>> done;
  std::vector<std::vector<double>> figures(static_cast<std::size_t>(ranks));
  Assembled last;
  Eigen::Index rows_held = 0;
  for (int rank = 0; rank < ranks; ++rank) {
    std::size_t call = 0, figure = 0;
    std::vector<std::vector<double>> mine;
    auto gather = [&](double* data, const std::vector<int>& counts) {
      long start = 0;
      for (int r = 0; r < ranks; ++r) {
        if (r < rank) std::copy(done[call].begin() + start, done[call].begin() + start + counts[r], data + start);
        start += counts[r];
      }
      mine.emplace_back(data, data + start);
      ++call;
    };
    auto all = [&](double value) {
      figures[static_cast<std::size_t>(rank)].push_back(value);
      std::vector<double> out;
      for (int r = 0; r <= rank; ++r) out.push_back(figures[static_cast<std::size_t>(r)][figure]);
      ++figure;
      return out;
    };
    model::Model<D> ranked = model;
    ranked.rank_nodes = rank_nodes;
    ranked.rank = rank;
    Assembler<D> part(ranked, false);
    part.share({gather, all});
    const auto [first, end] = part.rank_nodes();
    EXPECT_LT(first, end) << "rank " << rank;
    last = assemble(part, u_n, u_np1);
    const auto& m = part.measures(u_np1);
    // Every entry this rank holds is the whole tangent's, in this rank's rows only.
    const SparseMatrix& K = last.K;
    bool same = true, outside = false;
    for (int col = 0; col < K.outerSize(); ++col)
      for (SparseMatrix::InnerIterator it(K, col); it; ++it) {
        outside = outside || it.row() < first * D || it.row() >= end * D;
        same = same && bits(it.value()) == bits(one.K.coeff(it.row(), col));
      }
    EXPECT_TRUE(same) << "rank " << rank << ": K's entries differ from one process's";
    EXPECT_FALSE(outside) << "rank " << rank << " holds rows of another rank's nodes";
    Eigen::Index in_rows = 0;
    for (int col = 0; col < one.K.outerSize(); ++col)
      for (SparseMatrix::InnerIterator it(one.K, col); it; ++it) in_rows += it.row() >= first * D && it.row() < end * D;
    EXPECT_EQ(K.nonZeros(), in_rows) << "rank " << rank;
    rows_held += K.nonZeros();
    if (rank == ranks - 1) {
      EXPECT_EQ(bits(m.force_norm), bits(measured.force_norm));
      EXPECT_NEAR(m.strain_energy, measured.strain_energy, 1e-12 * measured.strain_energy);  // summed rank by rank
      EXPECT_EQ(m.orientation.cell, measured.orientation.cell);
      EXPECT_EQ(bits(m.orientation.det_F), bits(measured.orientation.det_F));
    }
    done = std::move(mine);
  }
  EXPECT_EQ(rows_held, one.K.nonZeros());
  // The forces gathered on the last rank are the one process's bits.
  EXPECT_TRUE(same_bits(last.f, one.f));
  EXPECT_TRUE(same_bits(last.magnitude, one.magnitude));
  EXPECT_TRUE(same_bits(last.f_tangent, one.f_tangent));
}

TEST(ParallelAssembly, RanksThatShareTheWorkGiveTheSameBits2d) { check_rank_share<2>(3); }
TEST(ParallelAssembly, RanksThatShareTheWorkGiveTheSameBits3d) { check_rank_share<3>(2); }

}  // namespace
}  // namespace conserve::assembly
