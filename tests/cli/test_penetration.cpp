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
slave = ")" +
         slave + "\"\nmaster = \"" + master + "\"\nkind = \"frictionless\"\n";
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
  std::printf(
      "[ measured ] disc into block: coarse slave, master nodes %.3e m inside (slaves %.1e m); fine slave, "
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

// The summary says which pairs held contact, and each body's penetration
// at the end both ways: what one body's nodes have behind the other's
// facets is what the other has behind its own.
TEST(Penetration, TheSummaryNamesThePairsInContactAndEachBodysPenetrationBothWays) {
  const auto dir = scratch("penetration_per_body");
  write_file(dir / "s.toml", disc_into_block("block:xmin", "disc:circle"));
  const CliResult check = run_cli("check s.toml", dir);
  ASSERT_EQ(check.exit_code, 0) << check.err;
  EXPECT_THAT(check.out, HasSubstr("contact: 1 pair(s): 0 self-contact, 0 in two passes, 1 in one\n  block:xmin on "
                                   "disc:circle"));
  const CliResult cli = run_cli("run s.toml -q -o out --set time.end=0.035", dir);  // while pressed
  ASSERT_EQ(cli.exit_code, 0) << cli.err;
  const auto j = nlohmann::json::parse(slurp(dir / "out/summary.json"));
  const auto& pairs = j.at("contact_pairs");
  EXPECT_EQ(pairs.at("count"), 1);
  ASSERT_EQ(pairs.at("active").size(), 1u);
  EXPECT_EQ(pairs.at("active")[0].at("slave"), "block:xmin");
  EXPECT_EQ(pairs.at("active")[0].at("master"), "disc:circle");
  const int steps = pairs.at("active")[0].at("steps").get<int>();
  EXPECT_GT(steps, 5);
  const auto& bodies = j.at("penetration_at_end");
  ASSERT_EQ(bodies.size(), 2u);
  EXPECT_EQ(bodies[0].at("body"), "disc");
  EXPECT_EQ(bodies[1].at("body"), "block");
  const double disc_in = bodies[0].at("nodes_behind").get<double>(),
               block_in = bodies[1].at("nodes_behind").get<double>();
  std::printf(
      "[ measured ] coarse slave at the end: disc nodes %.3e m behind block facets, block nodes %.3e m behind "
      "disc facets; %d steps in contact\n",
      disc_in, block_in, steps);
  EXPECT_GT(disc_in, 1e-4);    // the coarse slave's facets sag between its nodes into the disc
  EXPECT_LT(block_in, 1e-12);  // its nodes are held
  EXPECT_EQ(bodies[0].at("behind_its_facets").get<double>(), block_in);
  EXPECT_EQ(bodies[1].at("behind_its_facets").get<double>(), disc_in);
  EXPECT_THAT(cli.out, HasSubstr(fmt::format("contact: 1 of the 1 pairs searched (each pass counted) held contact: "
                                             "block:xmin on disc:circle ({} steps)",
                                             steps)));
  EXPECT_THAT(cli.out, HasSubstr(fmt::format("disc {:.3e} / {:.3e} m", disc_in, block_in)));
}

}  // namespace
}  // namespace conserve::test
