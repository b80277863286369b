// Checkpoint and restart (issue 7): a run stopped early and continued from
// a checkpoint writes the same history, byte for byte, as the run that was
// never interrupted; on a contact scenario, so that the active set is part
// of what the checkpoint must carry.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fcntl.h>
#include <fmt/format.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <set>
#include <sstream>
#include <thread>
#include <vector>

#include "support/cli.hpp"
#include "support/contact_scenarios.hpp"

namespace conserve::test {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

/// glancing_spheres(2, "frictionless", 0.05): contact from step 8 to 54,
/// releases at 47, 50 and 55; output and checkpoints added.
const std::string kGlancingDiscs =
    glancing_spheres(2, "frictionless", 0.05) + "[output]\nvtu_every = 20\ncheckpoint_every = 10\n";

/// ball_on_plane("stick", 0.12): the first slave sticks at step 64, a
/// second at 89.
const std::string kBallOnPlane = ball_on_plane("stick", 0.12) + "[output]\nvtu_every = 0\ncheckpoint_every = 25\n";

/// Runs `scenario` once uninterrupted and once stopped after `stop` steps
/// and restarted from the checkpoint of step `from`; both histories and
/// steps.csv must be identical.
void expect_identical_after_restart(const std::string& name, const std::string& scenario, int stop, int from) {
  const auto dir = scratch(name);
  write_file(dir / "s.toml", scenario);
  const CliResult full = run_cli("run s.toml -q -o full", dir);
  ASSERT_EQ(full.exit_code, 0) << full.err;
  const CliResult part = run_cli("run s.toml -q -o part --steps " + std::to_string(stop), dir);
  ASSERT_EQ(part.exit_code, 0) << part.err;
  const std::string ckpt =
      "part/checkpoints/ckpt_" + std::string(6 - std::to_string(from).size(), '0') + std::to_string(from) + ".bin";
  ASSERT_TRUE(fs::exists(dir / ckpt)) << ckpt;
  EXPECT_NE(slurp(dir / "full/history.csv"), slurp(dir / "part/history.csv"));
  const CliResult rest = run_cli("run s.toml -q -o part --restart " + ckpt, dir);
  ASSERT_EQ(rest.exit_code, 0) << rest.err;
  EXPECT_TRUE(slurp(dir / "full/history.csv") == slurp(dir / "part/history.csv")) << "history.csv differs";
  EXPECT_TRUE(slurp(dir / "full/steps.csv") == slurp(dir / "part/steps.csv")) << "steps.csv differs";
  if (fs::exists(dir / "full/solution.pvd"))  // the time series keeps the entries from before the restart
    EXPECT_EQ(slurp(dir / "full/solution.pvd"), slurp(dir / "part/solution.pvd"));
  for (const auto& f : fs::recursive_directory_iterator(dir / "part"))
    EXPECT_NE(f.path().extension(), ".tmp") << f.path();
}

/// The rows of a run's steps.csv: step, time and dt of each step taken.
struct StepRow {
  int step = 0;
  double time = 0.0, dt = 0.0;
};
std::vector<StepRow> step_rows(const fs::path& steps_csv) {
  std::istringstream rows(slurp(steps_csv));
  std::string line;
  std::getline(rows, line);  // header
  std::vector<StepRow> out;
  while (std::getline(rows, line)) {
    StepRow r;
    if (std::sscanf(line.c_str(), "%d,%lf,%lf", &r.step, &r.time, &r.dt) != 3) {
      ADD_FAILURE() << "a malformed row of " << steps_csv << ": " << line;
      break;
    }
    out.push_back(r);
  }
  return out;
}

TEST(Restart, FrictionlessContactHistoryIsBitIdentical) {
  // Checkpoint 30 has three slaves in contact, released after the restart.
  expect_identical_after_restart("restart_discs", kGlancingDiscs, 35, 30);
}

TEST(Restart, StickContactHistoryIsBitIdentical) {
  // Checkpoint 75 has one stuck slave; another sticks after the restart.
  expect_identical_after_restart("restart_ball", kBallOnPlane, 80, 75);
}

// The penalty's couplings (their facets, a stuck slave's anchor) and
// stored energy come back from a checkpoint.
TEST(Restart, PenaltyContactHistoryIsBitIdentical) {
  expect_identical_after_restart("restart_penalty_discs", with_method(kGlancingDiscs, "penalty"), 35, 30);
  expect_identical_after_restart("restart_penalty_ball", with_method(kBallOnPlane, "penalty"), 80, 75);
}

// Coulomb friction's state comes back: elimination's stick/slip and the
// penalty's slipping anchors (the discs slide along each other, μ = 0.3).
TEST(Restart, CoulombContactHistoryIsBitIdentical) {
  std::string coulomb = kGlancingDiscs;
  const std::size_t at = coulomb.find("kind = \"frictionless\"");
  ASSERT_NE(at, std::string::npos);
  coulomb.replace(at, std::string("kind = \"frictionless\"").size(), "kind = \"coulomb\"\nfriction = 0.3");
  expect_identical_after_restart("restart_coulomb_discs", coulomb, 35, 30);
  expect_identical_after_restart("restart_penalty_coulomb_discs", with_method(coulomb, "penalty"), 35, 30);
}

// The multipliers' active set comes back as elimination's does.
TEST(Restart, LagrangeContactHistoryIsBitIdentical) {
  expect_identical_after_restart("restart_lagrange_discs", with_method(kGlancingDiscs, "lagrange"), 35, 30);
}

// A free rigid body's motion (centre, velocity, rotation, spin) comes back
// from a checkpoint: the big disc of kGlancingDiscs, free and spinning,
// hit by the small one.
TEST(Restart, FreeRigidBodyHistoryIsBitIdentical) {
  std::string scenario = kGlancingDiscs;
  const std::string big = "name = \"big\"\n";
  scenario.replace(scenario.find(big), big.size(), big + "rigid = true\nfree = true\nangular_velocity = 3.0\n");
  expect_identical_after_restart("restart_free_body", scenario, 35, 30);
}

// With impacts located, a run restarted from the checkpoint of a step cut
// short at an impact goes on off the grid of Δt exactly as the run that
// wrote it.
TEST(Restart, LocatedImpactHistoryIsBitIdentical) {
  const std::string scenario = glancing_spheres(2, "frictionless", 0.05) +
                               "[active_set]\nscheme = \"persistent\"\nlocate_impacts = true\n"
                               "[output]\nvtu_every = 0\ncheckpoint_every = 1\ncheckpoint_keep = 0\n";
  const auto dir = scratch("restart_located_probe");
  write_file(dir / "s.toml", scenario);
  ASSERT_EQ(run_cli("run s.toml -q -o probe", dir).exit_code, 0);
  // The first step that ends off the grid of Δt = 5e-4 s: a cut step.
  int cut = -1;
  for (const StepRow& r : step_rows(dir / "probe/steps.csv"))
    if (cut < 0 && std::abs(r.time - std::round(r.time / 5e-4) * 5e-4) > 1e-9) cut = r.step;
  ASSERT_GT(cut, 0) << "no step was cut short at an impact";
  expect_identical_after_restart("restart_located", scenario, cut + 3, cut);
}

// With releases located, the steps ahead of a lift-off are shortened from
// the rate at which each slave's force fell over the last two steps: a run
// restarted within such a stretch needs those forces and step lengths
// from its checkpoint to go on exactly as the run that wrote it.
TEST(Restart, LocatedReleaseHistoryIsBitIdentical) {
  const std::string scenario = block_on_plane("stick", 0.06) +
                               "[active_set]\nscheme = \"persistent\"\nlocate_releases = true\n"
                               "[output]\nvtu_every = 0\ncheckpoint_every = 1\ncheckpoint_keep = 0\n";
  const auto dir = scratch("restart_released_probe");
  write_file(dir / "s.toml", scenario);
  ASSERT_EQ(run_cli("run s.toml -q -o probe", dir).exit_code, 0);
  // The second step in a row shorter than Δt = 1 ms: one whose length came
  // from the forces of the steps before it.
  int shortened = -1, in_a_row = 0;
  for (const StepRow& r : step_rows(dir / "probe/steps.csv")) {
    in_a_row = r.dt > 0.0 && r.dt < 0.999e-3 ? in_a_row + 1 : 0;
    if (shortened < 0 && in_a_row == 2) shortened = r.step;
  }
  ASSERT_GT(shortened, 0) << "no step was shortened ahead of a lift-off";
  expect_identical_after_restart("restart_released", scenario, shortened + 3, shortened);
}

// A slave whose push-out was given up stays held after a restart
// (contact::Constraint::hold is in the checkpoint): read back as a plain
// held slave, it would be pushed again at the next step and given up again.
TEST(Restart, GivenUpPushOutHistoryIsBitIdentical) {
  const std::string scenario =
      block_into_a_flank(2, "paper", 4e-3, 0.1) + "[output]\nvtu_every = 0\ncheckpoint_every = 10\n";
  expect_identical_after_restart("restart_given_up", scenario, 12, 10);
}

// The same block 1 cm deep at 1 m/s: its first slave is pushed out over
// steps 5 to 12, 1.25 mm a step (ActiveSet::push_target). Restarted from
// step 8, half-way out, it is pushed on from where it was held.
TEST(Restart, SpreadPushOutHistoryIsBitIdentical) {
  const std::string scenario =
      block_into_a_flank(2, "paper", 1e-2, 1.0) + "[output]\nvtu_every = 0\ncheckpoint_every = 8\n";
  expect_identical_after_restart("restart_spread_push", scenario, 14, 8);
}

/// Restarts from step 10 of kGlancingDiscs with `other` (kGlancingDiscs
/// with `from` replaced by `to`): refused with one line containing `what`.
void expect_refused_naming(const std::string& name, const std::string& from, const std::string& to,
                           const std::string& what) {
  const auto dir = scratch("restart_refused_" + name);
  write_file(dir / "s.toml", kGlancingDiscs);
  std::string other = kGlancingDiscs;
  ASSERT_NE(other.find(from), std::string::npos) << from;
  other.replace(other.find(from), from.size(), to);
  write_file(dir / "other.toml", other);
  ASSERT_EQ(run_cli("run s.toml -q -o a --steps 10", dir).exit_code, 0);
  ASSERT_EQ(run_cli("check other.toml", dir).exit_code, 0);
  const CliResult r = run_cli("run other.toml -q -o b --restart a/checkpoints/ckpt_000010.bin", dir);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_THAT(r.err, HasSubstr("ckpt_000010.bin: bad checkpoint: written by another scenario: " + what));
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_FALSE(fs::exists(dir / "b")) << "a refused restart wrote output";
}

// A refused checkpoint names the setting that differs (issue 11).
TEST(Restart, RefusalNamesAChangedTimeStep) {
  expect_refused_naming("step", "step = 5e-4", "step = 1e-3",
                        "the checkpoint was written with [time] step = 0.0005, this scenario has 0.001");
}

TEST(Restart, RefusalNamesAChangedMaterial) {
  expect_refused_naming("material", "young = 1.0e6", "young = 2.0e6",
                        "the checkpoint was written with body 'small' material = model svk, young 1000000 Pa, "
                        "poisson 0.3, density 1000 kg/m³, this scenario has model svk, young 2000000 Pa, poisson "
                        "0.3, density 1000 kg/m³");
}

TEST(Restart, RefusalNamesAChangedMaterialModel) {
  expect_refused_naming("model", "young = 1.0e6", "model = \"neo_hookean\"\nyoung = 1.0e6",
                        "the checkpoint was written with body 'small' material = model svk, young 1000000 Pa, "
                        "poisson 0.3, density 1000 kg/m³, this scenario has model neo_hookean, young 1000000 Pa, "
                        "poisson 0.3, density 1000 kg/m³");
}

TEST(Restart, RefusalNamesAChangedContactKind) {
  expect_refused_naming("kind", "kind = \"frictionless\"", "kind = \"stick\"",
                        "the checkpoint was written with contact[0] kind = frictionless, this scenario has stick");
}

TEST(Restart, RefusalNamesAChangedCoulombKindOrFriction) {
  expect_refused_naming("coulomb", "kind = \"frictionless\"", "kind = \"coulomb\"\nfriction = 0.3",
                        "the checkpoint was written with contact[0] kind = frictionless, this scenario has coulomb");
  const auto dir = scratch("restart_refused_friction");
  write_file(dir / "s.toml", kGlancingDiscs);
  const std::string coulomb = " --set 'contact.0.kind=\"coulomb\"' --set contact.0.friction=";
  ASSERT_EQ(run_cli("run s.toml -q -o a --steps 10" + coulomb + "0.3", dir).exit_code, 0);
  const CliResult r = run_cli("run s.toml -q -o b --restart a/checkpoints/ckpt_000010.bin" + coulomb + "0.5", dir);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_THAT(r.err, HasSubstr("written by another scenario: the checkpoint was written with contact[0] friction = "
                               "0.3, this scenario has 0.5"));
  EXPECT_FALSE(fs::exists(dir / "b")) << "a refused restart wrote output";
}

// The contact scheme changes the trajectory: a restart must be given the
// same [active_set] (here by `--set`) as the run it continues.
TEST(Restart, RefusalNamesAChangedContactScheme) {
  const auto dir = scratch("restart_refused_scheme");
  write_file(dir / "s.toml", kGlancingDiscs);
  const std::string paper = " --set active_set.scheme=paper";
  ASSERT_EQ(run_cli("run s.toml -q -o a --steps 10" + paper, dir).exit_code, 0);
  const CliResult r = run_cli("run s.toml -q -o b --restart a/checkpoints/ckpt_000010.bin", dir);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_THAT(r.err, HasSubstr("written by another scenario: the checkpoint was written with [active_set] scheme = "
                               "paper, this scenario has persistent"));
  EXPECT_FALSE(fs::exists(dir / "b")) << "a refused restart wrote output";
  const CliResult same = run_cli("run s.toml -q -o c --restart a/checkpoints/ckpt_000010.bin" + paper, dir);
  EXPECT_EQ(same.exit_code, 0) << same.err;
}

TEST(Restart, RefusalNamesChangedNodeCoordinates) {
  // Only the nodes move: the cells, their volumes and all else are equal.
  expect_refused_naming("nodes", "name = \"big\"\n", "name = \"big\"\ntranslate = [0.0, -0.001]\n",
                        "body 'big' node coordinates differ");
}

TEST(Restart, RefusesACheckpointOfAnotherThicknessOrSolverPath) {
  // Neither changes a 2D trajectory's displacements by much, but both
  // change its history: the thickness scales every energy, the linear
  // solver moves the iterates at round-off level.
  const auto dir = scratch("restart_other_thickness");
  write_file(dir / "s.toml", kGlancingDiscs);
  std::string thick = kGlancingDiscs;
  thick.replace(thick.find("[body.material]"), 15, "thickness = 0.5\n[body.material]");
  write_file(dir / "thick.toml", thick);
  write_file(dir / "full.toml", kGlancingDiscs + "[solver]\nmodified_newton = false\n");
  write_file(dir / "direct.toml", kGlancingDiscs + "[solver]\nmethod = \"direct\"\n");
  ASSERT_EQ(run_cli("run s.toml -q -o a --steps 10", dir).exit_code, 0);
  for (const auto& [other, what] :
       {std::pair<std::string, std::string>{"thick.toml", "body 'small' thickness = 1, this scenario has 0.5"},
        {"full.toml", "[solver] modified_newton = true, this scenario has false"},
        {"direct.toml", "[solver] method = krylov, this scenario has direct"}}) {
    ASSERT_EQ(run_cli("check " + other, dir).exit_code, 0) << other;
    const CliResult r = run_cli("run " + other + " -q -o b --restart a/checkpoints/ckpt_000010.bin", dir);
    EXPECT_EQ(r.exit_code, 1) << other << ": " << r.err;
    EXPECT_THAT(r.err, HasSubstr("written by another scenario: the checkpoint was written with " + what)) << other;
  }
}

TEST(Restart, RefusesATruncatedCheckpoint) {
  const auto dir = scratch("restart_truncated");
  write_file(dir / "s.toml", kGlancingDiscs);
  ASSERT_EQ(run_cli("run s.toml -q -o a --steps 10", dir).exit_code, 0);
  const std::string bytes = slurp(dir / "a/checkpoints/ckpt_000010.bin");
  write_file(dir / "cut.bin", bytes.substr(0, bytes.size() / 2));
  const CliResult r = run_cli("run s.toml -q -o a --restart cut.bin", dir);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_THAT(r.err, HasSubstr("cut.bin: bad checkpoint"));
}

/// Starts `conserve ARGS...` in `dir` with its output discarded (its
/// standard error into `err`, in dir, if given); returns the child's
/// process id.
pid_t spawn_cli(const fs::path& dir, const std::vector<std::string>& args, const char* err = nullptr) {
  const pid_t pid = fork();
  if (pid == 0) {
    if (chdir(dir.c_str()) != 0) _exit(127);
    const int null = open("/dev/null", O_WRONLY);
    dup2(null, 1);
    dup2(err ? open(err, O_WRONLY | O_CREAT | O_TRUNC, 0644) : null, 2);
    std::vector<char*> argv{const_cast<char*>(CONSERVE_BINARY)};
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(CONSERVE_BINARY, argv.data());
    _exit(127);
  }
  return pid;
}

TEST(Restart, KilledRunContinuesBitIdentically) {
  // SIGKILL while the run writes VTU files, history rows and checkpoints:
  // whatever it left is whole (no .tmp file, no truncated VTU, no torn
  // history row), and the newest checkpoint continues it to the same
  // history, step sizes and time series as the run that was never killed.
  const auto dir = scratch("restart_killed");
  std::string scenario = kBallOnPlane;
  scenario.replace(scenario.find("vtu_every = 0"), 13, "vtu_every = 3");
  scenario.replace(scenario.find("checkpoint_every = 25"), 21, "checkpoint_every = 7\ncheckpoint_keep = 0");
  write_file(dir / "s.toml", scenario);
  const CliResult full = run_cli("run s.toml -q -o full", dir);
  ASSERT_EQ(full.exit_code, 0) << full.err;
  const pid_t pid = spawn_cli(dir, {"run", "s.toml", "-q", "-o", "part"});
  ASSERT_GT(pid, 0);
  int status = 0;
  bool exited = false;
  while (!fs::exists(dir / "part/checkpoints/ckpt_000035.bin") && !exited) {
    exited = waitpid(pid, &status, WNOHANG) == pid;
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  if (!exited) {
    kill(pid, SIGKILL);
    ASSERT_EQ(waitpid(pid, &status, 0), pid);
  }
  ASSERT_TRUE(WIFSIGNALED(status)) << "the run ended before it could be killed; give it more steps";
  // What the killed run left behind is whole.
  int newest = -1, vtus = 0;
  for (const auto& f : fs::recursive_directory_iterator(dir / "part")) {
    EXPECT_NE(f.path().extension(), ".tmp") << f.path();
    const std::string name = f.path().filename().string();
    if (f.path().extension() == ".vtu") {
      ++vtus;
      const std::string text = slurp(f.path());
      EXPECT_TRUE(text.ends_with("</VTKFile>\n")) << f.path() << " is truncated";
    }
    if (name.starts_with("ckpt_")) newest = std::max(newest, std::stoi(name.substr(5, 6)));
  }
  const std::string history = slurp(dir / "part/history.csv");
  ASSERT_FALSE(history.empty());
  EXPECT_EQ(history.back(), '\n') << "a torn history row";
  const std::string header = history.substr(0, history.find('\n'));
  std::istringstream rows(history);
  int lines = 0;
  for (std::string row; std::getline(rows, row); ++lines)
    EXPECT_EQ(std::count(row.begin(), row.end(), ','), std::count(header.begin(), header.end(), ',')) << row;
  const int killed_at = lines - 2;  // the last step with a history row
  ASSERT_GE(newest, 35);
  std::printf("[ measured ] killed after step %d with %d VTU files; restarting from checkpoint %d\n", killed_at, vtus,
              newest);
  const std::string ckpt = fmt::format("part/checkpoints/ckpt_{:06d}.bin", newest);
  const CliResult rest = run_cli("run s.toml -q -o part --restart " + ckpt, dir);
  ASSERT_EQ(rest.exit_code, 0) << rest.err;
  EXPECT_TRUE(slurp(dir / "full/history.csv") == slurp(dir / "part/history.csv")) << "history.csv differs";
  EXPECT_TRUE(slurp(dir / "full/steps.csv") == slurp(dir / "part/steps.csv")) << "steps.csv differs";
  EXPECT_EQ(slurp(dir / "full/solution.pvd"), slurp(dir / "part/solution.pvd"));
}

// Writing checkpoints does not change the run (issue 52): the kept
// tangent and the solver's state are set again from the checkpoint rather
// than dropped, so a run with a checkpoint every 10 steps writes the same
// history, byte for byte, as one without.
TEST(Restart, CheckpointsDoNotChangeTheRun) {
  const auto dir = scratch("restart_no_change");
  const std::string base = ball_on_plane("stick", 0.12) + "[output]\nvtu_every = 0\n";
  write_file(dir / "plain.toml", base);
  write_file(dir / "checkpointed.toml", base + "checkpoint_every = 10\ncheckpoint_keep = 0\n");
  ASSERT_EQ(run_cli("run plain.toml -q -o plain", dir).exit_code, 0);
  ASSERT_EQ(run_cli("run checkpointed.toml -q -o checkpointed", dir).exit_code, 0);
  ASSERT_TRUE(fs::exists(dir / "checkpointed/checkpoints/ckpt_000120.bin"));
  EXPECT_TRUE(slurp(dir / "plain/history.csv") == slurp(dir / "checkpointed/history.csv")) << "history.csv differs";
  EXPECT_TRUE(slurp(dir / "plain/steps.csv") == slurp(dir / "checkpointed/steps.csv")) << "steps.csv differs";
}

/// Starts `args` in `dir`, sends `signal` once history.csv has `rows` rows,
/// and returns the process's exit status.
int signalled_run(const fs::path& dir, const std::vector<std::string>& args, const fs::path& history, int rows,
                  int signal) {
  const pid_t pid = spawn_cli(dir, args, "err.txt");
  int status = 0;
  bool exited = false;
  const auto lines = [&] {
    const std::string text = fs::exists(history) ? slurp(history) : std::string();
    return static_cast<int>(std::count(text.begin(), text.end(), '\n'));
  };
  while (lines() < rows + 1 && !exited) {
    exited = waitpid(pid, &status, WNOHANG) == pid;
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  if (!exited) {
    kill(pid, signal);
    waitpid(pid, &status, 0);
  }
  return status;
}

// SIGTERM (a batch system's time limit) ends the run after the step under
// way with a checkpoint, summary.json, one line and exit code 5; the
// restart from that checkpoint writes the uninterrupted run's history.
TEST(Restart, SigtermWritesACheckpointAndTheRestartRepeatsTheRun) {
  const auto dir = scratch("restart_sigterm");
  write_file(dir / "s.toml", ball_on_plane("stick", 0.3) + "[output]\nvtu_every = 0\n");
  ASSERT_EQ(run_cli("run s.toml -q -o full", dir).exit_code, 0);
  const int status = signalled_run(dir, {"run", "s.toml", "-q", "-o", "part"}, dir / "part/history.csv", 40, SIGTERM);
  ASSERT_TRUE(WIFEXITED(status)) << "ended by a signal";
  ASSERT_EQ(WEXITSTATUS(status), 5) << "the run ended before the signal; give it more steps";
  const std::string err = slurp(dir / "err.txt");
  EXPECT_THAT(err, HasSubstr("conserve: stopped by SIGTERM at t = "));
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  const std::string summary = slurp(dir / "part/summary.json");
  EXPECT_THAT(summary, HasSubstr("\"stopped\": \"SIGTERM\""));
  const std::string at = "--restart ";
  const std::string ckpt = err.substr(err.find(at) + at.size(), err.find(')', err.find(at)) - err.find(at) - at.size());
  ASSERT_TRUE(fs::exists(dir / ckpt)) << ckpt;
  std::printf("[ measured ] SIGTERM: the run stopped with %s\n", ckpt.c_str());
  const CliResult rest = run_cli("run s.toml -q -o part --restart " + ckpt, dir);
  ASSERT_EQ(rest.exit_code, 0) << rest.err;
  EXPECT_TRUE(slurp(dir / "full/history.csv") == slurp(dir / "part/history.csv")) << "history.csv differs";
  EXPECT_TRUE(slurp(dir / "full/steps.csv") == slurp(dir / "part/steps.csv")) << "steps.csv differs";
}

TEST(Restart, Sigusr1StopsTheRunLikeSigterm) {
  const auto dir = scratch("restart_sigusr1");
  write_file(dir / "s.toml", ball_on_plane("frictionless", 0.3) + "[output]\nvtu_every = 0\n");
  const int status = signalled_run(dir, {"run", "s.toml", "-q", "-o", "out"}, dir / "out/history.csv", 20, SIGUSR1);
  ASSERT_TRUE(WIFEXITED(status));
  ASSERT_EQ(WEXITSTATUS(status), 5);
  EXPECT_THAT(slurp(dir / "err.txt"), HasSubstr("conserve: stopped by SIGUSR1"));
  EXPECT_THAT(slurp(dir / "out/summary.json"), HasSubstr("\"stopped\": \"SIGUSR1\""));
}

/// The checkpoint files in DIR/checkpoints, by name.
std::set<std::string> checkpoint_files(const fs::path& dir) {
  std::set<std::string> names;
  for (const auto& f : fs::directory_iterator(dir / "checkpoints")) names.insert(f.path().filename().string());
  return names;
}

TEST(Restart, KeepsOnlyTheNewestCheckpoints) {
  const auto dir = scratch("restart_keep");
  write_file(dir / "two.toml", kGlancingDiscs + "checkpoint_keep = 2\n");
  write_file(dir / "all.toml", kGlancingDiscs + "checkpoint_keep = 0\n");
  ASSERT_EQ(run_cli("run two.toml -q -o two --steps 45", dir).exit_code, 0);
  EXPECT_EQ(checkpoint_files(dir / "two"), (std::set<std::string>{"ckpt_000030.bin", "ckpt_000040.bin"}));
  ASSERT_EQ(run_cli("run all.toml -q -o all --steps 45", dir).exit_code, 0);
  EXPECT_EQ(checkpoint_files(dir / "all").size(), 4u);
  // A restart from an older checkpoint prunes those before the step it
  // reaches, and the later ones of the earlier run are gone (the folder
  // holds one run: simulation/output_folder.hpp); an unrelated file in
  // the folder is never touched.
  write_file(dir / "two/checkpoints/notes.txt", "mine");
  ASSERT_EQ(run_cli("run two.toml -q -o two --steps 5 --restart two/checkpoints/ckpt_000030.bin", dir).exit_code, 0);
  EXPECT_EQ(checkpoint_files(dir / "two"), (std::set<std::string>{"ckpt_000030.bin", "notes.txt"}));
  ASSERT_EQ(run_cli("run two.toml -q -o two --steps 20 --restart two/checkpoints/ckpt_000030.bin", dir).exit_code, 0);
  EXPECT_EQ(checkpoint_files(dir / "two"), (std::set<std::string>{"ckpt_000040.bin", "ckpt_000050.bin", "notes.txt"}));
}

}  // namespace
}  // namespace conserve::test
