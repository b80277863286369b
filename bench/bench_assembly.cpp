// Global assembly on the peer cube (bench/cube/febio_cube.toml: 13 182
// tetrahedra, 8 232 unknowns, 8 307 with the rigid plane's nodes):
// residual, residual with its magnitude (the round-off floor) and residual
// with tangent, with 1 and 2 assembly threads. Run:
//   ./build/release/bench/conserve_bench --benchmark_filter=Cube
// Times are wall times; the CPU column counts the main thread only.
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>

#include "assembly/assembler.hpp"
#include "assembly/threads.hpp"
#include "io/scenario.hpp"
#include "simulation/setup.hpp"

namespace conserve {
namespace {

/// The cube's model and a deformed step u_n → u_{n+1} (smooth fields of a
/// few per cent strain, so that every cell has non-zero stress).
struct CubeProblem {
  simulation::Problem<3> problem;
  std::unique_ptr<assembly::Assembler<3>> assembler;
  Eigen::VectorXd u_n, u_np1;

  CubeProblem() : problem(simulation::setup<3>(io::read_scenario(CONSERVE_SOURCE_DIR "/bench/cube/febio_cube.toml"))) {
    const auto& model = problem.model;
    assembler = std::make_unique<assembly::Assembler<3>>(model, false);
    u_n.resize(model.num_dofs());
    u_np1.resize(model.num_dofs());
    for (int n = 0; n < model.num_nodes(); ++n)
      for (int i = 0; i < 3; ++i) {
        const double s = std::sin(7.0 * model.X(i, n) + 3.0 * model.X((i + 1) % 3, n));
        u_n[n * 3 + i] = 0.02 * s;
        u_np1[n * 3 + i] = 0.025 * s + 0.01 * model.X((i + 2) % 3, n);
      }
  }
  static CubeProblem& get() {
    static CubeProblem p;
    return p;
  }
};

/// Sets the assembly threads for one benchmark, and back after it.
class ThreadsFor {
 public:
  explicit ThreadsFor(benchmark::State& st) : before_(assembly::threads()) {
    assembly::set_threads(static_cast<int>(st.range(0)));
    st.counters["threads"] = assembly::threads();
  }
  ThreadsFor(const ThreadsFor&) = delete;
  ThreadsFor& operator=(const ThreadsFor&) = delete;
  ~ThreadsFor() { assembly::set_threads(before_); }

 private:
  int before_;
};

void BM_CubeResidual(benchmark::State& st) {
  CubeProblem& p = CubeProblem::get();
  const ThreadsFor threads(st);
  Eigen::VectorXd f;
  const auto start = p.assembler->step_start(p.u_n);  // once per step in a run
  for (auto _ : st) p.assembler->internal_force(start, p.u_np1, fem::StressScheme::conserving, f);
  st.counters["unknowns"] = p.problem.model.num_dofs();
}
BENCHMARK(BM_CubeResidual)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_CubeResidualMagnitude(benchmark::State& st) {
  CubeProblem& p = CubeProblem::get();
  const ThreadsFor threads(st);
  Eigen::VectorXd f, magnitude;
  const auto start = p.assembler->step_start(p.u_n);  // once per step in a run
  for (auto _ : st) p.assembler->internal_force(start, p.u_np1, fem::StressScheme::conserving, f, &magnitude);
}
BENCHMARK(BM_CubeResidualMagnitude)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_CubeTangent(benchmark::State& st) {
  CubeProblem& p = CubeProblem::get();
  const ThreadsFor threads(st);
  Eigen::VectorXd f;
  SparseMatrix K = p.assembler->pattern().make_matrix();
  const auto start = p.assembler->step_start(p.u_n);
  for (auto _ : st) p.assembler->internal_force_tangent(start, p.u_np1, fem::StressScheme::conserving, f, K);
  st.counters["nonzeros"] = static_cast<double>(K.nonZeros());
  st.counters["parts"] = p.assembler->partition().num_parts();
  st.counters["visits_per_cell"] =
      static_cast<double>(p.assembler->partition().num_visits()) / p.problem.model.num_cells();
}
BENCHMARK(BM_CubeTangent)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace conserve
