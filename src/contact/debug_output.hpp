#pragma once
/// Debugging output: the contact state of every slave node as a VTU file
/// ("see the contact state in ParaView"). Open the file, Apply, show it as
/// Points (Representation → Points, Point Size 8) over the solution, and
/// colour by `gap` or `master_facet`; Glyph → `normal` shows the master
/// normals. Not part of the regular output.
#include <filesystem>
#include <optional>
#include <vector>

#include "contact/search.hpp"

namespace conserve::contact {

/// Writes the slave nodes `slave_nodes` (global numbers into `x`, D × n_nodes
/// [m]) as VTK vertices at their positions in `x`, with `matches[i]` the
/// search result of slave i (same length as `slave_nodes`). Point fields:
///   - `gap` [m]: g_N on the master facet (NaN when unmatched);
///   - `normal` (3 components): the master's outward unit normal (0 when unmatched, z = 0 in 2D);
///   - `master_facet`: the facet's column in the surface (−1 when unmatched);
///   - `xi` (3 components): ξ̄ (unclamped), padded with zeros;
///   - `inside`: 1 if ξ̄ lies in the facet (within `inside_tolerance`), else 0;
///   - `slave_node`: the global node number.
/// The file is written atomically (temporary file renamed into place).
/// Throws Error if the sizes disagree or the file cannot be written.
template <int D>
void write_contact_state_vtu(const std::filesystem::path& file, const std::vector<int>& slave_nodes,
                             const Positions<D>& x, const std::vector<std::optional<Match<D>>>& matches,
                             double inside_tolerance = 1e-10);

}  // namespace conserve::contact
