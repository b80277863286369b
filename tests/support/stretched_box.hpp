#pragma once
/// A soft, pre-stretched spinning box with Δt = 0.05 s and 5 Newton
/// iterations per step, for the cutback and inversion tests: stretched by
/// 1.2 with E = 1e5 Pa it needs smaller steps but recovers; stretched by
/// 1.3 with E = 5e4 Pa its Saint Venant–Kirchhoff cells are compressed past
/// their limit point as it rebounds and turn inside out at any step size.
#include <string>

namespace conserve::test {

inline std::string stretched_box(const std::string& stretch, const std::string& young, int vtu_every) {
  return R"(dimension = 3
[time]
step = 0.05
end = 0.2
[newton]
max_iterations = 5
[output]
vtu_every = )" + std::to_string(vtu_every) + R"(
[[body]]
name = "box"
velocity = [1.0, 0.5, 0.0]
angular_velocity = [0.5, 1.0, 3.0]
initial_deformation = [[)" + stretch + R"(, 0.05, 0.0], [0.0, 0.85, 0.0], [0.0, 0.0, 1.0]]
[body.material]
young = )" + young + R"(
poisson = 0.3
density = 1000.0
[body.mesh]
generator = "box"
lx = 1.0
ly = 0.4
lz = 0.3
size = 0.2
)";
}

}  // namespace conserve::test
