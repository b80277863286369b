#pragma once
/// What determines a run's trajectory, as a list of named entries (a hash
/// each, and a short printable value for settings), so that a checkpoint
/// of another scenario is refused naming the setting that differs.
#include <cstdint>
#include <string>
#include <vector>

#include "io/scenario.hpp"
#include "model/model.hpp"

namespace conserve::simulation {

/// One named part of what determines the trajectory.
struct FingerprintEntry {
  std::string name;        ///< "[time] step", "body 'ball' material", "contact[0] kind", ...
  std::uint64_t hash = 0;  ///< FNV-1a of its values' bytes
  std::string value;       ///< the value as the scenario gives it ("0.001"); empty for bulk data (a mesh)
};

using Fingerprint = std::vector<FingerprintEntry>;

/// The fingerprint of a run of `model` made from `scenario`: dimension,
/// body names; per body its material, thickness, initial velocity, angular
/// velocity and deformation, node coordinates, cells, cell volumes and
/// facet groups; gravity; prescribed dofs; time step, schemes, Newton
/// tolerances and factorization reuse; each contact pair's surfaces, kind
/// and depth factor. Not in it: the end time, output settings and the
/// effort limits (min_step, max_iterations, max_passes), so that a run may
/// be continued further, with other output, or with more effort.
template <int D>
Fingerprint scenario_fingerprint(const io::Scenario& scenario, const model::Model<D>& model);

/// The first entry (in the checkpoint's order) in which `checkpoint` and
/// `scenario` differ, as a phrase: "the checkpoint was written with [time]
/// step = 0.001, this scenario has 0.002", "body 'ball' node coordinates
/// differ", "contact[1] kind is not in this scenario"; empty if they agree.
/// Entries are matched by name and compared by hash.
std::string first_difference(const Fingerprint& checkpoint, const Fingerprint& scenario);

}  // namespace conserve::simulation
