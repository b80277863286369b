// Issue 11, "no silently wrong step": a step accepted only on its residual,
// inputs whose scales double precision cannot hold refused at check, the
// end-of-step contact geometry and det F in the history, drifts measured
// against scales that are never zero, inverted cells refused.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "io/history_writer.hpp"
#include "support/cli.hpp"
#include "support/stretched_box.hpp"
#include "support/contact_scenarios.hpp"

namespace conserve::test {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

/// A small spinning, moving box of Young's modulus `young`, density `density`.
std::string moving_box(const std::string& young, const std::string& density = "1000.0") {
  return R"(dimension = 3
[time]
step = 0.01
end = 0.03
[output]
vtu_every = 0
[[body]]
name = "box"
velocity = [1.0, 0.5, 0.0]
angular_velocity = [0.0, 0.0, 2.0]
[body.material]
young = )" + young + R"(
poisson = 0.3
density = )" + density + R"(
[body.mesh]
generator = "box"
lx = 0.2
ly = 0.2
lz = 0.2
size = 0.1
)";
}

/// stderr is one line, the program's error line.
void expect_one_line(const CliResult& r) {
  ASSERT_FALSE(r.err.empty());
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;
}

// young = 1e30: the internal forces cannot be computed to better than
// ~1e14 N while the inertia is ~1 N; every step used to end after one
// iteration on a small increment, residual 6e12 N, exit 0.
TEST(Trust, StepsOfAModelTooStiffForDoublePrecisionFail) {
  const auto dir = scratch("trust_too_stiff");
  write_file(dir / "s.toml", moving_box("1.0e30"));
  const CliResult r = run_cli("run s.toml -q -o out", dir);
  EXPECT_EQ(r.exit_code, 3) << r.out;
  expect_one_line(r);
  EXPECT_THAT(r.err, HasSubstr("round-off floor"));
  EXPECT_THAT(r.err, HasSubstr("too stiff for double precision"));
}

// young = 1e308 or density = 1e308: force scales overflow; refused at check.
TEST(Trust, ScalesDoublePrecisionCannotHoldAreRefusedAtCheck) {
  const auto dir = scratch("trust_scales");
  for (const auto& [young, density, key] :
       {std::tuple{"1.0e308", "1000.0", "material.young"}, std::tuple{"1.0e160", "1000.0", "material.young"},
        std::tuple{"1.0e6", "1.0e308", "material.density"}}) {
    write_file(dir / "s.toml", moving_box(young, density));
    for (const char* command : {"check s.toml", "run s.toml -q -o out"}) {
      const CliResult r = run_cli(command, dir);
      EXPECT_EQ(r.exit_code, 1) << command << " with young " << young << ", density " << density << ": " << r.out;
      expect_one_line(r);
      EXPECT_THAT(r.err, HasSubstr("conserve: error: s.toml:"));
      EXPECT_THAT(r.err, HasSubstr(": body[0].material (body 'box'): "));
      EXPECT_THAT(r.err, HasSubstr(key));
      EXPECT_FALSE(fs::exists(dir / "out"));
    }
  }
}

// The contact columns of the history, and their extremes in the summary
// and the end-of-run line (issue 11: nothing showed a slave behind its
// master).
TEST(Trust, HistoryShowsGapsPenetrationAndDetF) {
  const auto dir = scratch("trust_columns");
  write_file(dir / "s.toml", disc_rolling_on_floor(1e-3, 0.15));
  const CliResult r = run_cli("run s.toml -q -o out", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("deepest penetration"));
  EXPECT_THAT(r.out, HasSubstr("smallest det F"));
  const io::History h = io::read_history(dir / "out/history.csv");
  const auto active = h.column("active_contacts"), min_gap = h.column("min_active_gap"),
             max_gap = h.column("max_active_gap"), penetration = h.column("slave_penetration"),
             master = h.column("master_penetration"), deepest = h.column("max_penetration"),
             det = h.column("min_det_F");
  int contact_rows = 0;
  for (std::size_t i = 0; i < active.size(); ++i) {
    EXPECT_EQ(std::isnan(min_gap[i]), active[i] == 0) << "row " << i;  // empty when nothing is active
    EXPECT_EQ(std::isnan(max_gap[i]), active[i] == 0) << "row " << i;
    if (active[i] > 0) {
      ++contact_rows;
      EXPECT_LE(min_gap[i], max_gap[i]);
      EXPECT_GE(min_gap[i], -1e-12);
    }
    EXPECT_GE(penetration[i], 0.0);
    EXPECT_LE(penetration[i], 1e-12 * 5.0);  // the model is about 5 m across
    EXPECT_GE(master[i], 0.0);
    EXPECT_EQ(deepest[i], std::max(penetration[i], master[i])) << "row " << i;
    EXPECT_GT(det[i], 0.0);
    EXPECT_LT(det[i], 1.5);
  }
  EXPECT_GT(contact_rows, 10);
  const auto j = nlohmann::json::parse(slurp(dir / "out/summary.json"));
  EXPECT_LE(j.at("slave_penetration").get<double>(), 1e-12 * 5.0);
  EXPECT_EQ(j.at("max_penetration").get<double>(),
            std::max(j.at("slave_penetration").get<double>(), j.at("master_penetration").get<double>()));
  EXPECT_GE(j.at("min_active_gap").get<double>(), -1e-12);
  EXPECT_GT(j.at("min_det_F").get<double>(), 0.0);
  EXPECT_TRUE(j.at("held").is_number_integer());
}

/// A body dropped from rest under gravity: E0 = L0 = J0 = 0.
const std::string kDroppedFromRest = R"(dimension = 3
[time]
step = 0.01
end = 0.2
[loads]
gravity = [0.0, 0.0, -9.81]
[output]
vtu_every = 0
progress_every = 1
[[body]]
name = "box"
[body.material]
young = 1.0e6
poisson = 0.3
density = 1000.0
[body.mesh]
generator = "box"
lx = 0.2
ly = 0.2
lz = 0.2
size = 0.1
)";

// The drift of a body dropped from rest used to be divided by E(0) = 0
// (progress line 1.19e+09, L drift 1e+282).
TEST(Trust, DriftOfABodyDroppedFromRestIsMeaningful) {
  const auto dir = scratch("trust_drop");
  write_file(dir / "s.toml", kDroppedFromRest);
  const CliResult r = run_cli("run s.toml -o out", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(slurp(dir / "out/summary.json"));
  const double e = j.at("drift").at("E");
  std::printf("[ measured ] dropped from rest, 20 steps: E drift %.2e (E_ref %.3e J), L_x %.2e, L_y %.2e, J_z %.2e\n",
              e, j.at("drift_reference").at("energy").get<double>(), j.at("drift").at("L_x").get<double>(),
              j.at("drift").at("L_y").get<double>(), j.at("drift").at("J_z").get<double>());
  EXPECT_LT(e, 1e-10);
  EXPECT_GT(j.at("drift_reference").at("energy").get<double>(), 0.0);
  // Gravity along z: L_x, L_y and J_z are conserved, the others named with why.
  for (const char* q : {"L_x", "L_y", "J_z"}) EXPECT_LT(j.at("drift").at(q).get<double>(), 1e-10) << q;
  for (const char* q : {"L_z", "J_x", "J_y"}) {
    EXPECT_FALSE(j.at("drift").contains(q)) << q;
    EXPECT_EQ(j.at("not_conserved").at(q), "gravity") << q;
  }
  // The progress line's figure is the same drift.
  const auto last = r.err.rfind("|ΔE|/E_ref = ");
  ASSERT_NE(last, std::string::npos) << r.err;
  EXPECT_LT(std::stod(r.err.substr(last + std::string("|ΔE|/E_ref = ").size())), 1e-10) << r.err;
  const io::History h = io::read_history(dir / "out/history.csv");
  for (double d : h.column("drift_E")) EXPECT_LT(d, 1e-10);
}

/// A head-on impact of two boxes on the x axis: J stays at zero, up to
/// round-off (a cradle used to print J drift 1.96e+03). Full Newton: with
/// kept tangents, conforming faces stop some gaps' runs at the cutback
/// floor, which ones depending on the CPU's libm (this gap on one
/// machine; docs/validation.md, "What is weaker than hoped").
const std::string kHeadOn = R"(dimension = 3
[time]
step = 1e-3
end = 0.03
[solver]
modified_newton = false
[output]
vtu_every = 0
[[body]]
name = "a"
translate = [-0.1005, 0.0, 0.0]
velocity = [1.0, 0.0, 0.0]
[body.material]
young = 1.0e6
poisson = 0.3
density = 1000.0
[body.mesh]
generator = "box"
lx = 0.2
ly = 0.2
lz = 0.2
size = 0.1
[[body]]
name = "b"
translate = [0.1005, 0.0, 0.0]
[body.material]
young = 1.0e6
poisson = 0.3
density = 1000.0
[body.mesh]
generator = "box"
lx = 0.2
ly = 0.2
lz = 0.2
size = 0.1
[[contact]]
slave = "a:xmax"
master = "b:xmin"
kind = "frictionless"
)";

TEST(Trust, AngularMomentumThatStaysZeroHasNoDrift) {
  const auto dir = scratch("trust_head_on");
  write_file(dir / "s.toml", kHeadOn);
  const CliResult r = run_cli("run s.toml -q -o out", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(slurp(dir / "out/summary.json"));
  EXPECT_GT(j.at("activations").get<int>(), 0);
  // Conforming faces: the slaves sit on the master's vertices and border,
  // where the faceted surface's kinks can leave a slave behind a neighbour
  // facet (docs/theory.md, "Limits"); the figure is reported, not bounded.
  const auto& d = j.at("drift");
  std::printf("[ measured ] head-on impact: max penetration %.2e m; drift E %.2e, L (%.2e %.2e %.2e), "
              "J (%.2e %.2e %.2e)\n",
              j.at("max_penetration").get<double>(), d.at("E").get<double>(), d.at("L_x").get<double>(),
              d.at("L_y").get<double>(), d.at("L_z").get<double>(), d.at("J_x").get<double>(), d.at("J_y").get<double>(),
              d.at("J_z").get<double>());
  EXPECT_TRUE(j.at("not_conserved").empty());
  for (const char* q : {"E", "L_x", "L_y", "L_z", "J_x", "J_y", "J_z"}) EXPECT_LT(d.at(q).get<double>(), 1e-10) << q;
}

/// A soft, strongly pre-stretched spinning box: as it rebounds, Saint
/// Venant–Kirchhoff cells are compressed past their limit point and turn
/// inside out at any step size (det F down to −1.4 was seen).
const std::string kInverts = stretched_box("1.3", "5.0e4", 0);

TEST(Trust, AnInvertedCellStopsTheRunNamingBodyCellAndStep) {
  const auto dir = scratch("trust_inverted");
  write_file(dir / "s.toml", kInverts);
  const CliResult r = run_cli("run s.toml -q -o out", dir);
  EXPECT_EQ(r.exit_code, 3) << r.out;
  expect_one_line(r);
  EXPECT_THAT(r.err, HasSubstr("of body 'box' is inverted at the end of step"));
  EXPECT_THAT(r.err, HasSubstr("det F = -"));
  const auto at = r.err.find("is in ");
  ASSERT_NE(at, std::string::npos) << r.err;
  const auto checkpoint = r.err.find("checkpoints/ckpt_", at);
  ASSERT_NE(checkpoint, std::string::npos) << r.err;
  const std::string file = r.err.substr(checkpoint, r.err.find(".bin", checkpoint) + 4 - checkpoint);
  EXPECT_TRUE(fs::exists(dir / "out" / file)) << file;  // the last good state is saved
  const io::History h = io::read_history(dir / "out/history.csv");
  ASSERT_GT(h.rows.size(), 1u);
  for (double d : h.column("min_det_F")) EXPECT_GT(d, 0.0);
}

}  // namespace
}  // namespace conserve::test
