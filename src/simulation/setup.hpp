#pragma once
/// From a parsed scenario to the discretised problem: meshes made or read,
/// placed, turned into bodies; prescribed displacements; initial state.
#include "io/scenario.hpp"
#include "model/model.hpp"
#include "model/state.hpp"

namespace conserve::simulation {

template <int D>
struct Problem {
  model::Model<D> model;
  model::State initial;
};

/// Builds the problem. Throws InputError "SCENARIO: body[i] 'name': …" for
/// meshes that cannot be made or read, groups that do not exist, a degree
/// of freedom prescribed twice, inverted cells, or bodies that overlap in
/// the initial configuration (a node of one strictly inside a cell of
/// another; touching is fine).
template <int D>
Problem<D> setup(const io::Scenario& scenario);

}  // namespace conserve::simulation
