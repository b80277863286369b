#pragma once
/// Built-in mesh generators (through the Gmsh C++ API) for the shapes of the
/// paper's examples, so that no external mesh file is needed.
#include <map>
#include <string>
#include <vector>

#include "mesh/mesh.hpp"

namespace conserve::mesh {

/// One parameter of a generator, for validation and documentation.
struct GeneratorParameter {
  std::string name;
  std::string unit;
  std::string doc;
  bool required = true;
  double default_value = 0.0;  ///< used when !required
};

/// A generator: its dimension and parameters.
struct GeneratorInfo {
  int dim = 3;
  std::string doc;
  std::vector<GeneratorParameter> parameters;
};

/// All generators by name (box, cylinder, hollow_cylinder, spherical_shell,
/// plate, rectangle, disc, annulus, ...). Each lists its own parameters and
/// then `order` (not required, default 1), which every generator takes: 1
/// linear cells, 2 quadratic ones (mesh.hpp) whose boundary midside nodes
/// lie on the true curved surface; the bare surfaces (square, segment)
/// take order 1 only.
const std::map<std::string, GeneratorInfo>& generator_catalog();

/// Makes the mesh. Every mesh has the cell group "body", the facet group
/// "boundary" (all boundary facets, outward oriented) and named faces listed
/// in the generator's doc. Throws InputError on an unknown generator, an
/// unknown or missing parameter, a non-positive size, or an order other
/// than 1 or 2 (or 2 for a bare surface).
Mesh generate_mesh(const std::string& kind, const std::map<std::string, double>& params);

}  // namespace conserve::mesh
