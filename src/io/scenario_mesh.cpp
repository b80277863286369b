/// Scenario parsing: [body.mesh], a mesh file or a generator whose
/// parameters are checked against mesh::generator_catalog(); `order` (the
/// generator's element order, which every generator takes) is a declared
/// key of [body.mesh], checked as an integer 1 or 2.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "io/scenario_parts.hpp"
#include "mesh/generators.hpp"

namespace conserve::io::detail {
namespace {

namespace fs = std::filesystem;

fs::path resolve_mesh_file(const Section& s, const fs::path& scenario_file) {
  const auto text = s.string("file");
  if (text.empty()) s.fail("file", "is empty", "the path of a .msh or .stl file");
  fs::path file(text);
  if (file.is_relative()) file = scenario_file.parent_path() / file;
  file = fs::absolute(file).lexically_normal();
  std::error_code error;
  if (!fs::is_regular_file(file, error)) {
    s.fail("file", fmt::format("mesh file '{}' does not exist", file.string()),
           "an existing .msh or .stl file, relative to the scenario file's folder");
  }
  return file;
}

/// The keys of `s` other than "generator" and "order", in file order.
std::vector<std::string> keys_in_file_order(const Section& s) {
  std::vector<std::string> names = s.keys_in_file_order();
  names.erase(std::remove(names.begin(), names.end(), "generator"), names.end());
  names.erase(std::remove(names.begin(), names.end(), "order"), names.end());
  return names;
}

MeshSpec parse_file_mesh(const Section& s, const fs::path& scenario_file) {
  if (s.has("order"))
    s.fail("order", "is only allowed with 'generator'",
           "no 'order' with a file: its element types give it (3- or 6-node triangles, 4- or 10-node tetrahedra)");
  for (const auto& key : keys_in_file_order(s)) {
    if (key != "file" && key != "group" && key != "flip_normals" && key != "reorder") {
      s.fail(key, fmt::format("unknown key '{}'", key), "one of: " + key_names(s.spec()));
    }
  }
  MeshSpec mesh;
  mesh.file = resolve_mesh_file(s, scenario_file);
  mesh.group = s.string("group");
  mesh.flip_normals = s.boolean("flip_normals");
  mesh.reorder = s.boolean("reorder");
  return mesh;
}

std::string generator_names(int dim) {
  std::string names;
  for (const auto& [name, info] : mesh::generator_catalog()) {
    if (info.dim == dim) names += (names.empty() ? "" : ", ") + name;
  }
  return names;
}

/// The generator's own parameters (not `order`, a key of [body.mesh]).
std::string parameter_names(const mesh::GeneratorInfo& info) {
  std::string names;
  for (const auto& p : info.parameters)
    if (p.name != "order") names += (names.empty() ? "" : ", ") + p.name;
  return names;
}

std::string describe(const mesh::GeneratorParameter& p) {
  return fmt::format("a number{}: {}", p.unit.empty() ? "" : " [" + p.unit + "]", p.doc);
}

double parameter_value(const Section& s, const std::string& key, const std::string& generator,
                       const mesh::GeneratorInfo& info) {
  const auto known = std::find_if(info.parameters.begin(), info.parameters.end(),
                                  [&](const mesh::GeneratorParameter& p) { return p.name == key; });
  if (known == info.parameters.end()) {
    s.fail(key, fmt::format("unknown parameter '{}' of generator '{}'", key, generator),
           "one of: " + parameter_names(info));
  }
  const auto& node = *s.find(key);
  const auto value = number_value(node);
  if (!value) s.fail(key, fmt::format("got {}", type_of(node)), describe(*known));
  if (!std::isfinite(*value)) s.fail(key, fmt::format("{} is not finite", *value), describe(*known));
  return *value;
}

std::map<std::string, double> generator_parameters(const Section& s, const std::string& generator,
                                                   const mesh::GeneratorInfo& info) {
  std::map<std::string, double> values;
  for (const auto& key : keys_in_file_order(s)) values[key] = parameter_value(s, key, generator, info);
  // Parameters with defaults are left out when absent (mesh::generate_mesh
  // fills them in), so a scenario without `order` has the parameters it had.
  for (const auto& p : info.parameters) {
    if (!values.count(p.name) && p.required)
      s.fail(p.name, fmt::format("missing parameter of generator '{}'", generator), describe(p));
  }
  if (s.has("order")) values["order"] = s.integer("order");
  return values;
}

MeshSpec parse_generator_mesh(const Section& s) {
  MeshSpec mesh;
  mesh.generator = s.string("generator");
  if (s.has("group")) s.fail("group", "is only allowed with 'file'", "no 'group' with a generator");
  if (s.has("flip_normals"))
    s.fail("flip_normals", "is only allowed with 'file'", "no 'flip_normals' with a generator");
  if (s.has("reorder"))
    s.fail("reorder", "is only allowed with 'file'", "no 'reorder' with a generator (its nodes are reordered)");
  const auto& catalog = mesh::generator_catalog();
  const auto it = catalog.find(mesh.generator);
  const int dim = s.dimension();
  if (it == catalog.end()) {
    s.fail("generator", fmt::format("unknown generator '{}'", mesh.generator), "one of: " + generator_names(dim));
  }
  if (it->second.dim != dim) {
    s.fail("generator",
           fmt::format("generator '{}' makes {}D meshes but dimension = {}", it->first, it->second.dim, dim),
           fmt::format("a {}D generator, one of: {}", dim, generator_names(dim)));
  }
  mesh.parameters = generator_parameters(s, mesh.generator, it->second);
  return mesh;
}

}  // namespace

MeshSpec parse_mesh(const Section& s, const fs::path& scenario_file) {
  const bool file = s.has("file");
  const bool generator = s.has("generator");
  if (file && generator) s.fail_table("has both 'file' and 'generator'", "exactly one of them");
  if (!file && !generator) s.fail_table("has neither 'file' nor 'generator'", "exactly one of them");
  return file ? parse_file_mesh(s, scenario_file) : parse_generator_mesh(s);
}

}  // namespace conserve::io::detail
