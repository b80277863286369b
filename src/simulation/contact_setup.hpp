#pragma once
/// From the scenario's [[contact]] tables to contact pairs on the model.
#include <vector>

#include "contact/constraint.hpp"
#include "io/scenario.hpp"

namespace conserve::simulation {

/// One pair per [[contact]]: surfaces resolved on the model, the search
/// radius set to depth_factor × the master's longest facet edge.
/// Throws InputError "SCENARIO: contact[i]: …" for unknown bodies or groups.
template <int D>
std::vector<contact::ContactPair<D>> make_contact_pairs(const io::Scenario& scenario, const model::Model<D>& model);

}  // namespace conserve::simulation
