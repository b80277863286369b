#pragma once
/// Scenario text of the validation cases (docs/validation.md). The files in
/// examples/validation/ are these texts with comments in front; a test
/// checks that they stay the same.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

namespace conserve::test {

/// Bars of equal length in a row along x, a small gap between neighbours,
/// the first one moving at v0 towards the others; ν = 0, so that 1D wave
/// theory holds (c = √(E/ρ)).
struct Bars {
  int dimension = 2;
  int count = 2;
  double size = 0.025;     ///< element size [m]
  double step = 1e-5;      ///< Δt [s]
  double end = 2.5e-3;     ///< [s]
  double length = 1.0;     ///< L [m]
  /// Per bar, left to right, if the bars differ in length (else all `length`) [m].
  std::vector<double> lengths;
  double width = 0.1;      ///< cross-section edge (2D: height; thickness 1 m) [m]
  double gap = 1e-4;       ///< initial gap between neighbours [m]
  double v0 = 1.0;         ///< speed of the first bar [m/s]
  double young = 1.0e9;    ///< E [Pa]
  double density = 1.0e3;  ///< ρ [kg/m³]
  std::string directory = "out/validation/bars";
  /// Keys of its [active_set] table: the paper's scheme, which the
  /// documented figures are for (empty: the defaults, located + persistent).
  std::string active_set = "scheme = \"paper\"";

  [[nodiscard]] double wave_speed() const;
  [[nodiscard]] double area() const { return dimension == 3 ? width * width : width; }
  [[nodiscard]] double length_of(int k) const { return lengths.empty() ? length : lengths.at(k); }
  /// The shortest bar's length (2L/c of an impact between two bars) [m].
  [[nodiscard]] double shortest() const;
  [[nodiscard]] double mass(int k = 0) const { return density * length_of(k) * area(); }
};

inline double Bars::shortest() const {
  double l = length_of(0);
  for (int k = 1; k < count; ++k) l = std::min(l, length_of(k));
  return l;
}

inline double Bars::wave_speed() const { return std::sqrt(young / density); }

/// Name of bar k: A, B, C, ...
inline std::string bar_name(int k) { return std::string(1, static_cast<char>('A' + k)); }

inline std::string bar_body(const Bars& b, int k) {
  double x = (k - 0.5 * (b.count - 1)) * (b.length + b.gap);  // the centre of bar k
  if (!b.lengths.empty()) {
    double left = -b.gap * 0.5 * (b.count - 1);
    for (int j = 0; j < b.count; ++j) left -= 0.5 * b.length_of(j);
    for (int j = 0; j < k; ++j) left += b.length_of(j) + b.gap;
    x = left + 0.5 * b.length_of(k);
  }
  const std::string place = b.dimension == 3 ? fmt::format("[{}, 0.0, 0.0]", x) : fmt::format("[{}, 0.0]", x);
  const double v = k == 0 ? b.v0 : 0.0;
  const std::string velocity = b.dimension == 3 ? fmt::format("[{}, 0.0, 0.0]", v) : fmt::format("[{}, 0.0]", v);
  const std::string mesh = b.dimension == 3 ? fmt::format("generator = \"box\"\nlx = {}\nly = {}\nlz = {}\nsize = {}\n",
                                                          b.length_of(k), b.width, b.width, b.size)
                                            : fmt::format("generator = \"rectangle\"\nlx = {}\nly = {}\nsize = {}\n",
                                                          b.length_of(k), b.width, b.size);
  return fmt::format(
      "\n[[body]]\nname = \"{}\"\ntranslate = {}\nvelocity = {}\n[body.material]\nyoung = {}\npoisson = 0.0\n"
      "density = {}\n[body.mesh]\n{}",
      bar_name(k), place, velocity, b.young, b.density, mesh);
}

/// The scenario: bar k's xmax face is the slave of bar k+1's xmin face.
inline std::string bars_scenario(const Bars& b) {
  std::string s = fmt::format(
      "title = \"{} bars, longitudinal impact ({}D)\"\ndimension = {}\n\n[time]\nstep = {}\nend = {}\n\n"
      "[output]\ndirectory = \"{}\"\nvtu_every = 10\n",
      b.count, b.dimension, b.dimension, b.step, b.end, b.directory);
  for (int k = 0; k < b.count; ++k) s += bar_body(b, k);
  for (int k = 0; k + 1 < b.count; ++k)
    s += fmt::format("\n[[contact]]\nslave = \"{}:xmax\"\nmaster = \"{}:xmin\"\nkind = \"frictionless\"\n", bar_name(k),
                     bar_name(k + 1));
  if (!b.active_set.empty()) s += "\n[active_set]\n" + b.active_set + "\n";
  return s;
}

/// Plane-strain Hertz contact: a disc of radius R pressed onto a rigid
/// segment (y = −R) by a stiff block above it whose top face moves down
/// slowly; both contacts carry the same load P.
struct Hertz {
  double size = 0.08;      ///< element size of the disc [m]
  double step = 0.05;      ///< Δt [s]
  double end = 6.0;        ///< [s]
  double radius = 1.0;     ///< R [m]
  double rate = 0.01;      ///< downward speed of the block's top face [m/s]
  double young = 1.0e6;    ///< E of the disc [Pa]
  double poisson = 0.3;    ///< ν of the disc
  double density = 1.0e3;  ///< ρ of the disc and block [kg/m³]
  double gap = 1e-4;       ///< initial gaps [m]
  int order = 1;           ///< of the disc's and the block's cells
  std::string scheme = "paper";  ///< [active_set] scheme
  std::string directory = "out/validation/hertz";

  [[nodiscard]] double plane_strain_modulus() const { return young / (1.0 - poisson * poisson); }
};

inline std::string hertz_scenario(const Hertz& h) {
  const std::string order = h.order == 1 ? "" : fmt::format("order = {}\n", h.order);
  return fmt::format(
      R"toml(title = "Hertz: disc pressed onto a rigid plane (plane strain)"
dimension = 2

[time]
step = {}
end = {}

[output]
directory = "{}"
vtu_every = 10

[active_set]
scheme = "{}"

[[body]]
name = "disc"
[body.material]
young = {}
poisson = {}
density = {}
[body.mesh]
generator = "disc"
radius = {}
size = {}
{}
[[body]]
name = "block"
translate = [0.0, {}]
[body.material]
young = {}
poisson = 0.3
density = {}
[body.mesh]
generator = "rectangle"
lx = {}
ly = {}
size = {}
{}
[[body]]
name = "ground"
rigid = true
translate = [0.0, {}]
[body.mesh]
generator = "segment"
lx = {}
size = {}

[[boundary]]
body = "block"
group = "ymax"
rate = [0.0, {}]

[[contact]]
slave = "disc:circle"
master = "ground:surface"
kind = "frictionless"

[[contact]]
slave = "disc:circle"
master = "block:ymin"
kind = "frictionless"
)toml",
      h.step, h.end, h.directory, h.scheme, h.young, h.poisson, h.density, h.radius, h.size, order,
      h.radius + 0.1 * h.radius + h.gap, 1000.0 * h.young, h.density, h.radius, 0.2 * h.radius, 0.1 * h.radius * h.order,
      order, -h.radius - h.gap, h.radius, 0.5 * h.size, -h.rate);
}

}  // namespace conserve::test
