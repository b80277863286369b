// How the nodes of a scenario's model split over N ranks: contiguous
// ranges of the meshes' numbering ([solver] partition = "ranges"), and
// PT-Scotch's graph partition (solver/graph_partition.hpp), whose parts
// number a body the ranks share with "graph" (simulation/rank_numbering.hpp).
// Per N: the largest rank's nodes, its ghost nodes (other ranks' nodes
// that share a cell with its own: the columns of its rows that live
// elsewhere, what a matrix product fetches), their ratio, and the edges
// cut. A part of the scaling model (bench/results/scaling_model.md).
//
//   conserve_partition SCENARIO N [N ...]
#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <exception>
#include <vector>

#include "assembly/block_pattern.hpp"
#include "assembly/partition.hpp"
#include "io/scenario.hpp"
#include "simulation/rank_numbering.hpp"
#include "simulation/setup.hpp"
#include "solver/graph_partition.hpp"
#include "solver/ranks.hpp"

namespace {

struct Split {
  long most_nodes = 0, most_ghosts = 0;
  double ghost_ratio = 0.0;  ///< the largest of ghosts / own nodes over the ranks
  long cut = 0;
};

/// Per part: its nodes, and the other parts' nodes adjacent to them.
Split measure(const std::vector<int>& offsets, const std::vector<int>& neighbours, const std::vector<int>& part,
              int parts) {
  std::vector<long> own(static_cast<std::size_t>(parts), 0), ghosts(static_cast<std::size_t>(parts), 0);
  std::vector<int> seen(offsets.size() - 1, -1);  // per node: the last part that counted it as a ghost
  std::vector<std::vector<int>> members(static_cast<std::size_t>(parts));
  for (std::size_t B = 0; B + 1 < offsets.size(); ++B) members[static_cast<std::size_t>(part[B])].push_back(static_cast<int>(B));
  for (int p = 0; p < parts; ++p) {
    own[static_cast<std::size_t>(p)] = static_cast<long>(members[static_cast<std::size_t>(p)].size());
    for (const int B : members[static_cast<std::size_t>(p)])
      for (int q = offsets[B]; q < offsets[B + 1]; ++q) {
        const int A = neighbours[static_cast<std::size_t>(q)];
        if (part[static_cast<std::size_t>(A)] != p && seen[static_cast<std::size_t>(A)] != p)
          seen[static_cast<std::size_t>(A)] = p, ++ghosts[static_cast<std::size_t>(p)];
      }
  }
  Split s;
  s.cut = conserve::solver::edge_cut(offsets, neighbours, part);
  for (int p = 0; p < parts; ++p) {
    s.most_nodes = std::max(s.most_nodes, own[static_cast<std::size_t>(p)]);
    s.most_ghosts = std::max(s.most_ghosts, ghosts[static_cast<std::size_t>(p)]);
    if (own[static_cast<std::size_t>(p)] > 0)
      s.ghost_ratio = std::max(s.ghost_ratio, static_cast<double>(ghosts[static_cast<std::size_t>(p)]) /
                                                  static_cast<double>(own[static_cast<std::size_t>(p)]));
  }
  return s;
}

/// The run's numbering on `parts` ranks with [solver] partition = "graph"
/// (simulation/rank_numbering.hpp): each body's mesh cut out of the
/// model, renumbered where the run would, then the ranks of the nodes.
template <int D>
std::vector<int> graph_numbering(const conserve::io::Scenario& scenario, const conserve::model::Model<D>& model,
                                 int parts, std::vector<int>& offsets, std::vector<int>& neighbours) {
  std::vector<conserve::mesh::Mesh> meshes;
  std::vector<bool> renumber;
  for (std::size_t b = 0; b < model.bodies.size(); ++b) {
    const auto& body = model.bodies[b];
    conserve::mesh::Mesh m;
    m.dim = D;
    m.points = model.X.middleCols(body.first_node, body.num_nodes);
    m.cells = model.cells.middleCols(body.first_cell, body.num_cells).array() - body.first_node;
    meshes.push_back(std::move(m));
    renumber.push_back(!scenario.bodies[b].mesh.generator.empty() || scenario.bodies[b].mesh.reorder);
  }
  const auto n = conserve::simulation::number_for_ranks(meshes, renumber, parts, true);
  Eigen::MatrixXi cells(model.cells.rows(), model.cells.cols());
  for (std::size_t b = 0; b < meshes.size(); ++b)
    cells.middleCols(model.bodies[b].first_cell, model.bodies[b].num_cells) =
        meshes[b].cells.array() + model.bodies[b].first_node;
  const conserve::assembly::BlockPattern<D> pattern(model.num_nodes(), cells);
  offsets = pattern.node_offsets();
  neighbours = pattern.node_neighbours();
  std::vector<int> part(static_cast<std::size_t>(model.num_nodes()));
  for (int r = 0; r < parts; ++r) std::fill(part.begin() + n.rank_nodes[r], part.begin() + n.rank_nodes[r + 1], r);
  return part;
}

template <int D>
void report(const conserve::io::Scenario& scenario, const std::vector<int>& counts) {
  const auto problem = conserve::simulation::setup<D>(scenario);
  const auto& model = problem.model;
  const conserve::assembly::BlockPattern<D> pattern(model.num_nodes(), model.cells);
  const auto& offsets = pattern.node_offsets();
  const auto& neighbours = pattern.node_neighbours();
  fmt::print("{} nodes, {} cells\n\n", model.num_nodes(), model.num_cells());
  fmt::print("| ranks | nodes per rank (largest) | contiguous: ghosts (largest) | ghosts / own | edges cut | "
             "PT-Scotch: ghosts (largest) | ghosts / own | edges cut | the run's numbering (graph): ghosts / own | "
             "edges cut |\n|---|---|---|---|---|---|---|---|---|---|\n");
  for (const int n : counts) {
    const std::vector<int> first = conserve::assembly::partition_nodes(model.num_nodes(), model.cells, n).first_node;
    std::vector<int> ranges(static_cast<std::size_t>(model.num_nodes()));
    for (int r = 0; r < n; ++r) std::fill(ranges.begin() + first[r], ranges.begin() + first[r + 1], r);
    const Split a = measure(offsets, neighbours, ranges, n);
    const conserve::solver::GraphPartition g = conserve::solver::partition_graph(offsets, neighbours, n);
    const Split b = measure(offsets, neighbours, g.part, n);
    std::vector<int> run_offsets, run_neighbours;
    const std::vector<int> run = graph_numbering<D>(scenario, model, n, run_offsets, run_neighbours);
    const Split c = measure(run_offsets, run_neighbours, run, n);
    fmt::print("| {} | {} | {} | {:.3f} | {} | {} | {:.3f} | {} | {:.3f} | {} |\n", n, a.most_nodes, a.most_ghosts,
               a.ghost_ratio, a.cut, b.most_ghosts, b.ghost_ratio, b.cut, c.ghost_ratio, c.cut);
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    fmt::print(stderr, "usage: conserve_partition SCENARIO N [N ...]\n");
    return 2;
  }
  try {
    const conserve::io::Scenario scenario = conserve::io::read_scenario(argv[1]);
    std::vector<int> counts;
    for (int i = 2; i < argc; ++i) counts.push_back(std::atoi(argv[i]));
    if (scenario.dimension == 2)
      report<2>(scenario, counts);
    else
      report<3>(scenario, counts);
  } catch (const std::exception& e) {
    fmt::print(stderr, "conserve_partition: {}\n", e.what());
    conserve::solver::ranks::finalize();
    return 1;
  }
  conserve::solver::ranks::finalize();
  return 0;
}
