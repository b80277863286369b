// The cost of each point law (issue 45): the internal force (a residual's
// assembly) and the force with its tangent on a 16³-cube box of 24 576
// tetrahedra in the middle of a step with 10 % strains, per law: 0 svk
// (Simo–Tarnow, closed form), 1 neo_hookean, 2 mooney_rivlin (discrete
// gradient). One thread. Run: ./build/release/bench/conserve_bench
// --benchmark_filter=Law
#include <benchmark/benchmark.h>

#include <array>
#include <memory>

#include "assembly/assembler.hpp"
#include "assembly/threads.hpp"
#include "material/law.hpp"
#include "model/initial_state.hpp"
#include "support/grid_mesh.hpp"

namespace conserve {
namespace {

struct LawBox {
  model::Model<3> model;
  std::unique_ptr<assembly::Assembler<3>> assembler;
  Eigen::VectorXd u_n, u_np1;

  explicit LawBox(int law) {
    const material::Lame l = material::Lame::from_young_poisson(1e6, 0.3);
    const std::array<std::shared_ptr<const material::Law>, 3> laws = {
        material::make_law("svk", {{"young", 1e6}, {"poisson", 0.3}}),
        material::make_law("neo_hookean", {{"young", 1e6}, {"poisson", 0.3}}),
        material::make_law("mooney_rivlin",
                           {{"c10", 0.375 * l.mu}, {"c01", 0.125 * l.mu}, {"bulk", l.lambda + 2.0 * l.mu / 3.0}})};
    model::add_body<3>(model, test::box_mesh(16, 16, 16, 1.0, 1.0, 1.0), "box", laws[static_cast<std::size_t>(law)],
                       1000.0, 1.0);
    assembler = std::make_unique<assembly::Assembler<3>>(model, false);
    model::State state = model::rest_state<3>(model);
    model::InitialMotion motion;
    motion.deformation << 1.1, 0.05, 0, 0, 0.92, 0, 0, 0, 1.0;
    motion.angular_velocity << 0, 0, 2.0;
    model::set_initial_motion<3>(model, 0, motion, state);
    u_n = state.u;
    u_np1 = state.u + 1e-3 * state.v;
  }
  static LawBox& get(int law) {
    static std::array<std::unique_ptr<LawBox>, 3> boxes;
    auto& box = boxes[static_cast<std::size_t>(law)];
    if (!box) box = std::make_unique<LawBox>(law);
    return *box;
  }
};

void BM_LawResidual(benchmark::State& st) {
  LawBox& b = LawBox::get(static_cast<int>(st.range(0)));
  const int before = assembly::threads();
  assembly::set_threads(1);
  const auto start = b.assembler->step_start(b.u_n);
  Eigen::VectorXd f;
  for (auto _ : st) b.assembler->internal_force(start, b.u_np1, fem::StressScheme::conserving, f);
  assembly::set_threads(before);
  st.counters["cells"] = b.model.num_cells();
}
BENCHMARK(BM_LawResidual)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

void BM_LawResidualTangent(benchmark::State& st) {
  LawBox& b = LawBox::get(static_cast<int>(st.range(0)));
  const int before = assembly::threads();
  assembly::set_threads(1);
  const auto start = b.assembler->step_start(b.u_n);
  Eigen::VectorXd f;
  SparseMatrix K = b.assembler->pattern().make_matrix();
  for (auto _ : st) b.assembler->internal_force_tangent(start, b.u_np1, fem::StressScheme::conserving, f, K);
  assembly::set_threads(before);
}
BENCHMARK(BM_LawResidualTangent)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace conserve
