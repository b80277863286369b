#pragma once
/// Private to the scenario parser: the parsers of the [[body]],
/// [[boundary]] and [[contact]] tables (scenario_body.cpp,
/// scenario_mesh.cpp, scenario_contact.cpp).
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "io/scenario.hpp"
#include "io/toml_section.hpp"

namespace conserve::io::detail {

/// Fails on key `key` of `s` unless `name` keeps kNameRule (io/names.hpp);
/// `what` ("", "body ", "group ") starts the message.
void check_name(const Section& s, std::string_view key, std::string_view name, std::string_view what = "");

/// The body called `name`, or nullptr.
const BodySpec* find_body(const std::vector<BodySpec>& bodies, std::string_view name);

/// "a, b, c": the body names, for messages.
std::string body_names(const std::vector<BodySpec>& bodies);

/// All [[curve]] tables of the top level; names are unique.
std::vector<CurveSpec> parse_curves(const Section& top);

/// All [[body]] tables of the top level; names are unique, curves named
/// are among `curves`.
std::vector<BodySpec> parse_bodies(const Section& top, const std::filesystem::path& scenario_file,
                                   const std::vector<CurveSpec>& curves);

/// All [[boundary]] tables of the top level; each names one of `bodies`,
/// not a rigid one, and a curve among `curves` if any.
std::vector<BoundarySpec> parse_boundaries(const Section& top, const std::vector<BodySpec>& bodies,
                                           const std::vector<CurveSpec>& curves);

/// All [[load]] tables of the top level; each names a deformable body.
std::vector<LoadSpec> parse_loads(const Section& top, const std::vector<BodySpec>& bodies,
                                  const std::vector<CurveSpec>& curves);

/// The curve key `key` of `s` (empty if absent): fails unless it names one of `curves`.
std::string curve_name(const Section& s, std::string_view key, const std::vector<CurveSpec>& curves);

/// All [[contact]] tables of the top level (scenario_contact.cpp).
std::vector<ContactSpec> parse_contacts(const Section& top, const std::vector<BodySpec>& bodies);
/// [general_contact]: the pairs it makes (none without the table);
/// refused together with [[contact]] tables (`with_pairs`).
std::vector<ContactSpec> parse_general_contact(const Section& top, const std::vector<BodySpec>& bodies,
                                               bool with_pairs);

/// The [active_set] table (defaults if absent).
ActiveSetSpec parse_active_set(const Section& active_set);

/// One [body.mesh] table: a file (resolved against the scenario's folder,
/// must exist) or a generator with its parameters checked and completed.
MeshSpec parse_mesh(const Section& mesh, const std::filesystem::path& scenario_file);

}  // namespace conserve::io::detail
