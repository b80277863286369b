/// Checkpoint files: names, pruning and the stored step, also beyond 2^31
/// steps (issue 11).
#include <gtest/gtest.h>

#include <algorithm>

#include <set>
#include <string>

#include "contact/elimination/held_statistics.hpp"
#include "core/error.hpp"
#include "simulation/checkpoint.hpp"
#include "support/files.hpp"

namespace conserve::simulation {
namespace {

namespace fs = std::filesystem;

/// A 2D model of three nodes and no cells: enough to size a state.
model::Model<2> three_nodes() {
  model::Model<2> m;
  m.X = Eigen::Matrix<double, 2, Eigen::Dynamic>::Zero(2, 3);
  return m;
}

TEST(Checkpoint, PathNamesStepsBeyondThirtyTwoBits) {
  EXPECT_EQ(checkpoint_path("out", 42), fs::path("out/checkpoints/ckpt_000042.bin"));
  EXPECT_EQ(checkpoint_path("out", 3'000'000'005LL), fs::path("out/checkpoints/ckpt_3000000005.bin"));
}

TEST(Checkpoint, StepBeyondThirtyTwoBitsRoundTrips) {
  const auto dir = test::scratch("checkpoint_big_step");
  const model::Model<2> model = three_nodes();
  Checkpoint<2> c;
  c.fingerprint = {{"dimension", 2, "2"}, {"[time] step", 7, "0.001"}};
  c.state.step = 3'000'000'005LL;
  c.state.time = 3000.000005;
  c.state.u = Eigen::VectorXd::LinSpaced(6, 0.0, 1.0);
  c.state.v = Eigen::VectorXd::LinSpaced(6, -1.0, 0.0);
  c.control.dt = 1e-3;
  const fs::path file = checkpoint_path(dir, c.state.step);
  write_checkpoint<2>(file, c);
  const Checkpoint<2> back = read_checkpoint<2>(file, c.fingerprint, model);
  EXPECT_EQ(back.state.step, 3'000'000'005LL);
  EXPECT_EQ(back.state.time, c.state.time);
  EXPECT_EQ(back.state.u, c.state.u);
  EXPECT_EQ(back.state.v, c.state.v);
}

/// A checkpoint of three_nodes() at rest, Δt = 1 ms, with no constraint.
Checkpoint<2> at_rest() {
  Checkpoint<2> c;
  c.fingerprint = {{"dimension", 2, "2"}};
  c.state.u = Eigen::VectorXd::Zero(6);
  c.state.v = Eigen::VectorXd::Zero(6);
  c.control.dt = 1e-3;
  return c;
}

// The contact method's state is stored as its bytes, whatever they hold
// (contact::Method::save; the elimination's constraints are checked in
// tests/time/test_methods.cpp), beside the run's statistics and the step
// lengths that located releases predict from.
TEST(Checkpoint, KeepsTheContactStateAndWhatReleasesPredictFrom) {
  const auto dir = test::scratch("checkpoint_contact_state");
  const model::Model<2> model = three_nodes();
  Checkpoint<2> c = at_rest();
  c.totals.statistics = RunStatistics(contact::held_statistics());  // elimination's own statistics
  const std::vector<std::string> keys = c.totals.statistics.keys();
  c.totals.statistics.accumulated[static_cast<std::size_t>(
      std::find(keys.begin(), keys.end(), "pushes_given_up") - keys.begin())] = 3;
  c.control.last_dt = 2.5e-4;
  c.control.previous_dt = 5e-4;
  c.contact = std::string("\0\x01\x7f\n bytes", 9);
  write_checkpoint<2>(checkpoint_path(dir, 0), c);
  const Checkpoint<2> back =
      read_checkpoint<2>(checkpoint_path(dir, 0), c.fingerprint, model, RunStatistics(contact::held_statistics()));
  EXPECT_EQ(back.contact, c.contact);
  EXPECT_EQ(back.control.last_dt, 2.5e-4);
  EXPECT_EQ(back.control.previous_dt, 5e-4);
  EXPECT_EQ(back.totals.statistics.value("pushes_given_up"), 3);
  // Read for a run without those statistics (another contact method): refused.
  EXPECT_THROW(
      {
        try {
          (void)read_checkpoint<2>(checkpoint_path(dir, 0), c.fingerprint, model);
        } catch (const InputError& e) {
          EXPECT_NE(std::string(e.what()).find("run statistics"), std::string::npos) << e.what();
          throw;
        }
      },
      InputError);
}

TEST(Checkpoint, RefusesAnEarlierFormatVersion) {
  // Version 1 stored 32-bit steps: its files are refused with the versions.
  const auto dir = test::scratch("checkpoint_version_1");
  std::string bytes;
  const std::string magic = "conserve-checkpoint";
  const std::size_t size = magic.size();
  const std::uint32_t version = 1;
  bytes.append(reinterpret_cast<const char*>(&size), sizeof size).append(magic);
  bytes.append(reinterpret_cast<const char*>(&version), sizeof version).append(64, '\0');
  test::write_file(dir / "old.bin", bytes);
  try {
    read_checkpoint<2>(dir / "old.bin", {}, three_nodes());
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), (dir / "old.bin").string() +
                                         ": bad checkpoint: format version 1, this conserve reads version 20 only "
                                         "(restart with the conserve that wrote it, or run from the start)");
  }
}

TEST(Checkpoint, PrunesStepsBeyondThirtyTwoBits) {
  const auto dir = test::scratch("checkpoint_prune_big");
  for (const char* name :
       {"ckpt_2999999998.bin", "ckpt_2999999999.bin", "ckpt_3000000000.bin", "ckpt_3000000001.bin", "ckpt_999999.bin"})
    test::write_file(dir / "checkpoints" / name, "x");
  EXPECT_EQ(prune_checkpoints(dir, 3'000'000'001LL, 2), 3);
  std::set<std::string> left;
  for (const auto& f : fs::directory_iterator(dir / "checkpoints")) left.insert(f.path().filename().string());
  EXPECT_EQ(left, (std::set<std::string>{"ckpt_3000000000.bin", "ckpt_3000000001.bin"}));
}

}  // namespace
}  // namespace conserve::simulation
