#pragma once
/// Small contact scenarios shared by the contact tests (coarse meshes, short
/// runs: they are the shortened versions of the examples).
#include <algorithm>
#include <stdexcept>
#include <string>

namespace conserve::test {

/// Two free neo-Hookean discs (spheres) of quadratic cells, r = 0.1 m,
/// meeting off-centre at ±3 m/s, frictionless, for 60 ms: the impact
/// presses the master's curved facets into notches at their shared nodes,
/// where a sliding slave takes a second constraint.
inline std::string quadratic_bodies_meeting(int dimension) {
  const bool d3 = dimension == 3;
  std::string body = R"(
[[body]]
name = "{name}"{translate}
velocity = [{v}, 0.0{z}]
[body.material]
model = "neo_hookean"
young = 1.0e6
poisson = 0.3
density = 1000.0
[body.mesh]
generator = "{generator}"
radius = 0.1
size = {size}
order = 2
)";
  auto make = [&](const std::string& name, const std::string& translate, const std::string& v) {
    std::string b = body;
    auto put = [&](const std::string& key, const std::string& value) {
      for (auto at = b.find(key); at != std::string::npos; at = b.find(key)) b.replace(at, key.size(), value);
    };
    put("{name}", name);
    put("{translate}", translate);
    put("{v}", v);
    put("{z}", d3 ? ", 0.0" : "");
    put("{generator}", d3 ? "sphere" : "disc");
    put("{size}", d3 ? "0.06" : "0.04");
    return b;
  };
  const std::string surface = d3 ? "surface" : "circle";
  return "title = \"two quadratic bodies meeting off-centre\"\ndimension = " + std::to_string(dimension) +
         "\n[time]\nstep = 1e-3\nend = 0.06\n[output]\nvtu_every = 0\n" + make("left", "", "3.0") +
         make("right", d3 ? "\ntranslate = [0.205, 0.06, 0.0]" : "\ntranslate = [0.205, 0.06]", "-3.0") +
         "[[contact]]\nslave = \"left:" + surface + "\"\nmaster = \"right:" + surface +
         "\"\nkind = \"frictionless\"\n";
}

/// The paper's §6.3 ball (coarse mesh), dropped from just above a rigid
/// plane with 2 m/s tangential velocity, under gravity: one impact and the
/// rebound in `end` seconds.
inline std::string ball_on_plane(const std::string& kind, double end) {
  return R"(dimension = 3
[time]
step = 1e-3
end = )" + std::to_string(end) +
         R"(
[loads]
gravity = [0.0, 0.0, -9.81]
[[body]]
name = "ball"
translate = [0.0, 0.0, 0.42]
velocity = [2.0, 0.0, 0.0]
[body.material]
young = 4.0e6
poisson = 0.45
density = 1000.0
[body.mesh]
generator = "spherical_shell"
inner_radius = 0.2
outer_radius = 0.4
size = 0.15
[[body]]
name = "plane"
[body.material]
young = 4.0e6
poisson = 0.3
density = 1000.0
[body.mesh]
generator = "plate"
lx = 3.0
ly = 3.0
thickness = 0.2
size = 1.0
[[boundary]]
body = "plane"
group = "all"
[[contact]]
slave = "ball:outer"
master = "plane:top"
kind = ")" + kind + R"("
)";
}

/// A block (0.4 × 0.4 × 0.2 m, E = 1 MPa) set unstressed on a rigid plane
/// under gravity: it settles and vibrates on its support with a period of
/// about 25 ms, and the bottom nodes at its edges lift near each minimum of
/// the reaction. Δt = 1 ms.
inline std::string block_on_plane(const std::string& kind, double end) {
  return R"(dimension = 3
[time]
step = 1e-3
end = )" +
         std::to_string(end) +
         R"(
[loads]
gravity = [0.0, 0.0, -9.81]
[[body]]
name = "block"
translate = [0.0, 0.0, 0.1]
[body.material]
young = 1.0e6
poisson = 0.3
density = 1000.0
[body.mesh]
generator = "box"
lx = 0.4
ly = 0.4
lz = 0.2
size = 0.05
[[body]]
name = "plane"
rigid = true
[body.mesh]
generator = "square"
lx = 1.0
ly = 1.0
size = 0.25
[[contact]]
slave = "block:zmin"
master = "plane:surface"
kind = ")" +
         kind + "\"\n";
}

/// Two free deformable boxes (no gravity, nothing fixed): a small one hits
/// a bigger one off-centre, so that the impact also spins them.
inline std::string two_boxes(const std::string& kind, double end) {
  return R"(dimension = 3
[time]
step = 2e-3
end = )" + std::to_string(end) +
         R"(
[[body]]
name = "small"
translate = [-0.1015, 0.08, 0.03]
velocity = [2.0, 0.3, 0.0]
[body.material]
young = 2.0e5
poisson = 0.3
density = 1000.0
[body.mesh]
generator = "box"
lx = 0.2
ly = 0.2
lz = 0.2
size = 0.1
[[body]]
name = "big"
translate = [0.2, 0.0, 0.0]
[body.material]
young = 2.0e5
poisson = 0.3
density = 1000.0
[body.mesh]
generator = "box"
lx = 0.4
ly = 0.4
lz = 0.4
size = 0.2
[[contact]]
slave = "small:xmax"
master = "big:xmin"
kind = ")" + kind + R"("
)";
}

/// A block sliding into the corner of a rigid floor and a free elastic
/// wall (1 m/s towards each, 1 mm from each): the nodes on its bottom
/// edge next to the wall are on two slave surfaces (zmin on the floor,
/// xmax on the wall) and hold both constraints. The wall reaches below the
/// floor (no pair between them), so the corner is inside both masters.
inline std::string corner_block(double end) {
  return R"(dimension = 3
[time]
step = 2.0e-4
end = )" + std::to_string(end) +
         R"(
[[body]]
name = "block"
translate = [0.0, 0.0, 0.051]
velocity = [1.0, 0.0, -1.0]
[body.material]
young = 1.0e6
poisson = 0.3
density = 1000.0
[body.mesh]
generator = "box"
lx = 0.1
ly = 0.1
lz = 0.1
size = 0.05
[[body]]
name = "wall"
translate = [0.101, 0.0, 0.05]
[body.material]
young = 1.0e6
poisson = 0.3
density = 1000.0
[body.mesh]
generator = "box"
lx = 0.1
ly = 0.2
lz = 0.2
size = 0.05
[[body]]
name = "floor"
rigid = true
[body.mesh]
generator = "square"
lx = 1.0
ly = 1.0
size = 0.25
[[contact]]
slave = "block:zmin"
master = "floor:surface"
kind = "frictionless"
[[contact]]
slave = "block:xmax"
master = "wall:xmin"
kind = "frictionless"
)";
}

/// corner_block with a second free elastic wall across y: the block moves
/// at 1 m/s towards the floor and both walls (1 mm from each), so its
/// corner node is on three slave surfaces (zmin, xmax, ymax) and meets
/// three masters. The walls touch along x = 0.051 m; no pair between them.
inline std::string three_wall_corner_block(double end) {
  std::string s = corner_block(end);
  const auto swap = [&s](const std::string& from, const std::string& to) {
    const auto at = s.find(from);
    if (at == std::string::npos) throw std::logic_error("three_wall_corner_block: corner_block has no '" + from + "'");
    s.replace(at, from.size(), to);
  };
  swap("velocity = [1.0, 0.0, -1.0]", "velocity = [1.0, 1.0, -1.0]");
  swap("translate = [0.101, 0.0, 0.05]", "translate = [0.101, -0.05, 0.05]");
  swap("lx = 0.1\nly = 0.2\nlz = 0.2", "lx = 0.1\nly = 0.3\nlz = 0.2");
  s += R"([[body]]
name = "wall2"
translate = [-0.0745, 0.101, 0.05]
[body.material]
young = 1.0e6
poisson = 0.3
density = 1000.0
[body.mesh]
generator = "box"
lx = 0.251
ly = 0.1
lz = 0.2
size = 0.05
[[contact]]
slave = "block:ymax"
master = "wall2:ymin"
kind = "frictionless"
)";
  return s;
}

}  // namespace conserve::test

namespace conserve::test {

/// A glancing hit of a small elastic sphere (2D: disc) on a bigger one,
/// both free (no gravity, nothing fixed): the master is curved and faceted,
/// the slaves slide across its facets, and the hit spins both bodies.
inline std::string glancing_spheres(int dim, const std::string& kind, double end) {
  const bool d3 = dim == 3;
  const std::string v = d3 ? "[2.0, 0.0, 0.0]" : "[2.0, 0.0]";
  const std::string p_small = d3 ? "[-0.24, 0.09, 0.0]" : "[-0.24, 0.09]";
  return "dimension = " + std::to_string(dim) + R"(
[time]
step = 5e-4
end = )" + std::to_string(end) +
         R"(
[[body]]
name = "small"
translate = )" + p_small + R"(
velocity = )" + v + R"(
[body.material]
young = 1.0e6
poisson = 0.3
density = 1000.0
[body.mesh]
generator = ")" + (d3 ? "sphere" : "disc") + R"("
radius = 0.1
size = )" + (d3 ? "0.05" : "0.02") + R"(
[[body]]
name = "big"
[body.material]
young = 1.0e6
poisson = 0.3
density = 1000.0
[body.mesh]
generator = ")" + (d3 ? "sphere" : "disc") + R"("
radius = 0.15
size = )" + (d3 ? "0.06" : "0.03") + R"(
[[contact]]
slave = "small"
master = "big"
kind = ")" + kind + R"("
)";
}

}  // namespace conserve::test

namespace conserve::test {

/// A disc sliding fast along a rigid segment of several facets under
/// gravity (2D): slaves cross facet boundaries of a prescribed master, so
/// the reduced system's pattern changes inside Newton iterations.
inline std::string disc_sliding_on_segment(double end) {
  return R"(dimension = 2
[time]
step = 1e-3
end = )" + std::to_string(end) +
         R"(
[loads]
gravity = [0.0, -9.81]
[[body]]
name = "disc"
translate = [-0.3, 0.1005]
velocity = [3.0, -0.2]
[body.material]
young = 1.0e5
poisson = 0.3
density = 1000.0
[body.mesh]
generator = "disc"
radius = 0.1
size = 0.03
[[body]]
name = "floor"
rigid = true
[body.mesh]
generator = "segment"
lx = 2.0
size = 0.05
[[contact]]
slave = "disc"
master = "floor:surface"
kind = "frictionless"
)";
}

}  // namespace conserve::test

namespace conserve::test {

/// A small elastic disc (2D) thrown along the inside of a spinning free elastic
/// ring, no gravity, nothing fixed: it slides around the ring's concave inner
/// surface across many of its facets, pressed on it by its own centripetal
/// force. Everything free, so E, L and J are all conserved.
inline std::string disc_inside_ring(const std::string& kind, double step, double end) {
  return R"(dimension = 2
[time]
step = )" + std::to_string(step) +
         R"(
end = )" + std::to_string(end) +
         R"(
[[body]]
name = "disc"
translate = [0.0, -0.196]
velocity = [5.0, -0.3]
angular_velocity = -30.0
[body.material]
young = 2.0e6
poisson = 0.3
density = 1000.0
[body.mesh]
generator = "disc"
radius = 0.1
size = 0.025
[[body]]
name = "ring"
angular_velocity = -15.0
[body.material]
young = 2.0e6
poisson = 0.3
density = 1000.0
[body.mesh]
generator = "annulus"
inner_radius = 0.3
outer_radius = 0.4
size = 0.05
[[contact]]
slave = "disc"
master = "ring:inner"
kind = ")" + kind + R"("
)";
}

/// Two spinning elastic spheres in an oblique glancing hit (3D, free): the
/// slaves slide across the facets of the other sphere while both rotate.
inline std::string spinning_spheres(const std::string& kind, double step, double end) {
  return R"(dimension = 3
[time]
step = )" + std::to_string(step) +
         R"(
end = )" + std::to_string(end) +
         R"(
[[body]]
name = "small"
translate = [-0.24, 0.09, 0.0]
velocity = [2.0, 0.0, 0.0]
angular_velocity = [10.0, 20.0, 30.0]
[body.material]
young = 1.0e6
poisson = 0.3
density = 1000.0
[body.mesh]
generator = "sphere"
radius = 0.1
size = 0.05
[[body]]
name = "big"
angular_velocity = [-20.0, 10.0, 5.0]
[body.material]
young = 1.0e6
poisson = 0.3
density = 1000.0
[body.mesh]
generator = "sphere"
radius = 0.15
size = 0.06
[[contact]]
slave = "small"
master = "big"
kind = ")" + kind + R"("
)";
}

/// A spinning elastic sphere thrown along the inside of a spinning
/// spherical shell (3D, free): its slaves slide over the shell's concave
/// faceted inner surface.
inline std::string sphere_inside_shell(const std::string& kind, double step, double end) {
  return R"(dimension = 3
[time]
step = )" + std::to_string(step) +
         R"(
end = )" + std::to_string(end) +
         R"(
[[body]]
name = "small"
translate = [0.0, -0.19, 0.0]
velocity = [4.0, -0.3, 1.0]
angular_velocity = [10.0, 20.0, 30.0]
[body.material]
young = 1.0e6
poisson = 0.3
density = 1000.0
[body.mesh]
generator = "sphere"
radius = 0.1
size = 0.05
[[body]]
name = "shell"
angular_velocity = [0.0, 0.0, -10.0]
[body.material]
young = 1.0e6
poisson = 0.3
density = 1000.0
[body.mesh]
generator = "spherical_shell"
inner_radius = 0.3
outer_radius = 0.36
size = 0.06
[[contact]]
slave = "small"
master = "shell:inner"
kind = ")" + kind + R"("
)";
}

/// A hollow elastic disc (2D, an annulus) thrown onto a rigid floor (a bare
/// segment) at 4 m/s along x under gravity: it lands, rolls with full stick
/// and hops; `step` is Δt [s].
inline std::string disc_rolling_on_floor(double step, double end) {
  return R"(dimension = 2
[time]
step = )" + std::to_string(step) +
         R"(
end = )" + std::to_string(end) +
         R"(
[loads]
gravity = [0.0, -9.81]
[[body]]
name = "disc"
translate = [0.0, 0.2005]
velocity = [4.0, -0.5]
angular_velocity = -5.0
[body.material]
young = 1.0e6
poisson = 0.45
density = 1000.0
[body.mesh]
generator = "annulus"
inner_radius = 0.1
outer_radius = 0.2
size = 0.02
[[body]]
name = "floor"
rigid = true
translate = [1.5, 0.0]
[body.mesh]
generator = "segment"
lx = 5.0
size = 0.25
[[contact]]
slave = "disc:outer"
master = "floor:surface"
kind = "stick"
)";
}

/// `toml` with Newton iterating to its round-off floor. A step's energy
/// error is exactly Δu · r, the work of the residual Newton leaves; at the
/// default tolerance (1e-12 of the step's forces) it is about 1e-13 of E
/// per step and its sum depends on which side Newton comes from (the
/// predictor). A test of the scheme's own conservation takes it out.
inline std::string to_round_off(const std::string& toml) { return toml + "[newton]\nresidual_tolerance = 1e-15\n"; }

/// `toml` with `keys` ("scheme = \"paper\"\n") in its [active_set] table:
/// merged into the table if it has one (a key given there before is
/// replaced), else a table appended.
inline std::string with_active_set(const std::string& toml, const std::string& keys) {
  const std::string header = "[active_set]\n";
  const std::size_t at = toml.find(header);
  if (at == std::string::npos) return toml + header + keys;
  const std::size_t body = at + header.size();
  std::size_t end = toml.find("\n[", body - 1);
  end = end == std::string::npos ? toml.size() : end + 1;
  auto key_of = [](const std::string& line) { return line.substr(0, line.find_first_of(" =")); };
  std::string kept;
  for (std::size_t line = body; line < end;) {
    const std::size_t next = std::min(toml.find('\n', line) + 1, end);
    const std::string text = toml.substr(line, next - line);
    if (keys.find("\n" + key_of(text) + " ") == std::string::npos && keys.rfind(key_of(text) + " ", 0) != 0)
      kept += text;
    line = next;
  }
  return toml.substr(0, body) + kept + keys + toml.substr(end);
}

/// `toml` under the paper's scheme: the mid-point velocity (19), slaves
/// activated at the gap they start the step with.
inline std::string paper(const std::string& toml) { return with_active_set(toml, "scheme = \"paper\"\n"); }

/// `toml` with impacts located in time and the persistent-contact velocity
/// update (the defaults, given explicitly).
inline std::string located(const std::string& toml) {
  return with_active_set(toml, "scheme = \"persistent\"\nlocate_impacts = true\n");
}

/// A block driven at `speed` into the flank of a base (2D or 3D, no
/// gravity, facets of 5 cm) whose master surface is its top alone: the
/// block's bottom edge goes in through the base's side, which is no
/// master, `depth` below the top, and comes in under the top's border
/// already that far behind it (from step 5 of 40).
inline std::string block_into_a_flank(int dim, const std::string& scheme, double depth, double speed) {
  const bool d3 = dim == 3;
  // The top is y = 0.05 in 2D, z = 0.05 in 3D; the block starts 5 ms
  // short of the base's side x = -0.2, its bottom `depth` below the top.
  const std::string x = std::to_string(-0.25 - 5e-3 * speed), v = std::to_string(speed);
  const std::string top = d3 ? "zmax" : "ymax", bottom = d3 ? "zmin" : "ymin";
  // Material and mesh of both bodies, but for the length along x.
  const std::string body =
      std::string("[body.material]\nyoung = 1.0e5\npoisson = 0.3\ndensity = 1000.0\n[body.mesh]\n") +
      (d3 ? "generator = \"box\"\nly = 0.1\nlz = 0.1\n" : "generator = \"rectangle\"\nly = 0.1\n") + "size = 0.05\n";
  return "dimension = " + std::to_string(dim) + "\n[time]\nstep = 1e-3\nend = 0.04\n[active_set]\nscheme = \"" +
         scheme + "\"\n[[body]]\nname = \"base\"\n" + body + "lx = 0.4\n[[body]]\nname = \"block\"\ntranslate = [" + x +
         (d3 ? ", 0.0, " : ", ") + std::to_string(0.1 - depth) + "]\nvelocity = [" + v +
         (d3 ? ", 0.0, 0.0]" : ", 0.0]") + "\n" + body + "lx = 0.1\n[[contact]]\nslave = \"block:" + bottom +
         "\"\nmaster = \"base:" + top + "\"\nkind = \"frictionless\"\n";
}

/// `toml` with its first [[contact]] given `method = "<method>"` and the
/// extra keys `keys` ("penalty = 1e9\n"; later pairs take the first's
/// method): the same scenario under another constraint method.
inline std::string with_method(const std::string& toml, const std::string& method, const std::string& keys = "") {
  const std::size_t at = toml.find("[[contact]]");
  const std::size_t kind = toml.find("\nkind = ", at);
  const std::size_t end = toml.find('\n', kind + 1);
  return toml.substr(0, end + 1) + "method = \"" + method + "\"\n" + keys + toml.substr(end + 1);
}

}  // namespace conserve::test
