// Rigid bodies end to end: a rigid bare surface moves exactly at its
// velocity (read back from the VTU files), bad rigid or cell-less bodies are
// rejected with one line, and the ball-on-plane example passes `check`.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <vector>

#include "io/history_writer.hpp"
#include "support/vtu_arrays.hpp"
#include "support/cli.hpp"

namespace conserve::test {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using test::vtu_array;

/// A box above a rigid square (9 nodes, listed last) rising at 0.5 m/s.
const std::string kBoxAndRisingSquare =
    slurp(CONSERVE_SOURCE_DIR "/tests/data/scenarios/rigid_box_and_rising_square.toml");

/// A 2D disc above a rigid segment (5 nodes, listed last) moving along x.
const std::string kDiscAndSlidingSegment =
    slurp(CONSERVE_SOURCE_DIR "/tests/data/scenarios/rigid_disc_and_sliding_segment.toml");

/// The Float64 point field `name` of a VTU file (3 values per point).
std::vector<double> point_field(const std::string& xml, const std::string& name) {
  return vtu_array<double>(xml, "Name=\"" + name + "\"");
}

/// (time, file) of every data set of a .pvd file.
std::vector<std::pair<double, std::string>> pvd_entries(const std::string& pvd) {
  std::vector<std::pair<double, std::string>> entries;
  for (auto at = pvd.find("timestep=\""); at != std::string::npos; at = pvd.find("timestep=\"", at + 1)) {
    const double t = std::stod(pvd.substr(at + 10));
    const auto file = pvd.find("file=\"", at) + 6;
    entries.emplace_back(t, pvd.substr(file, pvd.find('"', file) - file));
  }
  return entries;
}

/// In every VTU of `dir`, the last `nodes` points have displacement
/// velocity·t exactly (bit for bit) and velocity `velocity`.
void expect_rigid_motion(const fs::path& dir, int nodes, const std::vector<double>& velocity) {
  const auto entries = pvd_entries(slurp(dir / "solution.pvd"));
  ASSERT_GE(entries.size(), 2u);
  for (const auto& [t, file] : entries) {
    SCOPED_TRACE(file);
    const std::string xml = slurp(dir / file);
    const auto u = point_field(xml, "displacement");
    const auto v = point_field(xml, "velocity");
    ASSERT_EQ(u.size(), v.size());
    ASSERT_GE(u.size(), 3u * nodes);
    for (std::size_t n = u.size() / 3 - nodes; n < u.size() / 3; ++n)
      for (std::size_t k = 0; k < velocity.size(); ++k) {
        const double expected = 0.0 + velocity[k] * t;  // value + rate·t, as prescribed
        EXPECT_EQ(u[3 * n + k], expected) << "node " << n << " component " << k << " t = " << t;
        // v_{n+1} = (2/Δt)(u_{n+1} − u_n) − v_n: exact up to round-off
        EXPECT_NEAR(v[3 * n + k], velocity[k], 1e-12) << "node " << n << " component " << k;
      }
  }
}

TEST(Rigid, BareSquareMovesExactlyAtItsVelocity) {
  const auto dir = scratch("rigid_square");
  write_file(dir / "rigid.toml", kBoxAndRisingSquare);
  const CliResult r = run_cli("run rigid.toml -o result -q --set output.precision=double", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("finished 20 steps"));
  expect_rigid_motion(dir / "result", 9, {0.0, 0.0, 0.5});
  const io::History h = io::read_history(dir / "result/history.csv");
  ASSERT_EQ(h.rows.size(), 21u);
  EXPECT_LT(h.column("L_z").back(), 0.0);  // the box falls; the massless square adds no momentum
}

TEST(Rigid, BareSegmentMovesExactlyAtItsVelocity2d) {
  const auto dir = scratch("rigid_segment");
  write_file(dir / "rigid.toml", kDiscAndSlidingSegment);
  const CliResult r = run_cli("run rigid.toml -o result -q --set output.precision=double", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  expect_rigid_motion(dir / "result", 5, {0.25, 0.0});
}

TEST(Rigid, CheckCountsTheRigidNodesAsPrescribedAndMassless) {
  const auto dir = scratch("rigid_check");
  write_file(dir / "rigid.toml", kBoxAndRisingSquare);
  const CliResult r = run_cli("check rigid.toml", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("valid. 3D, 2 bodies"));
  EXPECT_THAT(r.out, HasSubstr("(27 prescribed)"));  // 9 nodes × 3
  EXPECT_THAT(r.out, HasSubstr("mass 48 kg"));       // the box only: 0.4 · 0.4 · 0.3 · 1000
}

/// `conserve check` of `scenario` fails with one line containing `what`.
void expect_check_fails(const std::string& name, const std::string& scenario, const std::string& what) {
  const auto dir = scratch(name);
  write_file(dir / "scenario.toml", scenario);
  const CliResult r = run_cli("check scenario.toml", dir);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_THAT(r.err, HasSubstr(what));
}

// A surface load on a group the body's mesh has not, on a rigid body, or
// with both kinds: one line naming the file's line and the key.
TEST(Rigid, BadSurfaceLoadsAreRefusedNamingTheKey) {
  expect_check_fails("load_group", kBoxAndRisingSquare + "[[load]]\nbody = \"box\"\ngroup = \"lid\"\npressure = 1e3\n",
                     "scenario.toml:36: load[0].group: body 'box' has no facet group 'lid' (groups: boundary, xmax");
  expect_check_fails("load_rigid", kBoxAndRisingSquare + "[[load]]\nbody = \"floor\"\npressure = 1e3\n",
                     "load[0].body: body 'floor' is rigid");
  expect_check_fails("load_both",
                     kBoxAndRisingSquare + "[[load]]\nbody = \"box\"\npressure = 1e3\ntraction = [1, 0, 0]\n",
                     "load[0]: has both 'traction' and 'pressure'");
}

TEST(Rigid, DeformableBodyWithACenterIsRejected) {
  expect_check_fails("rigid_center", replaced(kBoxAndRisingSquare, "name = \"box\"\n", "name = \"box\"\ncenter = [0, 0, 0]\n"),
                     "body[0].center: is only allowed on a rigid body");
}

TEST(Rigid, CellLessDeformableBodyIsRejected) {
  const auto text = replaced(replaced(kBoxAndRisingSquare, "rigid = true\n", ""), "[body.mesh]\ngenerator = \"square\"",
                             "[body.material]\nyoung = 1.0e5\npoisson = 0.3\ndensity = 1000.0\n"
                             "[body.mesh]\ngenerator = \"square\"");
  expect_check_fails("rigid_bare_deformable", text,
                     "body[1].mesh.generator (body 'floor'): the mesh has no cells; only a rigid body may be a bare surface");
}

TEST(Rigid, BoundaryOnRigidBodyIsRejected) {
  expect_check_fails("rigid_boundary", kBoxAndRisingSquare + "[[boundary]]\nbody = \"floor\"\ngroup = \"all\"\n",
                     "boundary[0].body: body 'floor' is rigid");
}

TEST(Rigid, BallOnPlaneExamplePassesCheck) {
  const auto example = fs::path(CONSERVE_SOURCE_DIR) / "examples/ball/ball_on_plane.toml";
  const CliResult r = run_cli("check '" + example.string() + "'", scratch("ball_on_plane_check"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("valid. 3D, 2 bodies"));
  EXPECT_THAT(r.out, HasSubstr("(45 prescribed)"));  // the plane: 5 × 3 nodes × 3
}

}  // namespace
}  // namespace conserve::test

namespace conserve::test {
namespace {

// A rigid paddle turning at a prescribed angular velocity hits a
// neo-Hookean disc (frictionless, the default located + persistent
// scheme): the disc's L and J change by exactly the impulses of the
// paddle's reaction (history.csv R_*, M_z: the force and moment the paddle
// applies), its energy by the paddle's work (work:paddle, since t = 0),
// and `total`, which counts that work, is constant.
TEST(Rigid, APaddlesReactionAndWorkAccountForTheDiscsMomentaAndEnergy) {
  const auto dir = scratch("rigid_paddle");
  write_file(dir / "paddle.toml", slurp(CONSERVE_SOURCE_DIR "/tests/data/scenarios/paddle_2d.toml"));
  const CliResult r = run_cli("run paddle.toml -o result -q", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const io::History h = io::read_history(dir / "result/history.csv");
  const auto t = h.column("time"), total = h.column("total"), Jz = h.column("J_z");
  const auto K = h.column("kinetic"), W = h.column("strain"), P = h.column("potential");
  const auto Lx = h.column("L_x:ball"), Ly = h.column("L_y:ball");
  const auto Rx = h.column("R_x:paddle"), Ry = h.column("R_y:paddle"), Mz = h.column("M_z:paddle");
  const auto work = h.column("work:paddle"), active = h.column("active_contacts");
  double impulse_x = 0.0, impulse_y = 0.0, angular = 0.0;
  double L_ref = 0.0, J_ref = 0.0, E_ref = 0.0, L_err = 0.0, J_err = 0.0, E_err = 0.0, total_err = 0.0;
  int contact_steps = 0;
  std::vector<double> E(t.size());
  for (std::size_t n = 0; n < t.size(); ++n) E[n] = K[n] + W[n] + P[n];
  for (std::size_t n = 1; n < t.size(); ++n) {
    const double dt = t[n] - t[n - 1];
    impulse_x += dt * Rx[n], impulse_y += dt * Ry[n], angular += dt * Mz[n];
    L_ref = std::max({L_ref, std::abs(Lx[n]), std::abs(Ly[n])});
    J_ref = std::max(J_ref, std::abs(Jz[n]));
    E_ref = std::max(E_ref, std::abs(E[n]));
    L_err = std::max({L_err, std::abs(Lx[n] - Lx[0] - impulse_x), std::abs(Ly[n] - Ly[0] - impulse_y)});
    J_err = std::max(J_err, std::abs(Jz[n] - Jz[0] - angular));
    E_err = std::max(E_err, std::abs(E[n] - E[0] - work[n]));
    total_err = std::max(total_err, std::abs(total[n] - total[0]));
    contact_steps += active[n] > 0;
  }
  std::printf("[ measured ] paddle hits a disc: L_ball(t) - L_ball(0) - integral R dt %.2e, J %.2e, E - E0 - work %.2e, "
              "total - total0 %.2e (relative to the largest |L|, |J|, E); L_y %.1f -> %.1f kg m/s, E %.1f -> %.1f J, "
              "%d steps in contact\n",
              L_err / L_ref, J_err / J_ref, E_err / E_ref, total_err / E_ref, Ly.front(), Ly.back(), E.front(), E.back(),
              contact_steps);
  const double done = work.back();
  EXPECT_GT(contact_steps, 5);
  EXPECT_GT(Ly.back(), 0.0);        // the disc came down at 1 m/s and leaves upwards
  EXPECT_GT(E.back(), 2.0 * E[0]);  // the paddle did work on it
  EXPECT_GT(done, 0.0);
  EXPECT_LT(L_err, 1e-10 * L_ref);
  EXPECT_LT(J_err, 1e-10 * J_ref);
  EXPECT_LT(E_err, 1e-10 * E_ref);
  EXPECT_LT(total_err, 1e-10 * E_ref);
}

}  // namespace
}  // namespace conserve::test
