/// The assembly's thread count may change between the steps of a run
/// (assembly::ThreadGovernor re-chooses it every second): a run of the peer
/// cube through its first contacts with 1 and 2 threads alternating step
/// by step ends in the same bits as one on a single thread; and the
/// governor's rules (assembly/threads.hpp).
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>

#include "assembly/threads.hpp"
#include "io/scenario.hpp"
#include "simulation/stepper.hpp"

namespace conserve::simulation {
namespace {

using assembly::ThreadGovernor;

/// u and v after `steps` steps of the peer cube, the thread count before
/// step k being threads(k).
template <class Threads>
model::State run_cube(int steps, Threads&& threads) {
  const io::Scenario sc =
      io::read_scenario(CONSERVE_SOURCE_DIR "/bench/cube/febio_cube.toml", {"solver.threads=1", "output.vtu_every=0"});
  Stepper<3> stepper(sc);
  model::State state = stepper.problem().initial;
  for (int k = 0; k < steps; ++k) {
    assembly::set_threads(threads(k));
    double dt = 0.0;
    int failures = 0;
    stepper.advance(state, dt, failures);
  }
  return state;
}

bool same_bits(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), sizeof(double) * a.size()) == 0;
}

TEST(ThreadSwitch, ThreadsChangingBetweenStepsGiveTheSameBits) {
  const int before = assembly::threads();
  if (!assembly::set_threads(2)) GTEST_SKIP() << "built without OpenMP: one thread only";
  constexpr int kSteps = 80;  // contact from step 74
  const model::State one = run_cube(kSteps, [](int) { return 1; });
  const model::State alternating = run_cube(kSteps, [](int k) { return 1 + k % 2; });
  assembly::set_threads(before);
  ASSERT_GT(one.v.norm(), 0.0);
  EXPECT_TRUE(same_bits(one.u, alternating.u));
  EXPECT_TRUE(same_bits(one.v, alternating.v));
}

TEST(ThreadGovernor, TakesTheCoresOtherProcessesLeaveFree) {
  EXPECT_EQ(ThreadGovernor::free_cores(2, 0.0), 2);
  EXPECT_EQ(ThreadGovernor::free_cores(2, 0.2), 2);   // a daemon's tick
  EXPECT_EQ(ThreadGovernor::free_cores(2, 0.3), 1);   // a core in use
  EXPECT_EQ(ThreadGovernor::free_cores(2, 1.0), 1);
  EXPECT_EQ(ThreadGovernor::free_cores(2, 3.0), 1);   // never fewer than one
  EXPECT_EQ(ThreadGovernor::free_cores(8, 2.1), 6);
  EXPECT_EQ(ThreadGovernor::free_cores(8, 2.3), 5);
}

TEST(ThreadGovernor, AFixedCountOrASmallModelIsNotMeasured) {
  const int before = assembly::threads();
  const ThreadGovernor fixed(3, 100000);
  EXPECT_FALSE(fixed.automatic());
  EXPECT_STREQ(fixed.policy(), "[solver] threads");
  EXPECT_EQ(fixed.threads(), 3);
  if (!std::getenv("OMP_NUM_THREADS")) {
    const ThreadGovernor small(0, assembly::kMinParallelCells - 1);
    EXPECT_FALSE(small.automatic());
    EXPECT_EQ(small.threads(), 1);
    const ThreadGovernor large(0, assembly::kMinParallelCells);
    if (assembly::processors() > 1) {
      EXPECT_TRUE(large.automatic());
      EXPECT_EQ(large.threads(), 1);  // until the first measurement
    }
  }
  assembly::set_threads(before);
}

TEST(OtherLoad, MeasuresNothingBeforeItsWindowAndAFigureAfter) {
  assembly::OtherLoad load;
  if (!load.available()) GTEST_SKIP() << "no /proc/stat here";
  EXPECT_FALSE(load.sample(3600.0).has_value());
  volatile double spin = 0.0;  // this process's own work is not counted as other load
  const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(200);
  while (std::chrono::steady_clock::now() < until) spin = spin + 1.0;
  const auto others = load.sample(0.1);
  ASSERT_TRUE(others.has_value());
  EXPECT_GE(*others, 0.0);
  EXPECT_LE(*others, assembly::processors() + 0.5);
}

}  // namespace
}  // namespace conserve::simulation
