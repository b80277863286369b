// Global assembly on the peer cube (bench/cube/febio_cube.toml: 13 182
// tetrahedra, 8 232 unknowns, 8 307 with the rigid plane's nodes):
// residual, residual with its magnitude (the round-off floor) and residual
// with tangent, with 1 and 2 assembly threads; and what moving a cache line
// between the two cores costs. Run:
//   ./build/release/bench/conserve_bench --benchmark_filter=Cube
// Times are wall times; the CPU column counts the main thread only.
#include <benchmark/benchmark.h>

#include <atomic>
#include <cmath>
#include <cstdint>
#include <memory>
#include <thread>

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

/// What a cache line costs to move between two cores: one thread writes a
/// counter, the other answers, per round trip. On the project's VM kind it
/// is about 100 ns in one placement of the two vCPUs and about 400 ns in
/// another, which holds for minutes (bench/README.md, "Parallel
/// assembly"); the assembly's speed on 2 threads followed it until the
/// threads stopped sharing their results' cache lines.
void BM_CoreToCoreRoundTrip(benchmark::State& st) {
  alignas(64) std::atomic<std::int64_t> turn{0};
  std::atomic<bool> stop{false};
  std::thread answer([&] {
    for (std::int64_t seen = 1; !stop.load(std::memory_order_relaxed); seen += 2) {
      while (turn.load(std::memory_order_acquire) < seen)
        if (stop.load(std::memory_order_relaxed)) return;
      turn.store(seen + 1, std::memory_order_release);
    }
  });
  std::int64_t next = 1;
  for (auto _ : st) {
    turn.store(next, std::memory_order_release);
    while (turn.load(std::memory_order_acquire) != next + 1) {
    }
    next += 2;
  }
  stop = true;
  answer.join();
}
BENCHMARK(BM_CoreToCoreRoundTrip)->Unit(benchmark::kNanosecond)->UseRealTime();

}  // namespace
}  // namespace conserve
