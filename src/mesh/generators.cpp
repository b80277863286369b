// Built-in generators: the catalog, parameter validation, and the
// OpenCASCADE geometry of each shape (meshed by gmsh_mesher.cpp), and the
// structured bare surfaces (square, segment) for rigid bodies. The
// geometry is built in coordinates normalised by the largest length
// parameter, so that OpenCASCADE's and Gmsh's absolute tolerances act the
// same at every scale; the points are scaled back at the end. Every
// generator with cells makes linear or quadratic ones (parameter `order`).
#include "mesh/generators.hpp"

#include <fmt/format.h>
#include <gmsh.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.hpp"
#include "mesh/gmsh_mesher.hpp"
#include "mesh/surface_mesh.hpp"

namespace conserve::mesh {

namespace {

using Params = std::map<std::string, double>;
using detail::EntityShape;
namespace occ = gmsh::model::occ;

/// A generator: catalog entry, analytic volume [m³] / area [m²], geometry
/// and the classification of its boundary entities into facet groups.
/// Surface-only generators instead set `surface`, which makes the mesh
/// directly (structured, no Gmsh); `measure` then estimates its facets.
struct Generator {
  GeneratorInfo info;
  double (*measure)(const Params&) = nullptr;
  void (*build)(const Params&) = nullptr;
  std::string (*classify)(const EntityShape&, const Params&) = nullptr;
  Mesh (*surface)(const Params&) = nullptr;
};

constexpr double kPi = std::numbers::pi;
/// Estimated cells above which generation is refused (size too small).
constexpr double kMaxCells = 2e7;

GeneratorParameter length(const std::string& name, const std::string& doc) { return {name, "m", doc, true, 0.0}; }

GeneratorParameter size_parameter() {
  return length("size", "target element edge length (Gmsh Mesh.MeshSizeMax; MeshSizeMin = size/10)");
}

bool near(double a, double b) { return std::abs(a - b) < 1e-6; }  // normalised coordinates

/// "<axis>min"/"<axis>max" for a face/edge of an axis-aligned box centred at
/// the origin with the given edge lengths.
std::string box_side(const EntityShape& s, const std::vector<double>& lengths) {
  static const char* axes[] = {"x", "y", "z"};
  for (std::size_t k = 0; k < lengths.size(); ++k) {
    if (near(s.centre[static_cast<Eigen::Index>(k)], -lengths[k] / 2)) return std::string(axes[k]) + "min";
    if (near(s.centre[static_cast<Eigen::Index>(k)], lengths[k] / 2)) return std::string(axes[k]) + "max";
  }
  return "";
}

/// "inner" or "outer" for a curved face/edge of a hollow shape, by its width.
std::string inner_or_outer(const EntityShape& s, const Params& p) {
  return s.hi.x() - s.lo.x() < p.at("inner_radius") + p.at("outer_radius") ? "inner" : "outer";
}

std::string z_end(const EntityShape& s, double length) {
  if (near(s.centre.z(), -length / 2)) return "zmin";
  if (near(s.centre.z(), length / 2)) return "zmax";
  return "";
}

void cut(int dim, int object, int tool) {
  gmsh::vectorpair out;
  std::vector<gmsh::vectorpair> map;
  occ::cut({{dim, object}}, {{dim, tool}}, out, map);
}

Generator box() {
  return {{3,
           "Box [-lx/2, lx/2] × [-ly/2, ly/2] × [-lz/2, lz/2]. Facet groups: xmin, xmax, ymin, ymax, zmin, zmax.",
           {length("lx", "edge length along x"), length("ly", "edge length along y"),
            length("lz", "edge length along z"), size_parameter()}},
          [](const Params& p) { return p.at("lx") * p.at("ly") * p.at("lz"); },
          [](const Params& p) {
            occ::addBox(-p.at("lx") / 2, -p.at("ly") / 2, -p.at("lz") / 2, p.at("lx"), p.at("ly"), p.at("lz"));
          },
          [](const EntityShape& s, const Params& p) {
            return box_side(s, {p.at("lx"), p.at("ly"), p.at("lz")});
          }};
}

Generator cylinder() {
  return {{3,
           "Solid circular cylinder, axis z, centred at the origin. Facet groups: side, zmin, zmax.",
           {length("radius", "radius"), length("length", "length along z"), size_parameter()}},
          [](const Params& p) { return kPi * p.at("radius") * p.at("radius") * p.at("length"); },
          [](const Params& p) { occ::addCylinder(0, 0, -p.at("length") / 2, 0, 0, p.at("length"), p.at("radius")); },
          [](const EntityShape& s, const Params& p) {
            const std::string end = z_end(s, p.at("length"));
            return end.empty() ? std::string("side") : end;
          }};
}

Generator hollow_cylinder() {
  return {{3,
           "Tube, axis z, centred at the origin. Facet groups: inner, outer, zmin, zmax.",
           {length("inner_radius", "radius of the hole"), length("outer_radius", "outer radius"),
            length("length", "length along z"), size_parameter()}},
          [](const Params& p) {
            return kPi * (std::pow(p.at("outer_radius"), 2) - std::pow(p.at("inner_radius"), 2)) * p.at("length");
          },
          [](const Params& p) {
            const double l = p.at("length");
            const int outer = occ::addCylinder(0, 0, -l / 2, 0, 0, l, p.at("outer_radius"));
            cut(3, outer, occ::addCylinder(0, 0, -l, 0, 0, 2 * l, p.at("inner_radius")));
          },
          [](const EntityShape& s, const Params& p) {
            const std::string end = z_end(s, p.at("length"));
            return end.empty() ? inner_or_outer(s, p) : end;
          }};
}

Generator sphere() {
  return {
      {3, "Solid sphere centred at the origin. Facet group: surface.", {length("radius", "radius"), size_parameter()}},
      [](const Params& p) { return 4.0 / 3.0 * kPi * std::pow(p.at("radius"), 3); },
      [](const Params& p) { occ::addSphere(0, 0, 0, p.at("radius")); },
      [](const EntityShape&, const Params&) { return std::string("surface"); }};
}

Generator spherical_shell() {
  return {{3,
           "Hollow sphere centred at the origin. Facet groups: inner, outer.",
           {length("inner_radius", "radius of the cavity"), length("outer_radius", "outer radius"), size_parameter()}},
          [](const Params& p) {
            return 4.0 / 3.0 * kPi * (std::pow(p.at("outer_radius"), 3) - std::pow(p.at("inner_radius"), 3));
          },
          [](const Params& p) {
            const int outer = occ::addSphere(0, 0, 0, p.at("outer_radius"));
            cut(3, outer, occ::addSphere(0, 0, 0, p.at("inner_radius")));
          },
          inner_or_outer};
}

Generator plate() {
  return {{3,
           "Thin box [-lx/2, lx/2] × [-ly/2, ly/2] × [-thickness, 0] whose top face is z = 0 (e.g. a rigid "
           "floor). Facet groups: top (z = 0), bottom (z = -thickness).",
           {length("lx", "edge length along x"), length("ly", "edge length along y"),
            length("thickness", "thickness along z"), size_parameter()}},
          [](const Params& p) { return p.at("lx") * p.at("ly") * p.at("thickness"); },
          [](const Params& p) {
            occ::addBox(-p.at("lx") / 2, -p.at("ly") / 2, -p.at("thickness"), p.at("lx"), p.at("ly"),
                        p.at("thickness"));
          },
          [](const EntityShape& s, const Params& p) {
            if (near(s.centre.z(), 0.0)) return std::string("top");
            return near(s.centre.z(), -p.at("thickness")) ? std::string("bottom") : std::string();
          }};
}

Generator rectangle() {
  return {{2,
           "Rectangle [-lx/2, lx/2] × [-ly/2, ly/2] in the plane z = 0. Facet groups: xmin, xmax, ymin, ymax.",
           {length("lx", "edge length along x"), length("ly", "edge length along y"), size_parameter()}},
          [](const Params& p) { return p.at("lx") * p.at("ly"); },
          [](const Params& p) { occ::addRectangle(-p.at("lx") / 2, -p.at("ly") / 2, 0, p.at("lx"), p.at("ly")); },
          [](const EntityShape& s, const Params& p) {
            return box_side(s, {p.at("lx"), p.at("ly")});
          }};
}

Generator disc() {
  return {{2,
           "Disc centred at the origin in the plane z = 0. Facet group: circle.",
           {length("radius", "radius"), size_parameter()}},
          [](const Params& p) { return kPi * p.at("radius") * p.at("radius"); },
          [](const Params& p) { occ::addDisk(0, 0, 0, p.at("radius"), p.at("radius")); },
          [](const EntityShape&, const Params&) { return std::string("circle"); }};
}

Generator annulus() {
  return {{2,
           "Ring centred at the origin in the plane z = 0. Facet groups: inner, outer.",
           {length("inner_radius", "radius of the hole"), length("outer_radius", "outer radius"), size_parameter()}},
          [](const Params& p) { return kPi * (std::pow(p.at("outer_radius"), 2) - std::pow(p.at("inner_radius"), 2)); },
          [](const Params& p) {
            const int outer = occ::addDisk(0, 0, 0, p.at("outer_radius"), p.at("outer_radius"));
            cut(2, outer, occ::addDisk(0, 0, 0, p.at("inner_radius"), p.at("inner_radius")));
          },
          inner_or_outer};
}

GeneratorParameter facet_size(const std::string& count) { return length("size", "target facet edge length: " + count); }

int divisions(double length, double size) { return std::max(1, static_cast<int>(std::ceil(length / size - 1e-9))); }

/// lx × ly in the plane z = 0: a grid of nx × ny squares, two triangles
/// each, counter-clockwise seen from +z (normal +z).
Mesh square_mesh(const Params& p) {
  const int nx = divisions(p.at("lx"), p.at("size")), ny = divisions(p.at("ly"), p.at("size"));
  Eigen::MatrixXd points = Eigen::MatrixXd::Zero(3, (nx + 1) * (ny + 1));
  const auto node = [nx](int i, int j) { return j * (nx + 1) + i; };
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      points(0, node(i, j)) = p.at("lx") * (static_cast<double>(i) / nx - 0.5);
      points(1, node(i, j)) = p.at("ly") * (static_cast<double>(j) / ny - 0.5);
    }
  Eigen::MatrixXi facets(3, 2 * nx * ny);
  int f = 0;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      facets.col(f++) << node(i, j), node(i + 1, j), node(i + 1, j + 1);
      facets.col(f++) << node(i, j), node(i + 1, j + 1), node(i, j + 1);
    }
  return bare_surface(3, std::move(points), std::move(facets));
}

/// The segment y = 0, |x| ≤ lx/2 in n pieces, each from larger to smaller x
/// so that its normal (t_y, −t_x) is +y.
Mesh segment_mesh(const Params& p) {
  const int n = divisions(p.at("lx"), p.at("size"));
  Eigen::MatrixXd points = Eigen::MatrixXd::Zero(2, n + 1);
  for (int i = 0; i <= n; ++i) points(0, i) = p.at("lx") * (static_cast<double>(i) / n - 0.5);
  Eigen::MatrixXi facets(2, n);
  for (int i = 0; i < n; ++i) facets.col(i) << i + 1, i;
  return bare_surface(2, std::move(points), std::move(facets));
}

Generator square() {
  return {
      {3,
       "Flat square [-lx/2, lx/2] × [-ly/2, ly/2] in the plane z = 0, a bare surface of triangles without "
       "cells (only for a rigid body). Facet group: surface (= boundary), normals +z.",
       {length("lx", "edge length along x"), length("ly", "edge length along y"),
        facet_size("ceil(lx/size) × ceil(ly/size) squares, two triangles each")}},
      [](const Params& p) { return 2.0 * divisions(p.at("lx"), p.at("size")) * divisions(p.at("ly"), p.at("size")); },
      nullptr,
      nullptr,
      square_mesh};
}

Generator segment() {
  return {{2,
           "Straight segment y = 0, -lx/2 ≤ x ≤ lx/2, a bare line of 2-node facets without cells (only for a "
           "rigid body). Facet group: surface (= boundary), normals +y.",
           {length("lx", "length along x"), facet_size("ceil(lx/size) equal facets")}},
          [](const Params& p) { return static_cast<double>(divisions(p.at("lx"), p.at("size"))); },
          nullptr,
          nullptr,
          segment_mesh};
}

const std::map<std::string, Generator>& generators() {
  static const std::map<std::string, Generator> all = {
      {"box", box()},
      {"cylinder", cylinder()},
      {"hollow_cylinder", hollow_cylinder()},
      {"sphere", sphere()},
      {"spherical_shell", spherical_shell()},
      {"plate", plate()},
      {"rectangle", rectangle()},
      {"disc", disc()},
      {"annulus", annulus()},
      {"square", square()},
      {"segment", segment()},
  };
  return all;
}

template <typename Map>
std::string key_list(const Map& map) {
  std::string out;
  for (const auto& entry : map) out += (out.empty() ? "" : ", ") + entry.first;
  return out;
}

const Generator& find_generator(const std::string& kind) {
  const auto it = generators().find(kind);
  if (it == generators().end())
    throw InputError(fmt::format("unknown mesh generator '{}' (expected one of: {})", kind, key_list(generators())));
  return it->second;
}

/// The parameters with defaults filled in, checked.
Params checked_parameters(const std::string& kind, const GeneratorInfo& info, const Params& given) {
  std::map<std::string, const GeneratorParameter*> allowed;
  for (const GeneratorParameter& p : info.parameters) allowed[p.name] = &p;
  for (const auto& [name, value] : given)
    if (!allowed.contains(name))
      throw InputError(
          fmt::format("generator '{}': unknown parameter '{}' (expected: {})", kind, name, key_list(allowed)));
  Params out;
  for (const GeneratorParameter& p : info.parameters) {
    const auto it = given.find(p.name);
    if (it == given.end() && p.required)
      throw InputError(fmt::format("generator '{}': missing parameter '{}' ({} [{}])", kind, p.name, p.doc, p.unit));
    const double value = it == given.end() ? p.default_value : it->second;
    if (!std::isfinite(value) || (p.unit == "m" && value <= 0.0))
      throw InputError(fmt::format("generator '{}': parameter '{}' = {:g} (expected {})", kind, p.name, value,
                                   p.unit == "m" ? "a positive length [m]" : "a finite number"));
    out[p.name] = value;
  }
  return out;
}

void check_shape(const std::string& kind, const Generator& generator, const Params& p) {
  if (p.contains("inner_radius") && p.at("inner_radius") >= p.at("outer_radius"))
    throw InputError(fmt::format("generator '{}': inner_radius = {:g} must be smaller than outer_radius = {:g}", kind,
                                 p.at("inner_radius"), p.at("outer_radius")));
  const int dim = generator.info.dim;
  const double simplex = dim == 3 ? std::sqrt(2.0) / 12.0 : std::sqrt(3.0) / 4.0;  // regular simplex of edge 1
  const double cells =
      generator.surface ? generator.measure(p) : generator.measure(p) / (simplex * std::pow(p.at("size"), dim));
  if (cells > kMaxCells)
    throw InputError(
        fmt::format("generator '{}': size = {:g} would make about {:.3g} cells (expected a size giving "
                    "at most {:g})",
                    kind, p.at("size"), cells, kMaxCells));
}

/// The parameter every generator takes, added to each in the catalog.
GeneratorParameter order_parameter() {
  return {"order", "",
          "element order: 1 (3-node triangles, 4-node tetrahedra) or 2 (6-node triangles, 10-node tetrahedra, "
          "midside nodes on the curved boundary); a bare surface is order 1 only",
          false, 1.0};
}

/// The element order asked for, checked: 1 or 2, and 1 for a bare surface
/// (its facets are straight, and rigid masters stay linear).
int checked_order(const std::string& kind, const Generator& generator, const Params& p) {
  const double order = p.at("order");
  if (order != 1.0 && order != 2.0)
    throw InputError(fmt::format("generator '{}': parameter 'order' = {:g} (expected 1 or 2)", kind, order));
  if (generator.surface && order != 1.0)
    throw InputError(fmt::format(
        "generator '{}': order = 2, but it makes a bare surface of straight facets without cells (expected order = 1)",
        kind));
  return static_cast<int>(order);
}

/// Divides every length by the largest one (returned).
double normalise(const GeneratorInfo& info, Params& p) {
  double scale = 0.0;
  for (const GeneratorParameter& q : info.parameters)
    if (q.unit == "m" && q.name != "size") scale = std::max(scale, p.at(q.name));
  for (const GeneratorParameter& q : info.parameters)
    if (q.unit == "m") p[q.name] /= scale;
  return scale;
}

}  // namespace

const std::map<std::string, GeneratorInfo>& generator_catalog() {
  static const std::map<std::string, GeneratorInfo> catalog = [] {
    std::map<std::string, GeneratorInfo> out;
    for (const auto& [name, generator] : generators()) {
      out[name] = generator.info;
      out[name].parameters.push_back(order_parameter());
    }
    return out;
  }();
  return catalog;
}

Mesh generate_mesh(const std::string& kind, const std::map<std::string, double>& params) {
  const Generator& generator = find_generator(kind);
  Params p = checked_parameters(kind, generator_catalog().at(kind), params);
  const int order = checked_order(kind, generator, p);
  check_shape(kind, generator, p);
  if (generator.surface) return generator.surface(p);
  detail::GmshRecipe recipe;
  recipe.name = kind;
  recipe.dim = generator.info.dim;
  recipe.order = order;
  recipe.scale = normalise(generator.info, p);
  recipe.size = p.at("size");
  recipe.build = [&generator, p] { generator.build(p); };
  recipe.classify = [&generator, p](const EntityShape& s) { return generator.classify(s, p); };
  return detail::mesh_with_gmsh(recipe);
}

}  // namespace conserve::mesh
