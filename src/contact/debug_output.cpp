#include "contact/debug_output.hpp"

#include <fmt/format.h>

#include <limits>

#include "core/error.hpp"
#include "io/vtu_writer.hpp"

namespace conserve::contact {

namespace {

io::VtuField field(const char* name, int components, std::size_t count) {
  return {name, components, std::vector<double>(static_cast<std::size_t>(components) * count, 0.0)};
}

}  // namespace

template <int D>
void write_contact_state_vtu(const std::filesystem::path& file, const std::vector<int>& slave_nodes,
                             const Positions<D>& x, const std::vector<std::optional<Match<D>>>& matches,
                             double inside_tolerance) {
  const std::size_t n = slave_nodes.size();
  if (matches.size() != n)
    throw Error(fmt::format("contact state {}: {} matches for {} slave nodes", file.string(), matches.size(), n));
  io::VtuGrid grid;
  grid.points.resize(D, static_cast<Eigen::Index>(n));
  grid.cells.resize(1, static_cast<Eigen::Index>(n));
  io::VtuField gap = field("gap", 1, n), normal = field("normal", 3, n), facet = field("master_facet", 1, n),
               xi = field("xi", 3, n), inside = field("inside", 1, n), node = field("slave_node", 1, n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto j = static_cast<Eigen::Index>(i);
    if (slave_nodes[i] < 0 || slave_nodes[i] >= x.cols())
      throw Error(fmt::format("contact state {}: slave node {} is not a node", file.string(), slave_nodes[i]));
    grid.points.col(j) = x.col(slave_nodes[i]);
    grid.cells(0, j) = static_cast<int>(i);
    node.values[i] = slave_nodes[i];
    const auto& match = matches[i];
    gap.values[i] = match ? match->projection.gap : std::numeric_limits<double>::quiet_NaN();
    facet.values[i] = match ? match->facet : -1;
    if (!match) continue;
    for (int c = 0; c < D; ++c) normal.values[3 * i + static_cast<std::size_t>(c)] = match->projection.normal(c);
    for (int c = 0; c < D - 1; ++c) xi.values[3 * i + static_cast<std::size_t>(c)] = match->projection.xi(c);
    inside.values[i] = match->projection.inside(inside_tolerance) ? 1.0 : 0.0;
  }
  grid.point_data = {gap, normal, facet, xi, inside, node};
  io::write_vtu(file, grid);
}

template void write_contact_state_vtu<2>(const std::filesystem::path&, const std::vector<int>&, const Positions<2>&,
                                         const std::vector<std::optional<Match<2>>>&, double);
template void write_contact_state_vtu<3>(const std::filesystem::path&, const std::vector<int>&, const Positions<3>&,
                                         const std::vector<std::optional<Match<3>>>&, double);

}  // namespace conserve::contact
