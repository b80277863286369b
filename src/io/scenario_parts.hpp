#pragma once
/// Private to the scenario parser: the parsers of the [[body]] and
/// [[boundary]] tables (scenario_body.cpp, scenario_mesh.cpp).
#include <filesystem>
#include <vector>

#include "io/scenario.hpp"
#include "io/toml_section.hpp"

namespace conserve::io::detail {

/// All [[body]] tables of the top level; names are unique.
std::vector<BodySpec> parse_bodies(const Section& top, const std::filesystem::path& scenario_file);

/// All [[boundary]] tables of the top level; each names one of `bodies`.
std::vector<BoundarySpec> parse_boundaries(const Section& top, const std::vector<BodySpec>& bodies);

/// One [body.mesh] table: a file (resolved against the scenario's folder,
/// must exist) or a generator with its parameters checked and completed.
MeshSpec parse_mesh(const Section& mesh, const std::filesystem::path& scenario_file);

}  // namespace conserve::io::detail
