/// Scenario parsing: [[body]] with [body.material] (rigid or deformable),
/// and [[boundary]].
#include <fmt/format.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.hpp"
#include "io/names.hpp"
#include "material/law.hpp"
#include "io/scenario_parts.hpp"

namespace conserve::io::detail {
namespace {

std::string law_parameter_names(const material::LawInfo& info) {
  std::string names;
  for (const auto& p : info.parameters) names += (names.empty() ? "" : ", ") + p.name;
  return names;
}

/// "a finite number [Pa] > 0", as the parser describes its own keys.
std::string describe(const material::LawParameter& p) {
  std::string range;
  if (p.min > -std::numeric_limits<double>::infinity())
    range += fmt::format(" {} {:g}", p.min_inclusive ? "≥" : ">", p.min);
  if (p.max < std::numeric_limits<double>::infinity())
    range += fmt::format("{} < {:g}", range.empty() ? "" : " and", p.max);
  return fmt::format("a finite number{}{}", p.unit.empty() ? "" : " [" + p.unit + "]", range);
}

double law_parameter(const Section& s, const material::LawParameter& p, const std::string& model) {
  const toml::node* node = s.find(p.name);
  if (!node) s.fail(p.name, fmt::format("missing key (a parameter of model '{}')", model), describe(p));
  const auto value = number_value(*node);
  if (!value) s.fail(p.name, fmt::format("got {}", type_of(*node)), describe(p));
  if (!std::isfinite(*value)) s.fail(p.name, fmt::format("{} is not finite", *value), describe(p));
  const bool above = p.min_inclusive ? *value >= p.min : *value > p.min;
  if (!above || !(*value < p.max))
    s.fail(p.name, fmt::format("{} is out of range", *value), describe(p));
  return *value;
}

/// The model's parameters, each within its range; a key that is none of
/// them (or `model`, `density`) is refused, naming it.
MaterialSpec parse_material(const Section& s) {
  MaterialSpec material;
  material.model = s.string("model");
  const auto& catalog = material::law_catalog();
  const auto it = catalog.find(material.model);
  if (it == catalog.end()) {
    std::string models;
    for (const auto& [name, info] : catalog) models += (models.empty() ? "" : ", ") + name;
    s.fail("model", fmt::format("unknown material model '{}'", material.model), "one of: " + models);
  }
  const material::LawInfo& info = it->second;
  for (const std::string& key : s.keys_in_file_order()) {
    if (key == "model" || key == "density") continue;
    const bool known = std::any_of(info.parameters.begin(), info.parameters.end(),
                                   [&](const material::LawParameter& p) { return p.name == key; });
    if (!known)
      s.fail(key, fmt::format("unknown key '{}' (not a parameter of model '{}')", key, material.model),
             fmt::format("one of: {}, density, model", law_parameter_names(info)));
  }
  for (const auto& p : info.parameters) material.parameters[p.name] = law_parameter(s, p, material.model);
  material.density = s.number("density");
  try {
    info.make(material.parameters);
  } catch (const InputError& e) {
    s.fail_table(e.what(), fmt::format("parameters model '{}' can take", material.model));
  }
  return material;
}

Eigen::Matrix3d parse_initial_deformation(const Section& s) {
  const Eigen::Matrix3d f0 = s.matrix("initial_deformation");
  const double det = f0.determinant();  // the identity-padded 2×2 block in 2D
  if (!(det > 0.0)) {
    s.fail("initial_deformation", fmt::format("det F0 = {} is not positive", det),
           "an invertible, orientation-preserving F0");
  }
  return f0;
}

/// [body.rotate]: `degrees` about `axis` (3D) or z (2D), or a `matrix`.
Eigen::Matrix3d parse_rotate(const Section& body) {
  if (!body.has("rotate")) return Eigen::Matrix3d::Identity();
  const Section s = body.table("rotate");
  const bool by_angle = s.has("degrees"), by_matrix = s.has("matrix");
  if (by_angle == by_matrix)
    s.fail_table(by_angle ? "has both `degrees` and `matrix`" : "has neither `degrees` nor `matrix`",
                 s.dimension() == 3 ? "either `axis` and `degrees`, or `matrix`" : "either `degrees` or `matrix`");
  if (by_matrix) {
    if (s.has("axis")) s.fail("axis", "is not used with `matrix`", "no axis beside a rotation matrix");
    const Eigen::Matrix3d R = s.matrix("matrix");
    const double error = (R * R.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
    if (!(error <= 1e-9) || !(R.determinant() > 0.0))
      s.fail("matrix", fmt::format("is not a rotation (|R Rᵀ − I| = {:.3g}, det R = {:.6g})", error, R.determinant()),
             "an orthogonal matrix with determinant 1, to 1e-9");
    return R;
  }
  const double angle = s.number("degrees") * std::acos(-1.0) / 180.0;
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  if (s.dimension() == 2) {
    if (s.has("axis")) s.fail("axis", "is only meaningful in 3D", "no axis in 2D (the rotation is about z)");
  } else {
    if (!s.has("axis")) s.fail("axis", "missing key", "the axis to turn about, 3 numbers, with `degrees`");
    axis = s.vector("axis");
    if (!(axis.norm() > 0.0)) s.fail("axis", "is zero", "a direction: 3 numbers, not all zero");
  }
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

double parse_thickness(const Section& s) {
  if (s.dimension() == 3 && s.has("thickness")) {
    s.fail("thickness", "is only meaningful in 2D", "no thickness with dimension = 3");
  }
  return s.number("thickness");
}

/// A rigid body moves as prescribed: it takes no initial deformation.
void reject_on_rigid_body(const Section& s, std::string_view key) {
  if (s.has(key)) {
    s.fail(key, "is not allowed on a rigid body",
           fmt::format("no {} with rigid = true: a rigid body moves as its velocity and angular velocity say", key));
  }
}

/// The keys of a prescribed rigid motion, on a deformable body.
void reject_on_deformable_body(const Section& s, std::string_view key) {
  if (s.has(key))
    s.fail(key, "is only allowed on a rigid body",
           fmt::format("no {} without rigid = true (a deformable body's velocity is its initial one)", key));
}

/// The material: required for a deformable body, optional (but validated)
/// for a rigid one, which without it keeps zeros (setup makes it massless).
/// A rigid body's material may be its density alone (its elastic
/// constants are not used); given, they are checked as a deformable body's.
MaterialSpec parse_body_material(const Section& s, bool rigid, bool optional) {
  if (!s.has("material")) {
    if (!optional)
      s.fail("material", rigid ? "a free rigid body needs a density" : "missing key",
             rigid ? "[body.material] with density > 0" : "a table [material]; only a rigid body may omit it");
    return {};
  }
  const Section material = s.table("material");
  if (rigid && material.keys_in_file_order() == std::vector<std::string>{"density"}) {
    MaterialSpec out;
    out.density = material.number("density");
    return out;
  }
  return parse_material(material);
}

BodySpec parse_body(const Section& s, const std::filesystem::path& scenario_file,
                    const std::vector<CurveSpec>& curves) {
  BodySpec body;
  body.name = s.string("name");
  check_name(s, "name", body.name);
  body.rigid = s.boolean("rigid");
  body.free = s.boolean("free");
  if (body.free && !body.rigid) s.fail("free", "is only allowed on a rigid body", "rigid = true with free = true");
  if (body.free) {
    for (const char* key : {"center", "velocity_curve", "angular_velocity_curve"})
      if (s.has(key))
        s.fail(key, "is not allowed on a free rigid body",
               fmt::format("no {}: a free body turns about its centre of mass, at the rate contact and its "
                           "initial spin give",
                           key));
  }
  if (body.rigid) {
    reject_on_rigid_body(s, "initial_deformation");
    if (s.has("center")) body.center = s.vector("center");
    body.velocity_curve = curve_name(s, "velocity_curve", curves);
    body.angular_velocity_curve = curve_name(s, "angular_velocity_curve", curves);
  } else {
    for (const char* key : {"center", "velocity_curve", "angular_velocity_curve"}) reject_on_deformable_body(s, key);
  }
  body.translate = s.vector("translate");
  body.rotate = parse_rotate(s);
  body.velocity = s.vector("velocity");
  body.angular_velocity = s.angular_velocity("angular_velocity");
  body.initial_deformation = parse_initial_deformation(s);
  body.thickness = parse_thickness(s);
  body.mean_dilatation = s.string("dilatation") == "mean";
  if (body.mean_dilatation && body.rigid)
    s.fail("dilatation", "is not allowed on a rigid body", "no dilatation: a rigid body does not deform");
  body.material = parse_body_material(s, body.rigid, body.rigid && !body.free);
  if (body.free && !(body.material.density > 0.0))
    s.fail("material", "a free rigid body needs a density", "[body.material] with density > 0");
  body.mesh = parse_mesh(s.table("mesh"), scenario_file);
  return body;
}

BoundarySpec parse_boundary(const Section& s, const std::vector<BodySpec>& bodies,
                            const std::vector<CurveSpec>& curves) {
  BoundarySpec boundary;
  boundary.body = s.string("body");
  check_name(s, "body", boundary.body);
  const auto body = find_body(bodies, boundary.body);
  if (!body) s.fail("body", fmt::format("unknown body '{}'", boundary.body), "one of: " + body_names(bodies));
  if (body->rigid) {
    s.fail("body", fmt::format("body '{}' is rigid: all its degrees of freedom are already prescribed", body->name),
           "a deformable body (a rigid body moves at its velocity; it takes no [[boundary]])");
  }
  boundary.group = s.string("group");
  check_name(s, "group", boundary.group);
  boundary.components = s.components("components");
  boundary.value = s.vector("value");
  boundary.rate = s.vector("rate");
  boundary.curve = curve_name(s, "curve", curves);
  return boundary;
}

}  // namespace

void check_name(const Section& s, std::string_view key, std::string_view name, std::string_view what) {
  if (const std::string problem = name_problem(name); !problem.empty())
    s.fail(key, fmt::format("{}{}", what, problem), kNameRule);
}

const BodySpec* find_body(const std::vector<BodySpec>& bodies, std::string_view name) {
  const auto it = std::find_if(bodies.begin(), bodies.end(), [&](const BodySpec& b) { return b.name == name; });
  return it == bodies.end() ? nullptr : &*it;
}

std::string body_names(const std::vector<BodySpec>& bodies) {
  std::string names;
  for (const auto& body : bodies) names += (names.empty() ? "" : ", ") + body.name;
  return names;
}

std::string curve_name(const Section& s, std::string_view key, const std::vector<CurveSpec>& curves) {
  if (!s.has(key)) return {};
  const std::string name = s.string(key);
  std::string names;
  for (const CurveSpec& c : curves) {
    if (c.name == name) return name;
    names += (names.empty() ? "" : ", ") + c.name;
  }
  s.fail(key, fmt::format("no [[curve]] named '{}'", name),
         names.empty() ? std::string("a [[curve]] table with that name") : "one of: " + names);
}

std::vector<LoadSpec> parse_loads(const Section& top, const std::vector<BodySpec>& bodies,
                                  const std::vector<CurveSpec>& curves) {
  std::vector<LoadSpec> loads;
  for (const Section& s : top.table_array("load")) {
    LoadSpec load;
    load.body = s.string("body");
    check_name(s, "body", load.body);
    const auto body = find_body(bodies, load.body);
    if (!body) s.fail("body", fmt::format("unknown body '{}'", load.body), "one of: " + body_names(bodies));
    if (body->rigid)
      s.fail("body", fmt::format("body '{}' is rigid: its motion is prescribed", body->name), "a deformable body");
    load.group = s.string("group");
    check_name(s, "group", load.group);
    if (s.has("traction") == s.has("pressure"))
      s.fail_table(s.has("traction") ? "has both 'traction' and 'pressure'" : "has neither 'traction' nor 'pressure'",
                   "exactly one of them");
    load.pressure = s.has("pressure");
    load.traction = s.vector("traction");
    if (load.pressure) load.pressure_value = s.number("pressure");
    load.curve = curve_name(s, "curve", curves);
    loads.push_back(std::move(load));
  }
  return loads;
}

std::vector<CurveSpec> parse_curves(const Section& top) {
  std::vector<CurveSpec> curves;
  for (const Section& table : top.table_array("curve")) {
    CurveSpec curve;
    curve.name = table.string("name");
    check_name(table, "name", curve.name);
    for (const CurveSpec& earlier : curves)
      if (earlier.name == curve.name)
        table.fail("name", fmt::format("duplicate curve name '{}'", curve.name), "a name no other [[curve]] has");
    curve.points = table.points("points");
    curves.push_back(std::move(curve));
  }
  return curves;
}

std::vector<BodySpec> parse_bodies(const Section& top, const std::filesystem::path& scenario_file,
                                   const std::vector<CurveSpec>& curves) {
  std::vector<BodySpec> bodies;
  const auto tables = top.table_array("body");
  for (std::size_t i = 0; i < tables.size(); ++i) {
    const auto name = tables[i].string("name");
    const auto earlier = std::find_if(bodies.begin(), bodies.end(), [&](const BodySpec& b) { return b.name == name; });
    if (earlier != bodies.end()) {
      tables[i].fail("name", fmt::format("duplicate body name '{}'", name),
                     fmt::format("a name not used by body[{}]", earlier - bodies.begin()));
    }
    bodies.push_back(parse_body(tables[i], scenario_file, curves));
  }
  return bodies;
}

std::vector<BoundarySpec> parse_boundaries(const Section& top, const std::vector<BodySpec>& bodies,
                                           const std::vector<CurveSpec>& curves) {
  std::vector<BoundarySpec> boundaries;
  for (const auto& table : top.table_array("boundary")) boundaries.push_back(parse_boundary(table, bodies, curves));
  return boundaries;
}

}  // namespace conserve::io::detail
