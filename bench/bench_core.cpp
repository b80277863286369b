// Core-engine benchmarks (issue 2): element kernel, global assembly and one
// whole Newton iteration on a structured box of 6·26³ = 105 456 tetrahedra
// (19 683 nodes, 59 049 unknowns). Run: ./build/release/bench/conserve_bench
#include <benchmark/benchmark.h>

#include <memory>

#include "material/svk_law.hpp"
#include "assembly/assembler.hpp"
#include "model/initial_state.hpp"
#include "support/grid_mesh.hpp"
#include "time/integrator.hpp"
#include "time/step_problem.hpp"

namespace conserve {
namespace {

constexpr int kCells = 26;

/// A deformed, spinning box shared by the global benchmarks.
struct BoxProblem {
  model::Model<3> model;
  std::unique_ptr<assembly::Assembler<3>> assembler;
  model::State state;

  BoxProblem() {
    model::add_body<3>(model, test::box_mesh(kCells, kCells, kCells, 1.0, 1.0, 1.0), "box",
                       std::make_shared<const material::Svk>(material::Lame::from_young_poisson(1e6, 0.3)), 1000.0, 1.0);
    assembler = std::make_unique<assembly::Assembler<3>>(model, false);
    state = model::rest_state<3>(model);
    model::InitialMotion motion;
    motion.deformation << 1.1, 0.05, 0, 0, 0.95, 0, 0, 0, 1.0;
    motion.angular_velocity << 0, 0, 2.0;
    model::set_initial_motion<3>(model, 0, motion, state);
  }
  static BoxProblem& get() {
    static BoxProblem p;
    return p;
  }
};

void BM_ElementForceTangent(benchmark::State& st) {
  fem::NodeMatrix<3> X;
  X << 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1;
  const auto g = fem::simplex_geometry<3>(X, 1.0);
  const fem::StepPositions<3> x{1.05 * X, 1.1 * X};
  fem::NodeMatrix<3> f;
  fem::ElementMatrix<3> K;
  for (auto _ : st) {
    fem::internal_force_tangent<3>(g, material::Svk(material::Lame{1.0, 1.0}), x, fem::StressScheme::conserving, f, K);
    benchmark::DoNotOptimize(K.data());
  }
}
BENCHMARK(BM_ElementForceTangent);

void BM_AssembleForce(benchmark::State& st) {
  BoxProblem& p = BoxProblem::get();
  Eigen::VectorXd f;
  const Eigen::VectorXd u1 = p.state.u + 1e-3 * p.state.v;
  const auto start = p.assembler->step_start(p.state.u);  // once per step in a run
  for (auto _ : st) p.assembler->internal_force(start, u1, fem::StressScheme::conserving, f);
  st.counters["cells"] = p.model.num_cells();
}
BENCHMARK(BM_AssembleForce)->Unit(benchmark::kMillisecond);

void BM_AssembleForceTangent(benchmark::State& st) {
  BoxProblem& p = BoxProblem::get();
  Eigen::VectorXd f;
  SparseMatrix K = p.assembler->pattern().make_matrix();
  const Eigen::VectorXd u1 = p.state.u + 1e-3 * p.state.v;
  const auto start = p.assembler->step_start(p.state.u);
  for (auto _ : st) p.assembler->internal_force_tangent(start, u1, fem::StressScheme::conserving, f, K);
  st.counters["nonzeros"] = static_cast<double>(K.nonZeros());
}
BENCHMARK(BM_AssembleForceTangent)->Unit(benchmark::kMillisecond);

/// One whole Newton iteration: residual, tangent, linear set-up and solve
/// (to 1e-8 for the Krylov back ends), update. Argument: the method
/// (0 UMFPACK LU, 1 GMRES + ILU(0), 2 GMRES + GAMG).
void BM_NewtonIteration(benchmark::State& st) {
  BoxProblem& p = BoxProblem::get();
  const double dt = 1e-3;
  assembly::DirichletMask mask(p.assembler->pattern().make_matrix(), {});
  SparseMatrix K = p.assembler->pattern().make_matrix();
  solver::LinearSolverSettings settings;
  settings.method = st.range(0) == 0 ? solver::Method::direct : solver::Method::krylov;
  settings.preconditioner = st.range(0) == 2 ? solver::Preconditioner::gamg : solver::Preconditioner::ilu;
  const auto solver = solver::make_linear_solver(settings, p.model.num_dofs());
  solver->set_coordinates(p.model.X);
  Eigen::VectorXd u1 = p.state.u + dt * p.state.v, r, dx;
  time::StepProblem<3> problem(*p.assembler, mask, fem::StressScheme::conserving, p.state, dt, u1, K);
  solver->set_operator(problem.tangent());  // symbolic analysis outside the loop
  int iterations = 0;
  for (auto _ : st) {
    problem.residual(r);
    solver->set_operator(problem.tangent());
    iterations = solver->solve(-r, dx, 1e-8).iterations;
    problem.update(0.0 * dx);  // keep the iterate: every iteration does the same work
  }
  st.counters["unknowns"] = p.model.num_dofs();
  st.counters["linear_iterations"] = iterations;
  st.SetLabel(solver->name());
}
BENCHMARK(BM_NewtonIteration)->Unit(benchmark::kMillisecond)->Arg(0)->Arg(1)->Arg(2)->Iterations(3);

}  // namespace
}  // namespace conserve
