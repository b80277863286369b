#pragma once
/// A small valid scenario for command-line tests: one cube read from
/// cube.msh (tests/data/msh/cube_ascii.msh, which a test writes next to the
/// scenario), 3 steps, no VTU output.
#include <string>

#include "support/files.hpp"

namespace conserve::test {

/// Title on line 1; the body's mesh file "cube.msh" on line 16.
inline const std::string kCubeScenario = R"(title = "cube"
dimension = 3
[time]
step = 0.01
end = 0.03
[output]
vtu_every = 0
[[body]]
name = "cube"
[body.material]
young = 1.0e5
poisson = 0.3
density = 1000.0
[body.mesh]
file = "cube.msh"
)";

/// The text of tests/data/msh/cube_ascii.msh.
inline std::string cube_msh() { return slurp(std::string(CONSERVE_SOURCE_DIR) + "/tests/data/msh/cube_ascii.msh"); }

}  // namespace conserve::test
