/// Rigid bodies, [[contact]] pairs and [active_set]: valid input with its
/// defaults, and one test per validation rule with FILE:LINE and key path.
#include <gtest/gtest.h>

#include <algorithm>

#include "scenario_test_support.hpp"

namespace conserve::io {
namespace {

using cases::case_file;
using cases::fails_with;

/// Lines 1–11: minimal() with body "a" (deformable); 12–20: the rigid body
/// "plane" (a bare square, no material); `extra_plane` goes in after line
/// 15 (so it is line 16 and on), `rest` after the plane.
std::string two_bodies(std::string_view rest = "", std::string_view extra_plane = "") {
  return cases::minimal(
      "[[body]]\n"                  // 12
      "name = \"plane\"\n"          // 13
      "rigid = true\n"              // 14
      "velocity = [0, 0, 0.5]\n" +  // 15
      std::string(extra_plane) +
      "[body.mesh]\n"
      "generator = \"square\"\n"
      "lx = 2\n"
      "ly = 2\n"
      "size = 1\n" +
      std::string(rest));
}

/// A [[contact]] table starting on line 21 after two_bodies(): 22 slave,
/// 23 master, 24 kind, then `extra`.
std::string contact(std::string_view slave, std::string_view master, std::string_view extra = "") {
  return two_bodies("[[contact]]\nslave = \"" + std::string(slave) + "\"\nmaster = \"" + std::string(master) +
                    "\"\nkind = \"stick\"\n" + std::string(extra));
}

TEST(ScenarioRigid, RigidBodyWithoutMaterial) {
  const auto s = parse_scenario(two_bodies(), case_file());
  ASSERT_EQ(s.bodies.size(), 2u);
  EXPECT_FALSE(s.bodies[0].rigid);
  const auto& plane = s.bodies[1];
  EXPECT_TRUE(plane.rigid);
  EXPECT_EQ(plane.velocity, Eigen::Vector3d(0, 0, 0.5));
  EXPECT_EQ(plane.material.parameter("young"), 0.0);
  EXPECT_EQ(plane.material.density, 0.0);
  EXPECT_EQ(plane.mesh.generator, "square");
  EXPECT_EQ(plane.angular_velocity, Eigen::Vector3d::Zero());
  EXPECT_EQ(plane.initial_deformation, Eigen::Matrix3d::Identity());
}

TEST(ScenarioRigid, RigidFalseIsDeformable) {
  auto text = two_bodies("", "[body.material]\nyoung = 1e9\npoisson = 0.2\ndensity = 100\n");
  text.replace(text.find("rigid = true"), 12, "rigid = false");
  const auto s = parse_scenario(text, case_file());
  EXPECT_FALSE(s.bodies[1].rigid);
}

TEST(ScenarioRigid, MaterialOfARigidBodyIsStillValidated) {
  const auto material = "[body.material]\nyoung = 1e9\npoisson = 0.7\ndensity = 100\n";  // lines 16–19
  EXPECT_TRUE(fails_with(two_bodies("", material), 18, "body[1].material.poisson", "0.7 is out of range"));
  const auto s =
      parse_scenario(two_bodies("", "[body.material]\nyoung = 1e9\npoisson = 0.2\ndensity = 100\n"), case_file());
  EXPECT_EQ(s.bodies[1].material.density, 100.0);
}

TEST(ScenarioRigid, RigidMustBeABoolean) {
  auto text = two_bodies();
  text.replace(text.find("rigid = true"), 12, "rigid = 1");
  EXPECT_TRUE(fails_with(text, 14, "body[1].rigid", "got an integer (expected true or false)"));
}

TEST(ScenarioRigid, NoInitialDeformationOnARigidBody) {
  EXPECT_TRUE(fails_with(two_bodies("", "initial_deformation = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]\n"), 16,
                         "body[1].initial_deformation", "is not allowed on a rigid body"));
}

// A free rigid body: rigid, with a density (alone, or with the elastic
// constants, which are not used), and no centre or curves.
TEST(ScenarioRigid, FreeRigidBodyTakesItsDensityAlone) {
  const auto s = parse_scenario(two_bodies("", "free = true\n[body.material]\ndensity = 7800\n"), case_file());
  EXPECT_TRUE(s.bodies[1].free);
  EXPECT_EQ(s.bodies[1].material.density, 7800.0);
  EXPECT_FALSE(parse_scenario(two_bodies(), case_file()).bodies[1].free);
}

TEST(ScenarioRigid, FreeBodyRulesNameTheKey) {
  EXPECT_TRUE(fails_with(two_bodies("", "free = true\n"), 12, "body[1].material", "a free rigid body needs a density"));
  EXPECT_TRUE(fails_with(two_bodies("", "free = true\ncenter = [0, 0, 0]\n[body.material]\ndensity = 1\n"), 17,
                         "body[1].center", "is not allowed on a free rigid body"));
  auto deformable = two_bodies("", "free = true\n[body.material]\nyoung = 1e9\npoisson = 0.2\ndensity = 100\n");
  deformable.replace(deformable.find("rigid = true"), 12, "rigid = false");
  EXPECT_TRUE(fails_with(deformable, 16, "body[1].free", "is only allowed on a rigid body"));
}

// A rigid body turns about its centre, each rate scaled by a curve.
TEST(ScenarioRigid, PrescribedMotionWithCurves) {
  const auto s = parse_scenario(
      two_bodies("[[curve]]\nname = \"ramp\"\npoints = [[0, 0], [0.5, 1], [1, 1]]\n",
                 "angular_velocity = [0, 0, 2]\ncenter = [0, 0, 1]\nangular_velocity_curve = \"ramp\"\n"),
      case_file());
  const BodySpec& plane = s.bodies[1];
  EXPECT_EQ(plane.angular_velocity, Eigen::Vector3d(0, 0, 2));
  ASSERT_TRUE(plane.center.has_value());
  EXPECT_EQ(*plane.center, Eigen::Vector3d(0, 0, 1));
  EXPECT_EQ(plane.angular_velocity_curve, "ramp");
  EXPECT_TRUE(plane.velocity_curve.empty());
  ASSERT_EQ(s.curves.size(), 1u);
  EXPECT_EQ(s.curves[0].points.size(), 3u);
  EXPECT_EQ(s.curves[0].points[1], (std::pair<double, double>(0.5, 1.0)));
}

// Curves: times must increase; a name that no [[curve]] has; the
// motion keys on a deformable body.
TEST(ScenarioRigid, CurveErrors) {
  EXPECT_TRUE(fails_with(two_bodies("[[curve]]\nname = \"c\"\npoints = [[0, 0], [0.5, 1], [0.2, 1]]\n"), 23,
                         "curve[0].points[2]",
                         "time 0.2 does not come after 0.5 (point 1) (expected times that strictly increase)"));
  EXPECT_TRUE(fails_with(two_bodies("[[curve]]\nname = \"c\"\npoints = [[0, 0]]\n"), 23, "curve[0].points",
                         "has 1 point(s)"));
  EXPECT_TRUE(fails_with(two_bodies("", "velocity_curve = \"nope\"\n"), 16, "body[1].velocity_curve",
                         "no [[curve]] named 'nope' (expected a [[curve]] table with that name)"));
  EXPECT_TRUE(fails_with(two_bodies("[[curve]]\nname = \"c\"\npoints = [[0, 0], [1, 1]]\n[[curve]]\nname = \"c\"\n"
                                    "points = [[0, 0], [1, 1]]\n"),
                         25, "curve[1].name", "duplicate curve name 'c'"));
  std::string deformable = two_bodies("[[curve]]\nname = \"c\"\npoints = [[0, 0], [1, 1]]\n");
  deformable.insert(deformable.find("name = \"a\"\n") + 11, "velocity_curve = \"c\"\n");
  const auto line = 1 + std::count(deformable.begin(), deformable.begin() + deformable.find("velocity_curve"), '\n');
  EXPECT_TRUE(fails_with(deformable, static_cast<int>(line), "body[0].velocity_curve", "is only allowed on a rigid body"));
}

TEST(ScenarioRigid, DeformableBodyNeedsAMaterial) {
  auto text = two_bodies();
  text.replace(text.find("rigid = true\n"), 13, "\n");
  EXPECT_TRUE(fails_with(text, 12, "body[1].material", "missing key (expected a table [material]"));
}

TEST(ScenarioRigid, NoBoundaryOnARigidBody) {
  EXPECT_TRUE(fails_with(two_bodies("[[boundary]]\nbody = \"plane\"\ngroup = \"all\"\n"), 22, "boundary[0].body",
                         "body 'plane' is rigid: all its degrees of freedom are already prescribed"));
}

TEST(ScenarioRigid, TwoDimensionalRigidSegment) {
  const auto text = "dimension = 2\n" + cases::with_mesh("generator = \"disc\"\nradius = 1\nsize = 0.1\n",
                                                        "[[body]]\nname = \"ground\"\nrigid = true\nvelocity = [1, 0]\n"
                                                        "[body.mesh]\ngenerator = \"segment\"\nlx = 4\nsize = 1\n");
  const auto s = parse_scenario(text, case_file());
  EXPECT_TRUE(s.bodies[1].rigid);
  EXPECT_EQ(s.bodies[1].velocity, Eigen::Vector3d(1, 0, 0));
  EXPECT_EQ(s.bodies[1].mesh.parameters, (std::map<std::string, double>{{"lx", 4}, {"size", 1}}));
}

TEST(ScenarioContact, PairWithDefaults) {
  const auto s = parse_scenario(contact("a", "plane:surface"), case_file());
  ASSERT_EQ(s.contacts.size(), 1u);
  const ContactSpec& c = s.contacts[0];
  EXPECT_EQ(c.slave_body, "a");
  EXPECT_EQ(c.slave_group, "boundary");
  EXPECT_EQ(c.master_body, "plane");
  EXPECT_EQ(c.master_group, "surface");
  EXPECT_EQ(c.kind, ContactKind::stick);
  EXPECT_EQ(c.depth_factor, 0.5);
  EXPECT_EQ(s.active_set.max_passes, 30);
  // Located impacts with the persistent velocity by default (issue 46).
  EXPECT_EQ(s.active_set.scheme, ContactScheme::persistent);
  EXPECT_TRUE(s.active_set.locate_impacts);
}

// The paper's scheme is one key away: `scheme = "paper"` turns the impact
// location off with it, unless it is asked for.
TEST(ScenarioContact, ThePapersSchemeIsOneKeyAway) {
  const auto paper = parse_scenario(contact("a", "plane:surface", "[active_set]\nscheme = \"paper\"\n"), case_file());
  EXPECT_EQ(paper.active_set.scheme, ContactScheme::paper);
  EXPECT_FALSE(paper.active_set.locate_impacts);
  const auto both = parse_scenario(
      contact("a", "plane:surface", "[active_set]\nscheme = \"paper\"\nlocate_impacts = true\n"), case_file());
  EXPECT_TRUE(both.active_set.locate_impacts);
  const auto unlocated =
      parse_scenario(contact("a", "plane:surface", "[active_set]\nlocate_impacts = false\n"), case_file());
  EXPECT_EQ(unlocated.active_set.scheme, ContactScheme::persistent);
  EXPECT_FALSE(unlocated.active_set.locate_impacts);
}

TEST(ScenarioContact, EveryKeySet) {
  const auto text = contact("a:top", "plane", "depth_factor = 0.2\n") +
                    "[[contact]]\nslave = \"a:top\"\nmaster = \"a:bottom\"\nkind = \"frictionless\"\n"
                    "[active_set]\nmax_passes = 3\n";
  const auto s = parse_scenario(text, case_file());
  ASSERT_EQ(s.contacts.size(), 2u);
  EXPECT_EQ(s.contacts[0].slave_group, "top");
  EXPECT_EQ(s.contacts[0].master_group, "boundary");
  EXPECT_EQ(s.contacts[0].depth_factor, 0.2);
  EXPECT_EQ(s.contacts[1].kind, ContactKind::frictionless);
  EXPECT_EQ(s.contacts[1].slave_body, "a");
  EXPECT_EQ(s.contacts[1].master_body, "a");  // one body, two different groups: allowed
  EXPECT_EQ(s.active_set.max_passes, 3);
}

TEST(ScenarioContact, UnknownBodyIsNamedAndBodiesListed) {
  EXPECT_TRUE(fails_with(contact("ball:outer", "plane"), 22, "contact[0].slave",
                         "unknown body 'ball' (expected a body, one of: a, plane)"));
  EXPECT_TRUE(fails_with(contact("a", "floor"), 23, "contact[0].master", "unknown body 'floor'"));
  EXPECT_TRUE(fails_with(contact(":outer", "plane"), 22, "contact[0].slave", "':outer' names no body"));
}

TEST(ScenarioContact, EmptyGroupName) {
  EXPECT_TRUE(fails_with(contact("a:", "plane"), 22, "contact[0].slave", "'a:' has an empty group name"));
  EXPECT_TRUE(fails_with(contact("a", "plane:"), 23, "contact[0].master", "empty group name"));
}

// A surface against itself is self-contact, held in one pass.
TEST(ScenarioContact, ASurfaceAgainstItselfIsSelfContact) {
  const auto s = parse_scenario(contact("a", "a:boundary"), case_file());
  EXPECT_EQ(s.contacts[0].slave_group, s.contacts[0].master_group);
  EXPECT_TRUE(fails_with(contact("a:top", "a:top", "passes = 2\n"), 25, "contact[0].passes",
                         "is 2 for 'a:top' against itself: self-contact holds every node already"));
}

// Two contacts between the same two surfaces, swapped, or one given
// twice: one contact with passes = 2 holds both sides' nodes (and leaves
// out the second pass's constraints that repeat the first's). Refused
// when the file is read.
TEST(ScenarioContact, APairOfSurfacesIsGivenOnceInOneDirection) {
  const std::string swapped = "[[contact]]\nslave = \"a:bottom\"\nmaster = \"a:top\"\nkind = \"stick\"\n";
  EXPECT_TRUE(fails_with(contact("a:top", "a:bottom", swapped), 27, "contact[1].master",
                         "contact[0] holds the same two surfaces the other way round ('a:top' on 'a:bottom')"));
  const std::string twice = "[[contact]]\nslave = \"a\"\nmaster = \"plane:boundary\"\nkind = \"frictionless\"\n";
  EXPECT_TRUE(fails_with(contact("a:boundary", "plane", twice), 27, "contact[1].master",
                         "contact[0] holds the same two surfaces ('a:boundary' on 'plane:boundary')"));
  // Different groups of the same bodies stay allowed, in either direction.
  const std::string other = "[[contact]]\nslave = \"a:side\"\nmaster = \"a:top\"\nkind = \"stick\"\n";
  EXPECT_NO_THROW(parse_scenario(contact("a:top", "a:bottom", other), case_file()));
}

// passes: 1 (the default) or 2, two with kind = "frictionless" only, with
// any constraint method, against a deformable or a driven rigid master.
TEST(ScenarioContact, PassesAreOneOrTwoAndTwoAreFrictionless) {
  auto frictionless = [](std::string text) {
    text.replace(text.find("\"stick\""), 7, "\"frictionless\"");
    return text;
  };
  EXPECT_EQ(parse_scenario(contact("a:top", "a:bottom"), case_file()).contacts[0].passes, 1);
  EXPECT_EQ(parse_scenario(frictionless(contact("a:top", "a:bottom", "passes = 2\n")), case_file()).contacts[0].passes,
            2);
  EXPECT_TRUE(fails_with(contact("a:top", "a:bottom", "passes = 3\n"), 25, "contact[0].passes", "3 passes"));
  EXPECT_TRUE(fails_with(contact("a:top", "a:bottom", "passes = 0\n"), 25, "contact[0].passes", ""));
  EXPECT_TRUE(fails_with(contact("a:top", "a:bottom", "passes = 2\n"), 25, "contact[0].passes",
                         "is 2 with kind = \"stick\": two passes hold frictionless constraints only"));
  EXPECT_EQ(parse_scenario(frictionless(contact("a", "plane", "passes = 2\n")), case_file()).contacts[0].passes, 2);
  EXPECT_EQ(parse_scenario(frictionless(contact("a:top", "a:bottom", "passes = 2\nmethod = \"lagrange\"\n")),
                           case_file())
                .contacts[0]
                .method,
            "lagrange");
}

TEST(ScenarioContact, RigidBodyCannotBeTheSlave) {
  EXPECT_TRUE(fails_with(contact("plane:surface", "a"), 22, "contact[0].slave",
                         "a rigid body cannot be the slave; swap slave and master"));
}

TEST(ScenarioContact, KindIsRequiredAndChecked) {
  auto missing = contact("a", "plane");
  missing.replace(missing.find("kind = \"stick\"\n"), 15, "");
  EXPECT_TRUE(fails_with(missing, 21, "contact[0].kind", "missing key (expected one of: frictionless, stick, coulomb)"));
  auto wrong = contact("a", "plane");
  wrong.replace(wrong.find("\"stick\""), 7, "\"slip\"");
  EXPECT_TRUE(fails_with(wrong, 24, "contact[0].kind", "'slip' is not allowed (expected one of: frictionless, stick, coulomb)"));
}

TEST(ScenarioContact, RangesAndUnknownKeys) {
  EXPECT_TRUE(fails_with(contact("a", "plane", "depth_factor = 0\n"), 25, "contact[0].depth_factor",
                         "0 is out of range (expected a finite number > 0)"));
  EXPECT_TRUE(fails_with(contact("a", "plane", "mu = 0.3\n"), 25, "contact[0].mu",
                         "unknown key 'mu' (expected one of: slave, master, kind, friction, depth_factor, passes, method, penalty, "
                         "penalty_force)"));
  EXPECT_TRUE(fails_with(contact("a", "plane", "[active_set]\nmax_passes = 0\n"), 26, "active_set.max_passes",
                         "0 is out of range (expected an integer ≥ 1)"));
  EXPECT_TRUE(fails_with(contact("a", "plane", "[active_set]\npasses = 2\n"), 26, "active_set.passes", "unknown key"));
}

TEST(ScenarioContact, CoulombNeedsItsFrictionAndOnlyItReadsIt) {
  auto coulomb = [](const std::string& extra) {
    auto text = contact("a", "plane", extra);
    text.replace(text.find("\"stick\""), 7, "\"coulomb\"");
    return text;
  };
  EXPECT_TRUE(fails_with(coulomb(""), 24, "contact[0].kind", "is \"coulomb\" without a friction coefficient"));
  EXPECT_TRUE(fails_with(coulomb("friction = -0.1\n"), 25, "contact[0].friction", "-0.1 is out of range"));
  EXPECT_TRUE(fails_with(contact("a", "plane", "friction = 0.3\n"), 25, "contact[0].friction",
                         "is read with kind = \"coulomb\" only (kind is \"stick\")"));
  const auto s = parse_scenario(coulomb("friction = 0.3\n"), case_file());
  EXPECT_EQ(s.contacts[0].kind, io::ContactKind::coulomb);
  EXPECT_EQ(s.contacts[0].friction, 0.3);
  EXPECT_EQ(parse_scenario(coulomb("friction = 0.3\nmethod = \"penalty\"\n"), case_file()).contacts[0].method,
            "penalty");
}

TEST(ScenarioContact, SecondPairErrorsNameIndexOne) {
  const auto text = contact("a", "plane") + "[[contact]]\nslave = \"a\"\nmaster = \"wall\"\nkind = \"stick\"\n";
  EXPECT_TRUE(fails_with(text, 27, "contact[1].master", "unknown body 'wall'"));
}

// The constraint method (issue 46): one for every pair, later pairs taking
// the first's; the penalty's keys only with it, its stiffness ≥ 0.
TEST(ScenarioContact, MethodKeys) {
  const auto penalty = parse_scenario(contact("a", "plane", "method = \"penalty\"\npenalty = 2e9\n"), case_file());
  EXPECT_EQ(penalty.contacts[0].method, "penalty");
  EXPECT_EQ(penalty.contacts[0].penalty, 2e9);
  EXPECT_EQ(penalty.contacts[0].penalty_force, PenaltyForce::conserving);
  EXPECT_EQ(parse_scenario(contact("a", "plane"), case_file()).contacts[0].method, "elimination");
  const std::string second = "[[contact]]\nslave = \"a:side\"\nmaster = \"plane\"\nkind = \"frictionless\"\n";
  const auto inherited =
      parse_scenario(contact("a:top", "plane", "method = \"penalty\"\npenalty_force = \"midpoint\"\n" + second),
                     case_file());
  EXPECT_EQ(inherited.contacts[1].method, "penalty");
  EXPECT_EQ(inherited.contacts[1].penalty_force, PenaltyForce::midpoint);
  // A later pair's own ε with the first pair's method (as --set gives it).
  const auto own = parse_scenario(contact("a:top", "plane", "method = \"penalty\"\n" + second + "penalty = 3e9\n"),
                                  case_file());
  EXPECT_EQ(own.contacts[1].penalty, 3e9);
  EXPECT_TRUE(fails_with(contact("a:top", "plane", second + "method = \"penalty\"\n"), 29, "contact[1].method",
                         "'penalty' differs from contact[0]'s 'elimination'; one constraint method serves every pair"));
  EXPECT_TRUE(fails_with(contact("a", "plane", "penalty = 1e9\n"), 25, "contact[0].penalty",
                         "is read by method = \"penalty\" only"));
  EXPECT_TRUE(fails_with(contact("a", "plane", "method = \"penalty\"\npenalty = -1\n"), 26, "contact[0].penalty",
                         "-1 is out of range (expected a finite number [Pa/m] ≥ 0)"));
  EXPECT_TRUE(fails_with(contact("a", "plane", "method = \"multipliers\"\n"), 25, "contact[0].method",
                         "'multipliers' is not allowed (expected one of: elimination, lagrange, penalty)"));
}

}  // namespace
}  // namespace conserve::io

namespace conserve::io {
namespace {

/// two_bodies() with a second deformable body "c" and then `rest`; the
/// [general_contact] table below starts on line 30.
std::string three_bodies(std::string_view rest) {
  return two_bodies(
      "[[body]]\n"  // 21
      "name = \"c\"\n"
      "[body.material]\n"
      "young = 1e6\n"
      "poisson = 0.3\n"
      "density = 1000\n"
      "[body.mesh]\n"
      "file = \"meshes/cube.msh\"\n" +  // 28
      std::string(rest));
}

// [general_contact]: deformable pairs in two passes (frictionless; one
// with friction), a deformable body's
// nodes against a rigid one's facets, each deformable body with itself,
// whole boundaries; exclusions and one pair's own kind.
TEST(ScenarioGeneralContact, PairsEveryBodyAndEachWithItself) {
  const auto s = parse_scenario(three_bodies("[general_contact]\n"), case_file());
  ASSERT_EQ(s.contacts.size(), 5u);  // a–plane, a–c, c–plane, a self, c self
  auto find = [&](const std::string& slave, const std::string& master) -> const ContactSpec* {
    for (const ContactSpec& c : s.contacts)
      if (c.slave_body == slave && c.master_body == master) return &c;
    return nullptr;
  };
  ASSERT_NE(find("a", "plane"), nullptr);
  EXPECT_EQ(find("a", "plane")->passes, 1);
  ASSERT_NE(find("a", "c"), nullptr);
  EXPECT_EQ(find("a", "c")->passes, 2);
  EXPECT_NE(find("c", "plane"), nullptr);
  EXPECT_NE(find("a", "a"), nullptr);
  EXPECT_NE(find("c", "c"), nullptr);
  for (const ContactSpec& c : s.contacts) {
    EXPECT_EQ(c.slave_group, "boundary");
    EXPECT_EQ(c.kind, ContactKind::frictionless);
  }
  const auto some = parse_scenario(
      three_bodies("[general_contact]\nexclude = [\"plane\"]\nself = false\n[[general_contact.pair]]\n"
                   "bodies = [\"c\", \"a\"]\nkind = \"coulomb\"\nfriction = 0.4\n"),
      case_file());
  ASSERT_EQ(some.contacts.size(), 1u);
  EXPECT_EQ(some.contacts[0].kind, ContactKind::coulomb);
  EXPECT_EQ(some.contacts[0].friction, 0.4);
  EXPECT_EQ(some.contacts[0].passes, 1);  // two passes are frictionless only
}

// `passes` for every deformable pair and for one pair: one pass where two
// over-constrain (flat faces of unlike meshes, docs/theory.md); a pair
// table may set its passes alone, keeping the general kind.
TEST(ScenarioGeneralContact, PassesOfEveryPairAndOfOne) {
  auto passes_of = [](const std::vector<ContactSpec>& contacts, const std::string& slave, const std::string& master) {
    for (const ContactSpec& c : contacts)
      if (c.slave_body == slave && c.master_body == master) return c.passes;
    return 0;
  };
  const auto one = parse_scenario(three_bodies("[general_contact]\npasses = 1\n"), case_file());
  EXPECT_EQ(passes_of(one.contacts, "a", "c"), 1);
  EXPECT_EQ(passes_of(one.contacts, "a", "plane"), 1);
  const auto pair = parse_scenario(
      three_bodies("[general_contact]\npasses = 1\n[[general_contact.pair]]\nbodies = [\"c\", \"a\"]\npasses = 2\n"),
      case_file());
  EXPECT_EQ(passes_of(pair.contacts, "a", "c"), 2);
  for (const ContactSpec& c : pair.contacts) EXPECT_EQ(c.kind, ContactKind::frictionless);
  const auto two = parse_scenario(
      three_bodies("[general_contact]\n[[general_contact.pair]]\nbodies = [\"a\", \"c\"]\npasses = 1\n"), case_file());
  EXPECT_EQ(passes_of(two.contacts, "a", "c"), 1);
}

TEST(ScenarioGeneralContact, PassesWhereTwoCannotHoldAreOneLine) {
  EXPECT_TRUE(fails_with(three_bodies("[general_contact]\npasses = 3\n"), 30, "general_contact.passes", "3"));
  EXPECT_TRUE(fails_with(three_bodies("[general_contact]\n[[general_contact.pair]]\nbodies = [\"a\", "
                                      "\"plane\"]\npasses = 2\n"),
                         32, "general_contact.pair[0].passes", "rigid"));
  EXPECT_TRUE(fails_with(three_bodies("[general_contact]\n[[general_contact.pair]]\nbodies = [\"a\"]\npasses = 2\n"),
                         32, "general_contact.pair[0].passes", "itself"));
  EXPECT_TRUE(fails_with(three_bodies("[general_contact]\n[[general_contact.pair]]\nbodies = [\"a\", \"c\"]\n"
                                      "kind = \"stick\"\npasses = 2\n"),
                         33, "general_contact.pair[0].passes", "frictionless constraints only"));
  EXPECT_TRUE(fails_with(three_bodies("[general_contact]\n[[general_contact.pair]]\nbodies = [\"a\", \"c\"]\n"), 30,
                         "general_contact.pair[0]", "sets neither kind nor passes"));
}

TEST(ScenarioGeneralContact, BadInputIsOneLine) {
  EXPECT_TRUE(fails_with(three_bodies("[general_contact]\nexclude = [\"d\"]\n"), 30, "general_contact.exclude",
                         "unknown body 'd'"));
  EXPECT_TRUE(fails_with(three_bodies("[general_contact]\nexclude = [\"c\", \"c\"]\n"), 30,
                         "general_contact.exclude[1]", "'c' is repeated"));
  EXPECT_TRUE(fails_with(three_bodies("[general_contact]\nexclude = [\"c\"]\n[[general_contact.pair]]\n"
                                      "bodies = [\"c\"]\nkind = \"stick\"\n"),
                         32, "general_contact.pair[0].bodies", "'c' is excluded"));
  EXPECT_TRUE(fails_with(three_bodies("[general_contact]\n[[general_contact.pair]]\nbodies = [\"a\", \"c\", "
                                      "\"plane\"]\nkind = \"stick\"\n"),
                         31, "general_contact.pair[0].bodies", "names 3 bodies"));
  EXPECT_TRUE(fails_with(three_bodies("[general_contact]\nkind = \"coulomb\"\n"), 30, "general_contact.kind",
                         "without a friction coefficient"));
  const std::string both = "[[contact]]\nslave = \"a\"\nmaster = \"plane\"\nkind = \"stick\"\n[general_contact]\n";
  EXPECT_TRUE(fails_with(three_bodies(both), 33, "general_contact", "is given with [[contact]] tables"));
}

}  // namespace
}  // namespace conserve::io
