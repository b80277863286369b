// [body.mesh] reorder (issue 55): a file's nodes renumbered in reverse
// Cuthill–McKee order, as a generated mesh's, are the same nodes and
// cells with a narrower band; without it the file's numbering is kept.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <string>

#include "io/scenario.hpp"
#include "simulation/setup.hpp"

namespace conserve::simulation {
namespace {

std::string cube(const std::string& mesh_keys) {
  return "[time]\nstep = 0.01\nend = 0.1\n[[body]]\nname = \"a\"\n"
         "[body.material]\nyoung = 1e6\npoisson = 0.3\ndensity = 1000\n"
         "[body.mesh]\nfile = \"" +
         std::string(CONSERVE_SOURCE_DIR) + "/tests/data/msh/cube_ascii.msh\"\n" + mesh_keys;
}

/// The largest difference of two node numbers in one cell.
int bandwidth(const model::Model<3>& m) {
  int band = 0;
  for (Eigen::Index c = 0; c < m.cells.cols(); ++c)
    band = std::max(band, m.cells.col(c).maxCoeff() - m.cells.col(c).minCoeff());
  return band;
}

/// The columns of X sorted lexicographically (the nodes as a set).
Eigen::MatrixXd sorted_columns(Eigen::MatrixXd X) {
  std::vector<Eigen::VectorXd> cols;
  for (Eigen::Index j = 0; j < X.cols(); ++j) cols.emplace_back(X.col(j));
  std::sort(cols.begin(), cols.end(), [](const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
    return std::lexicographical_compare(a.data(), a.data() + a.size(), b.data(), b.data() + b.size());
  });
  for (Eigen::Index j = 0; j < X.cols(); ++j) X.col(j) = cols[static_cast<std::size_t>(j)];
  return X;
}

TEST(Reorder, AFileMeshRenumberedIsTheSameMeshWithANarrowerBand) {
  const Problem<3> kept = setup<3>(io::parse_scenario(cube(""), "case.toml"));
  const Problem<3> reordered = setup<3>(io::parse_scenario(cube("reorder = true\n"), "case.toml"));
  ASSERT_EQ(kept.model.num_nodes(), reordered.model.num_nodes());
  ASSERT_EQ(kept.model.num_cells(), reordered.model.num_cells());
  EXPECT_NE(kept.model.X, reordered.model.X);  // renumbered
  EXPECT_EQ(sorted_columns(kept.model.X), sorted_columns(reordered.model.X));
  double v_kept = 0.0, v_reordered = 0.0;
  for (const auto& g : kept.model.geometry) v_kept += g.volume;
  for (const auto& g : reordered.model.geometry) v_reordered += g.volume;
  EXPECT_NEAR(v_reordered, v_kept, 1e-14 * v_kept);
  std::printf("[ measured ] bandwidth of the file's numbering %d, reordered %d\n", bandwidth(kept.model),
              bandwidth(reordered.model));
  EXPECT_LT(bandwidth(reordered.model), bandwidth(kept.model));
  // The file's groups follow their nodes.
  EXPECT_EQ(kept.model.bodies[0].facet_groups.size(), reordered.model.bodies[0].facet_groups.size());
}

}  // namespace
}  // namespace conserve::simulation
