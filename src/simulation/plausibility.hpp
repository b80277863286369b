#pragma once
/// Warnings, not errors, for input that is valid but likely a slip (a
/// unit, a digit): each names the scenario key and the figure behind it,
/// so that a user sees it before the run breaks or runs on nonsense.
/// `conserve check` and `conserve run` print them.
#include <string>
#include <vector>

#include "contact/constraint.hpp"
#include "io/scenario.hpp"
#include "model/model.hpp"

namespace conserve::simulation {

/// An impact faster than this fraction of a body's bar wave speed √(E/ρ)
/// strains it by about as much: SVK softens in compression and inverts
/// cells from about 40 % on.
inline constexpr double kFastImpact = 0.3;
/// Densities outside this range [kg/m³] belong to no solid a user is
/// likely to model (light foams ~10, tungsten 19 300, osmium 22 600).
inline constexpr double kLightestSolid = 10.0;
inline constexpr double kDensestSolid = 25000.0;
/// A slave surface whose median facet edge is this many times its
/// master's is coarser: node-to-segment contact holds the slave's nodes
/// only, and the master's may enter its facets between them.
inline constexpr double kCoarseSlave = 1.5;

/// The warnings for `scenario` built into `model` (simulation/setup.hpp):
/// - a contact whose bodies may meet faster than kFastImpact of a body's
///   wave speed (their initial velocities and spins, and a fall under
///   gravity across the model's extent);
/// - a generated mesh whose `size` is larger than the body it meshes;
/// - a density outside [kLightestSolid, kDensestSolid], with the mass it
///   gives the body;
/// - a contact pair (`pairs`, in scenario order) whose slave surface is
///   coarser than its master (kCoarseSlave), unless the master is flat;
/// - a contact pair whose slave nodes start behind its master, a bare
///   surface (facing away from them: flip_normals).
/// Each is one line "FILE:LINE: KEY: what (figures)".
template <int D>
std::vector<std::string> plausibility_warnings(const io::Scenario& scenario, const model::Model<D>& model,
                                               const std::vector<contact::ContactPair<D>>& pairs);

}  // namespace conserve::simulation
