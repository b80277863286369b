/// Scenario parsing: [[contact]] pairs and [active_set].
#include <fmt/format.h>

#include "io/scenario_parts.hpp"

namespace conserve::io::detail {
namespace {

/// "body" or "body:group" of a surface key, split.
struct SurfaceName {
  std::string body;
  std::string group;
};

constexpr std::string_view kSurfaceForm = "\"body\" or \"body:group\"";

/// Parses the surface key `key` ("slave" or "master"): the body must exist,
/// the group (default "boundary") must not be empty, both keep kNameRule.
SurfaceName parse_surface(const Section& s, std::string_view key, const std::vector<BodySpec>& bodies) {
  const auto text = s.string(key);
  const auto colon = text.find(':');
  SurfaceName surface{text.substr(0, colon), colon == std::string::npos ? "boundary" : text.substr(colon + 1)};
  if (!surface.body.empty()) check_name(s, key, surface.body, "body ");
  if (!surface.group.empty()) check_name(s, key, surface.group, "group ");
  if (surface.body.empty()) s.fail(key, fmt::format("'{}' names no body", text), kSurfaceForm);
  if (!find_body(bodies, surface.body)) {
    s.fail(key, fmt::format("unknown body '{}'", surface.body), "a body, one of: " + body_names(bodies));
  }
  if (surface.group.empty()) {
    s.fail(key, fmt::format("'{}' has an empty group name", text),
           fmt::format("{} with a non-empty group", kSurfaceForm));
  }
  return surface;
}

ContactKind kind_of(const std::string& kind) {
  return kind == "stick" ? ContactKind::stick : kind == "coulomb" ? ContactKind::coulomb : ContactKind::frictionless;
}

/// The friction of a table with keys `kind` and `friction`: required with
/// kind = "coulomb", refused otherwise.
double friction_of(const Section& s) {
  const std::string kind = s.string("kind");
  if (kind == "coulomb" && !s.has("friction"))
    s.fail("kind", "is \"coulomb\" without a friction coefficient", "friction = μ (≥ 0) with kind = \"coulomb\"");
  if (kind != "coulomb" && s.has("friction"))
    s.fail("friction", fmt::format("is read with kind = \"coulomb\" only (kind is \"{}\")", kind),
           "no friction key, or kind = \"coulomb\"");
  return s.number("friction");
}

ContactSpec parse_contact(const Section& s, const std::vector<BodySpec>& bodies) {
  const SurfaceName slave = parse_surface(s, "slave", bodies);
  if (find_body(bodies, slave.body)->rigid) {
    s.fail("slave",
           fmt::format("'{}' is rigid, and a rigid body cannot be the slave; swap slave and master", slave.body),
           "a deformable slave body");
  }
  const SurfaceName master = parse_surface(s, "master", bodies);
  ContactSpec contact;
  contact.slave_body = slave.body;
  contact.slave_group = slave.group;
  contact.master_body = master.body;
  contact.master_group = master.group;
  contact.kind = kind_of(s.string("kind"));
  contact.friction = friction_of(s);
  contact.depth_factor = s.number("depth_factor");
  contact.passes = s.integer("passes");
  const BodySpec& master_body = *find_body(bodies, master.body);
  if (contact.passes > 2)
    s.fail("passes", fmt::format("{} passes", contact.passes), "1 (slave nodes held) or 2 (both sides' nodes held)");
  if (contact.passes == 2 && master.body == slave.body && master.group == slave.group)
    s.fail("passes", fmt::format("is 2 for '{}:{}' against itself: self-contact holds every node already", master.body,
                                 master.group),
           "passes = 1 for a surface against itself");
  if (contact.passes == 2 && master_body.rigid && master_body.free)
    s.fail("passes",
           fmt::format("is 2, but the master '{}' is a free rigid body: its nodes have no unknowns of their own "
                       "to be held out of the slave's facets by",
                       master.body),
           "passes = 1 against a free rigid master");
  contact.method = s.string("method");
  // Measured with every [[contact]] in two passes: stick and Coulomb
  // pairs lost E + D by 1.7e-2 (2D) and 3.8e-2 (3D) on an oblique impact
  // (Friction.ObliqueImpactKeepsMomentaAndEnergyWithTheDissipation), and
  // their reduced tangent was of first order.
  if (contact.passes == 2 && contact.kind != ContactKind::frictionless)
    s.fail("passes",
           fmt::format("is 2 with kind = \"{}\": two passes hold frictionless constraints only (with stick or "
                       "friction they do not yet keep the energy)",
                       s.string("kind")),
           "passes = 2 with kind = \"frictionless\", or passes = 1");
  contact.penalty = s.number("penalty");
  contact.penalty_force = s.string("penalty_force") == "midpoint" ? PenaltyForce::midpoint : PenaltyForce::conserving;
  return contact;
}

std::string slave_name(const ContactSpec& c) { return c.slave_body + ":" + c.slave_group; }
std::string master_name(const ContactSpec& c) { return c.master_body + ":" + c.master_group; }

}  // namespace

std::vector<ContactSpec> parse_contacts(const Section& top, const std::vector<BodySpec>& bodies) {
  std::vector<ContactSpec> contacts;
  for (const auto& table : top.table_array("contact")) {
    ContactSpec c = parse_contact(table, bodies);
    // Later pairs take the first pair's method unless they name one: one
    // key changes the method of a whole scenario.
    if (!contacts.empty() && !table.has("method")) c.method = contacts.front().method;
    if (!contacts.empty() && !table.has("penalty_force")) c.penalty_force = contacts.front().penalty_force;
    if (!contacts.empty() && c.method != contacts.front().method)
      table.fail("method",
                 fmt::format("'{}' differs from contact[0]'s '{}'; one constraint method serves every pair", c.method,
                             contacts.front().method),
                 fmt::format("method = \"{}\" as in contact[0]", contacts.front().method));
    if (c.method != "penalty")
      for (const char* key : {"penalty", "penalty_force"})
        if (table.has(key))
          table.fail(key, "is read by method = \"penalty\" only",
                     fmt::format("no {} key, or method = \"penalty\"", key));
    if (!contacts.empty() && c.penalty_force != contacts.front().penalty_force)
      table.fail("penalty_force", "differs from contact[0]'s; one force evaluation serves every pair",
                 "the same penalty_force in every [[contact]]");
    // Both directions of one pair of surfaces are one contact with
    // passes = 2, which holds the second pass's repeats apart.
    const std::string slave = slave_name(c), master = master_name(c);
    for (std::size_t j = 0; j < contacts.size(); ++j) {
      const std::string earlier_slave = slave_name(contacts[j]), earlier_master = master_name(contacts[j]);
      if (earlier_slave == slave && earlier_master == master) {
        table.fail("master", fmt::format("contact[{}] holds the same two surfaces ('{}' on '{}')", j, slave, master),
                   "each pair of surfaces in one contact");
      }
      if (earlier_slave == master && earlier_master == slave) {
        table.fail("master",
                   fmt::format("contact[{}] holds the same two surfaces the other way round ('{}' on '{}')", j,
                               master, slave),
                   "one contact per pair of surfaces, with passes = 2 to hold both sides' nodes");
      }
    }
    contacts.push_back(std::move(c));
  }
  return contacts;
}

// Every two bodies not excluded, and each deformable one with itself:
// deformable pairs in `passes` (one with stick or friction; the earlier
// body's nodes the first pass's slaves, swapped for the finer surface's by
// make_contact_pairs), a deformable body's nodes against a rigid one's
// facets, rigid pairs none; whole boundaries. A [[general_contact.pair]]
// sets one pair's kind, passes or both.
std::vector<ContactSpec> parse_general_contact(const Section& top, const std::vector<BodySpec>& bodies,
                                               bool with_pairs) {
  if (!top.has("general_contact")) return {};
  const Section g = top.table("general_contact");
  if (with_pairs)
    g.fail_table("is given with [[contact]] tables",
                 "one of the two: [general_contact] pairs every body, [[general_contact.pair]] sets one pair");
  const std::vector<std::string> exclude = g.names("exclude");
  for (const std::string& name : exclude)
    if (!find_body(bodies, name))
      g.fail("exclude", fmt::format("unknown body '{}'", name), "bodies, out of: " + body_names(bodies));
  auto excluded = [&](const std::string& name) {
    return std::find(exclude.begin(), exclude.end(), name) != exclude.end();
  };
  struct Override {
    std::vector<std::string> bodies;
    std::optional<ContactKind> kind;
    double friction;
    std::optional<int> passes;
  };
  std::vector<Override> overrides;
  for (const Section& pair : g.table_array("pair")) {
    std::vector<std::string> names = pair.names("bodies");
    if (names.empty() || names.size() > 2)
      pair.fail("bodies", fmt::format("names {} bodies", names.size()), "one body (its self-contact) or two");
    for (const std::string& name : names) {
      if (!find_body(bodies, name))
        pair.fail("bodies", fmt::format("unknown body '{}'", name), "bodies, out of: " + body_names(bodies));
      if (excluded(name))
        pair.fail("bodies", fmt::format("'{}' is excluded", name), "bodies that [general_contact] pairs");
    }
    if (!pair.has("kind") && !pair.has("passes"))
      pair.fail_table("sets neither kind nor passes", "kind = \"…\" or passes = 1 or 2 for the pair");
    const bool self = names.size() == 1;
    if (self) names.push_back(names.front());
    std::sort(names.begin(), names.end());
    Override o{names, std::nullopt, 0.0, std::nullopt};
    if (pair.has("kind")) {
      o.kind = kind_of(pair.string("kind"));
      o.friction = friction_of(pair);
    } else if (pair.has("friction")) {
      pair.fail("friction", "is given without the pair's kind", "kind = \"coulomb\" with friction = μ");
    }
    if (pair.has("passes")) {
      o.passes = pair.integer("passes");
      const bool rigid = find_body(bodies, names[0])->rigid || find_body(bodies, names[1])->rigid;
      const ContactKind kind = o.kind.value_or(kind_of(g.string("kind")));
      if (*o.passes == 2 && self)
        pair.fail("passes", fmt::format("is 2 for '{}' with itself: self-contact holds every node already", names[0]),
                  "passes = 1, or two bodies");
      if (*o.passes == 2 && rigid)
        pair.fail("passes", "is 2 for a pair with a rigid body: general contact holds a rigid body's pairs in one pass",
                  "passes = 1, or two deformable bodies");
      if (*o.passes == 2 && kind != ContactKind::frictionless)
        pair.fail("passes", "is 2 with a kind other than frictionless: two passes hold frictionless constraints only",
                  "passes = 2 with kind = \"frictionless\", or passes = 1");
    }
    overrides.push_back(std::move(o));
  }
  ContactSpec base;
  base.kind = kind_of(g.string("kind"));
  base.friction = friction_of(g);
  base.method = g.string("method");
  const int deformable_passes = g.integer("passes");
  std::vector<ContactSpec> out;
  auto add = [&](const BodySpec& slave, const BodySpec& master, int passes) {
    ContactSpec c = base;
    c.slave_body = slave.name;
    c.master_body = master.name;
    c.passes = passes;
    c.finer_slave = !slave.rigid && !master.rigid && slave.name != master.name;
    std::vector<std::string> key{slave.name, master.name};
    std::sort(key.begin(), key.end());
    for (const Override& o : overrides) {
      if (o.bodies != key) continue;
      if (o.kind) c.kind = *o.kind, c.friction = o.friction;
      if (o.passes) c.passes = *o.passes;
    }
    if (c.kind != ContactKind::frictionless) c.passes = 1;  // two passes hold frictionless constraints only
    out.push_back(std::move(c));
  };
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    if (excluded(bodies[i].name)) continue;
    for (std::size_t j = i + 1; j < bodies.size(); ++j) {
      if (excluded(bodies[j].name) || (bodies[i].rigid && bodies[j].rigid)) continue;
      if (bodies[i].rigid)
        add(bodies[j], bodies[i], 1);
      else if (bodies[j].rigid)
        add(bodies[i], bodies[j], 1);
      else
        add(bodies[i], bodies[j], deformable_passes);
    }
  }
  if (g.boolean("self"))
    for (const BodySpec& b : bodies)
      if (!b.rigid && !excluded(b.name)) add(b, b, 1);
  return out;
}

ActiveSetSpec parse_active_set(const Section& active_set) {
  ActiveSetSpec spec;
  spec.max_passes = active_set.integer("max_passes");
  spec.scheme = active_set.string("scheme") == "persistent" ? ContactScheme::persistent : ContactScheme::paper;
  // The paper's scheme is one key away: with it impacts are not located
  // unless asked for (its slaves bounce off at every activation, and each
  // return would be another split).
  spec.locate_impacts = active_set.has("locate_impacts") ? active_set.boolean("locate_impacts")
                                                         : spec.scheme == ContactScheme::persistent;
  spec.gap_tolerance = active_set.number("gap_tolerance");
  spec.cluster_tolerance = active_set.number("cluster_tolerance");
  if (spec.cluster_tolerance < spec.gap_tolerance)
    active_set.fail("cluster_tolerance",
                    fmt::format("{} is below gap_tolerance = {}", spec.cluster_tolerance, spec.gap_tolerance),
                    "at least gap_tolerance: impacts that follow others are located no closer than a first one");
  spec.locate_releases = active_set.boolean("locate_releases");
  // With the paper's velocity an active slave's force reverses from step to
  // step (chatter), and the steps would shrink at every reversal: a block
  // settling on a plane took 12× the steps and 20000 activations in 0.3 s.
  if (spec.locate_releases && spec.scheme != ContactScheme::persistent)
    active_set.fail("locate_releases",
                    "needs scheme = \"persistent\": with the paper's velocity the slaves' forces reverse from step "
                    "to step, and the steps would shrink at every reversal",
                    "scheme = \"persistent\" with it, or false");
  return spec;
}

}  // namespace conserve::io::detail
