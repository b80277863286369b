// Penetration both ways (issue 44). Node-to-segment contact holds the
// slave's nodes; with the coarser body as the slave, the master's nodes
// sink into its facets between them. The report must say so: a fine disc
// hitting a coarse block that is the slave ends with disc nodes 1.4 mm
// inside the block, which history.csv (master_penetration,
// max_penetration), summary.json and the end-of-run line show; the same
// impact with the disc as the slave has none. `check` and `run` warn that
// the slave is the coarser surface.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>

#include "io/history_writer.hpp"
#include "support/cli.hpp"
#include "support/files.hpp"

namespace conserve::test {
namespace {

using ::testing::HasSubstr;

/// A disc (size 0.01 m) at 0.5 m/s into a block (size 0.1 m), plane
/// strain; `slave` and `master` are the contact's surfaces.
std::string disc_into_block(const std::string& slave, const std::string& master) {
  return R"(dimension = 2
[time]
step = 0.001
end = 0.05
[output]
vtu_every = 0
[[body]]
name = "disc"
translate = [-0.31, 0.0]
velocity = [0.5, 0.0]
[body.material]
young = 1.0e6
poisson = 0.3
density = 1000.0
[body.mesh]
generator = "disc"
radius = 0.1
size = 0.01
[[body]]
name = "block"
[body.material]
young = 1.0e6
poisson = 0.3
density = 1000.0
[body.mesh]
generator = "rectangle"
lx = 0.4
ly = 0.4
size = 0.1
[[contact]]
slave = ")" + slave + "\"\nmaster = \"" +
         master + "\"\nkind = \"frictionless\"\n";
}

struct Report {
  CliResult cli;
  double slave = 0.0, master = 0.0, deepest = 0.0;  ///< summary.json
  double history_master = 0.0;                      ///< largest master_penetration in history.csv
};

Report run_case(const std::string& name, const std::string& slave, const std::string& master) {
  const auto dir = scratch(name);
  write_file(dir / "s.toml", disc_into_block(slave, master));
  Report r;
  r.cli = run_cli("run s.toml -q -o out", dir);
  if (r.cli.exit_code != 0) return r;
  const auto j = nlohmann::json::parse(slurp(dir / "out/summary.json"));
  r.slave = j.at("slave_penetration").get<double>();
  r.master = j.at("master_penetration").get<double>();
  r.deepest = j.at("max_penetration").get<double>();
  const auto h = io::read_history(dir / "out/history.csv");
  const auto column = h.column("master_penetration"), deepest = h.column("max_penetration");
  for (std::size_t i = 0; i < column.size(); ++i) {
    r.history_master = std::max(r.history_master, column[i]);
    EXPECT_GE(deepest[i], column[i]) << "row " << i;
  }
  return r;
}

TEST(Penetration, MasterNodesInsideACoarseSlaveAreReported) {
  const Report coarse = run_case("penetration_coarse_slave", "block:xmin", "disc:circle");
  ASSERT_EQ(coarse.cli.exit_code, 0) << coarse.cli.err;
  const Report fine = run_case("penetration_fine_slave", "disc:circle", "block:xmin");
  ASSERT_EQ(fine.cli.exit_code, 0) << fine.cli.err;
  std::printf("[ measured ] disc into block: coarse slave, master nodes %.3e m inside (slaves %.1e m); fine slave, "
              "%.1e m (slaves %.1e m)\n",
              coarse.master, coarse.slave, fine.master, fine.slave);
  EXPECT_GT(coarse.master, 1e-3);  // 1.4 mm, 1.4 % of the disc's radius
  EXPECT_EQ(coarse.deepest, coarse.master);
  EXPECT_EQ(coarse.history_master, coarse.master);
  EXPECT_LT(coarse.slave, 1e-12);  // the slaves are held
  EXPECT_THAT(coarse.cli.out, HasSubstr(fmt::format("deepest penetration {:.3e} m", coarse.master)));
  EXPECT_THAT(coarse.cli.out, HasSubstr(fmt::format("master nodes behind slave facets {:.3e} m", coarse.master)));
  EXPECT_THAT(coarse.cli.err, HasSubstr("conserve: warning: s.toml:"));
  EXPECT_THAT(coarse.cli.err,
              HasSubstr(": contact[0].slave: the slave surface 'block:xmin' is coarser than its master 'disc:circle'"));
  EXPECT_LT(fine.master, 1e-12);
  EXPECT_LT(fine.deepest, 1e-12);
  EXPECT_EQ(fine.cli.err, "");  // no warning
}

}  // namespace
}  // namespace conserve::test
