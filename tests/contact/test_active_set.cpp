// The active set's pieces on hand-made configurations: which slaves hold
// what (SlaveIndex), the constraint a slave is activated with, creases and
// push-outs (activation.hpp), the normal forces and releases located in
// time (release.hpp), impacts located in time (ImpactLocator), and the set
// itself activating a slave that crosses a facet, splitting the step at
// its crossing, and releasing it when it pulls.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "contact/contact_support.hpp"
#include "contact/elimination/active_set.hpp"
#include "support/grid_mesh.hpp"

namespace conserve::contact {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
using Vec2 = Eigen::Vector2d;
using Mat2 = Eigen::Matrix2d;

/// A pair whose slave surface has the nodes `slaves` and no facets.
ContactPair<2> bare_pair(Kind kind, std::vector<int> slaves) {
  ContactPair<2> pair;
  pair.kind = kind;
  pair.slave.nodes = std::move(slaves);
  return pair;
}

Constraint<2> constraint_on(int pair, int slave, const Vec2& normal) {
  Constraint<2> c;
  c.pair = pair;
  c.slave = slave;
  c.kind = Kind::frictionless;
  c.normal = normal.normalized();
  return c;
}

TEST(SlaveIndex, ASlaveTakesASecondFrictionlessConstraintOfAnotherPairAtAnAngleAndNoThird) {
  const std::vector<ContactPair<2>> pairs{bare_pair(Kind::frictionless, {3, 4}), bare_pair(Kind::frictionless, {4, 5}),
                                          bare_pair(Kind::stick, {4}), bare_pair(Kind::frictionless, {4})};
  SlaveIndex<2> index(6, pairs);
  EXPECT_TRUE(index.can_hold(0, 4, Vec2(0, 1)));
  index.mark(constraint_on(0, 4, Vec2(0, 1)));
  EXPECT_EQ(index.count(4), 1);
  EXPECT_EQ(index.first_pair(4), 0);
  EXPECT_TRUE(index.active_in(0, 4));
  EXPECT_FALSE(index.active_in(0, 3));                            // node 3 holds nothing
  EXPECT_FALSE(index.can_hold(0, 4, Vec2(1, 0)));                 // the same pair again
  EXPECT_FALSE(index.can_hold(2, 4, Vec2(1, 0)));                 // a stick pair
  EXPECT_FALSE(index.can_hold(1, 4, Vec2(0.3, 1).normalized()));  // |n·n′| = 0.96 ≥ kParallelCosine
  EXPECT_TRUE(index.can_hold(1, 4, Vec2(1, 1).normalized()));     // 0.71
  index.mark(constraint_on(1, 4, Vec2(1, 1)));
  EXPECT_EQ(index.count(4), 2);
  EXPECT_FALSE(index.can_hold(3, 4, Vec2(1, 0)));  // no third
  index.rebuild({constraint_on(1, 5, Vec2(0, 1))});
  EXPECT_EQ(index.count(4), 0);
  EXPECT_EQ(index.count(5), 1);
  EXPECT_TRUE(index.active_in(1, 5));
  EXPECT_FALSE(index.active_in(0, 4));
}

TEST(SlaveIndex, AStickSlaveTakesNoSecondConstraint) {
  const std::vector<ContactPair<2>> pairs{bare_pair(Kind::stick, {0}), bare_pair(Kind::frictionless, {0})};
  SlaveIndex<2> index(1, pairs);
  Constraint<2> c = constraint_on(0, 0, Vec2(0, 1));
  c.kind = Kind::stick;
  index.mark(c);
  EXPECT_FALSE(index.can_hold(1, 0, Vec2(1, 0)));
}

TEST(NormalForces, OneConstraintReadsTheNormalPartAndTwoSplitTheForceAlongBothNormals) {
  const Vec2 n1 = Vec2(0, 1), n2 = Vec2(1, 2).normalized();
  std::vector<Constraint<2>> active{constraint_on(0, 0, n1), constraint_on(0, 1, n1), constraint_on(1, 1, n2)};
  Eigen::VectorXd g = Eigen::VectorXd::Zero(6);
  g.segment<2>(0) << 0.7, -2.5;
  g.segment<2>(2) = 3.0 * n1 + 5.0 * n2;  // not the projections: the normals are not orthogonal
  std::vector<int> slot(3, -1);
  const std::vector<double> f = normal_forces(active, g, slot);
  ASSERT_EQ(f.size(), 3u);
  EXPECT_EQ(f[0], -2.5);
  EXPECT_NEAR(f[1], 3.0, 1e-14);
  EXPECT_NEAR(f[2], 5.0, 1e-14);
  EXPECT_EQ(slot, std::vector<int>(3, -1));
}

/// A pressing constraint whose force fell from `start` to `end` over the
/// last step.
Constraint<2> falling(double start, double end, std::int64_t activated = 0) {
  Constraint<2> c = constraint_on(0, 0, Vec2(0, 1));
  c.start_force = start;
  c.normal_force = end;
  c.activated_step = activated;
  return c;
}

TEST(ReleaseStep, AForceFallingTowardsZeroShortensTheNextStepSoThatItsMeanStaysCompressive) {
  const double full = 1e-3;
  // −df/dt = 4/1e-3: f would reach 0 at 1.5 ms after the last step's
  // middle; the next step's mean stays ≥ 0 for steps up to 2 f/r − h = 2 ms.
  const std::vector<Constraint<2>> active{falling(10.0, 6.0)};
  const double next = release_step(active, 5, full, full, full);
  EXPECT_DOUBLE_EQ(next, kReleaseApproach * 2e-3);
  const double rate = 4.0 / full;
  EXPECT_GT(6.0 - rate * 0.5 * (full + next), 0.0);  // the next step's mean force
  // Steps shrink geometrically towards the lift-off, but not below the floor.
  EXPECT_DOUBLE_EQ(release_step(std::vector<Constraint<2>>{falling(6.0, 1e-9)}, 5, full, full, full),
                   full / kReleaseShortest);
}

TEST(ReleaseStep, RisingFarOffOrNewForcesLeaveTheStepAlone) {
  const double full = 1e-3;
  EXPECT_EQ(release_step(std::vector<Constraint<2>>{}, 5, full, full, full), full);
  EXPECT_EQ(release_step(std::vector<Constraint<2>>{falling(6.0, 10.0)}, 5, full, full, full), full);
  EXPECT_EQ(release_step(std::vector<Constraint<2>>{falling(10.0, 9.9)}, 5, full, full, full), full);  // 0.2 s away
  EXPECT_EQ(release_step(std::vector<Constraint<2>>{falling(10.0, 6.0, 5)}, 5, full, full, full), full);
  // A slave pressing with less than kLoadedFraction of the mean is not waited for.
  EXPECT_EQ(release_step(std::vector<Constraint<2>>{falling(1e-3, 5e-4), falling(100.0, 100.0)}, 5, full, full, full),
            full);
}

/// A master facet from (1, 0) to (0, 0) (nodes 1, 2), normal +y, and a
/// slave (node 0).
ContactSurface floor_facet() {
  ContactSurface s;
  s.facets.resize(2, 1);
  s.facets.col(0) << 1, 2;
  build_adjacency(s, 2);
  return s;
}

Positions<2> floor_positions(const Vec2& slave) {
  Positions<2> x(2, 3);
  x.col(0) = slave;
  x.col(1) << 1.0, 0.0;
  x.col(2) << 0.0, 0.0;
  return x;
}

Constraint<2> arriving(double gap) {
  Constraint<2> c = constraint_on(0, 0, Vec2(0, 1));
  c.facet = 0;
  c.master = {1, 2};
  c.gap = gap;
  return c;
}

Match<2> behind(double gap) {
  Match<2> m;
  m.facet = 0;
  m.projection.gap = gap;
  m.projection.normal = Vec2(0, 1);
  return m;
}

TEST(ImpactLocator, TheGapToleranceWidensWhileAPairIsInContactOrWithinTheWindowOfAnEvent) {
  ImpactLocator<2> locator(3, 2);
  EXPECT_EQ(locator.gap_tolerance(0, 0, 0.5), kInf);  // not located
  locator.configure({0.01, 0.1, 0.05});
  const Eigen::VectorXd v = Eigen::VectorXd::Zero(6);
  locator.begin_step(1.0, 1e-3, v, {});
  EXPECT_DOUBLE_EQ(locator.gap_tolerance(0, 0, 0.5), 0.005);  // the onset: a first impact
  locator.begin_step(1.0, 1e-3, v, {arriving(0.0)});          // pair 0 in contact
  EXPECT_DOUBLE_EQ(locator.gap_tolerance(0, 0, 0.5), 0.05);
  EXPECT_DOUBLE_EQ(locator.gap_tolerance(1, 0, 0.5), 0.005);
  locator.activated(1);
  locator.released(2);
  EXPECT_TRUE(locator.released_in_step(2));
  locator.end_step(1.001);
  locator.begin_step(1.04, 1e-3, v, {});
  EXPECT_FALSE(locator.released_in_step(2));
  EXPECT_DOUBLE_EQ(locator.gap_tolerance(1, 0, 0.5), 0.05);  // within the window of pair 1's activation
  EXPECT_DOUBLE_EQ(locator.gap_tolerance(0, 2, 0.5), 0.05);  // of node 2's release
  EXPECT_DOUBLE_EQ(locator.gap_tolerance(0, 0, 0.5), 0.005);
  locator.begin_step(1.06, 1e-3, v, {});
  EXPECT_DOUBLE_EQ(locator.gap_tolerance(1, 0, 0.5), 0.005);
  EXPECT_EQ(locator.activation_times()[1], 1.001);
  EXPECT_EQ(locator.release_times()[2], 1.001);
  EXPECT_EQ(locator.release_times()[0], -kInf);
  locator.configure({});
  EXPECT_FALSE(locator.located());
}

TEST(ImpactLocator, TheStepEndsWhereTheSlaveArrivesAtHalfItsToleranceOnTheMidPointPath) {
  const ContactSurface master = floor_facet();
  const Positions<2> x_n = floor_positions(Vec2(0.5, 0.5));
  ImpactLocator<2> locator(3, 1);
  locator.configure({0.01, 0.01, 0.0});
  // Gap 0.5 at the start, −0.1 at the end: 0.45 of a 0.6 drop to δ/2 = 0.05.
  Eigen::VectorXd v = Eigen::VectorXd::Zero(6);
  v[1] = -0.6 / 1e-3;  // arriving at the velocity of the straight path: g is linear in s
  locator.begin_step(0.0, 1e-3, v, {});
  EXPECT_NEAR(locator.split_at(arriving(0.5), behind(-0.1), master, x_n, 0.1), 0.75, 1e-14);
  locator.begin_step(0.0, 1e-3, Eigen::VectorXd::Zero(6), {});  // from rest: g = γ − 0.6 s²
  EXPECT_NEAR(locator.split_at(arriving(0.5), behind(-0.1), master, x_n, 0.1), std::sqrt(0.75), 1e-14);
  EXPECT_EQ(locator.split_at(arriving(0.05), behind(-0.1), master, x_n, 0.1), 1.0);  // starts within
}

TEST(Activation, AFrictionlessSlaveCrossingAFacetHoldsItsStartGapWithTheMidPointFrame) {
  ContactPair<2> pair;
  pair.master = floor_facet();
  pair.kind = Kind::frictionless;
  const Positions<2> x_n = floor_positions(Vec2(0.3, 0.2)), x_np1 = floor_positions(Vec2(0.5, -0.1));
  const Constraint<2> c = make_constraint<2>(pair, 0, 0, behind(-0.1), x_n, x_np1, {7, true, false, 1.0});
  EXPECT_EQ(c.slave, 0);
  EXPECT_EQ(c.facet, 0);
  EXPECT_EQ(c.master, (std::array<int, 2>{1, 2}));
  EXPECT_NEAR(c.gap, 0.2, 1e-15);
  EXPECT_NEAR((c.normal - Vec2(0, 1)).norm(), 0.0, 1e-15);
  EXPECT_NEAR(c.xi(0), 1.0 - 0.4, 1e-15);  // ξ at the mid-point x = 0.4, from node 1 at x = 1
  EXPECT_EQ(c.activated_step, 7);
  EXPECT_FALSE(c.push || c.hold);
  pair.kind = Kind::stick;
  const Constraint<2> s = make_constraint<2>(pair, 0, 0, behind(-0.1), x_n, x_np1, {7, true, false, 1.0});
  EXPECT_NEAR(s.xi(0), 1.0 - 0.3, 1e-15);  // frozen where the slave started
  EXPECT_NEAR(s.gap, 0.2, 1e-15);
}

TEST(Activation, ASlaveStartingBehindIsPushedOutAStepsShareAtATimeOrHeld) {
  ContactPair<2> pair;
  pair.master = floor_facet();
  pair.kind = Kind::frictionless;
  pair.search.penetration_tolerance = 1e-12;
  // The whole configuration translates rigidly: no other non-rigid motion
  // carries the slave out at zero work.
  Positions<2> x_n = floor_positions(Vec2(0.5, -0.05)), x_np1 = x_n;
  x_np1.row(0).array() += 0.01;
  EXPECT_NEAR(push_out<2>(arriving(0.0), x_n, x_np1), 0.0, 1e-15);
  const Constraint<2> pushed = make_constraint<2>(pair, 0, 0, behind(-0.05), x_n, x_np1, {0, true, false, 0.2});
  EXPECT_TRUE(pushed.push);
  EXPECT_NEAR(pushed.gap, -0.05 + kPushOutStep * 0.2, 1e-15);
  EXPECT_EQ(push_target(-0.01, 0.2), 0.0);  // a step's share reaches the facet
  const Constraint<2> held = make_constraint<2>(pair, 0, 0, behind(-0.05), x_n, x_np1, {0, true, true, 0.2});
  EXPECT_TRUE(held.hold);
  EXPECT_FALSE(held.push);
  EXPECT_NEAR(held.gap, -0.05, 1e-15);
  const Constraint<2> second = make_constraint<2>(pair, 0, 0, behind(-0.05), x_n, x_np1, {0, false, false, 0.2});
  EXPECT_FALSE(second.push || second.hold);
  EXPECT_NEAR(second.gap, -0.05, 1e-15);
  // Behind by round-off: on the facet.
  const Positions<2> touching = floor_positions(Vec2(0.5, -1e-13));
  EXPECT_EQ(make_constraint<2>(pair, 0, 0, behind(-1e-13), touching, touching, {0, true, false, 0.2}).gap, 0.0);
  // A facet stretched by more than the depth carries the slave out at zero work.
  Positions<2> stretched = x_n;
  stretched(0, 1) += 0.2;
  EXPECT_GT(push_out<2>(arriving(0.0), x_n, stretched), 0.05);
  const Constraint<2> free = make_constraint<2>(pair, 0, 0, behind(-0.05), x_n, stretched, {0, true, false, 0.2});
  EXPECT_FALSE(free.push);
  EXPECT_EQ(free.gap, 0.0);
}

TEST(Activation, APushOutOfARigidlyRotatingConfigurationIsZero) {
  Positions<2> x_a = floor_positions(Vec2(0.4, 0.0));
  const double angle = 0.3;
  Mat2 R;
  R << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
  const Positions<2> x_b = (R * x_a).colwise() + Vec2(0.2, -0.7);
  Constraint<2> c = arriving(0.0);
  c.xi(0) = 0.6;  // the slave's point of the facet
  EXPECT_LT(push_out<2>(c, x_a, x_b), 1e-14);
  c.xi(0) = 0.5;  // 0.1 away from it, the rotation slides it along the facet: not rigid
  EXPECT_GT(push_out<2>(c, x_a, x_b), 1e-2);
}

/// A V-shaped master (nodes 1 (−1, 0.5), 2 (0, 0), 3 (1, 0.5)), its
/// facets facing into the V, and a flat continuation (4 (2, 0.5)).
ContactPair<2> vee() {
  ContactPair<2> pair;
  pair.kind = Kind::frictionless;
  pair.master.facets.resize(2, 3);
  pair.master.facets.col(0) << 2, 1;
  pair.master.facets.col(1) << 3, 2;
  pair.master.facets.col(2) << 4, 3;
  build_adjacency(pair.master, 2);
  return pair;
}

TEST(Crease, ASlaveOnOneArmOfAVeeFoundBehindTheOtherHoldsBoth) {
  const ContactPair<2> pair = vee();
  Positions<2> x(2, 5);
  x << 0, -1, 0, 1, 2,  //
      0, 0.5, 0, 0.5, 0.5;
  const Vec2 left = facet_normal<2>(facet_nodes<2>(pair.master, 0, x));
  const Vec2 right = facet_normal<2>(facet_nodes<2>(pair.master, 1, x));
  ASSERT_NEAR((left - Vec2(0.5, 1).normalized()).norm(), 0.0, 1e-15);  // into the V
  ASSERT_NEAR((right - Vec2(-0.5, 1).normalized()).norm(), 0.0, 1e-15);
  Constraint<2> held = constraint_on(0, 0, left);
  held.facet = 0;
  held.master = {2, 1};
  Match<2> end = behind(-0.01);
  end.facet = 1;
  end.projection.normal = right;
  EXPECT_TRUE(forms_crease(pair, held, end));
  held.push = true;  // a slave pushed out, or held by (48), takes no crease pair
  EXPECT_FALSE(forms_crease(pair, held, end));
  held.push = false;
  held.rate = true;
  EXPECT_FALSE(forms_crease(pair, held, end));
  held.rate = false;
  end.facet = 0;  // its own facet
  EXPECT_FALSE(forms_crease(pair, held, end));
  end.facet = 2;  // shares no node with facet 0
  EXPECT_FALSE(forms_crease(pair, held, end));
  end.facet = 1;
  end.projection.normal = (left + Vec2(-1e-4, 1e-4)).normalized();  // within kCreaseSine of parallel
  EXPECT_FALSE(forms_crease(pair, held, end));
  end.projection.normal = -right;  // the other side
  EXPECT_FALSE(forms_crease(pair, held, end));
  end.projection.normal = Vec2(-1, 0.5).normalized();  // folded past a right angle: n·n′ < 0
  EXPECT_FALSE(forms_crease(pair, held, end));
  ContactPair<2> stick = vee();
  stick.kind = Kind::stick;
  end.projection.normal = right;
  EXPECT_FALSE(forms_crease(stick, held, end));
}

/// A unit square (slave, body 1) 0.1 above a 2 × 1 block (master, body 0).
struct SquareOnBlock {
  model::Model<2> model;
  std::unique_ptr<ActiveSet<2>> set;

  SquareOnBlock() {
    model = test::one_body_model<2>(test::rectangle_mesh(2, 1, 2.0, 1.0), "block");
    mesh::Mesh square = test::rectangle_mesh(1, 1, 1.0, 1.0);
    square.points.row(0).array() += 0.5;
    square.points.row(1).array() += 1.1;
    model::add_body<2>(model, square, "square", model.bodies[0].law, 1.0, 1.0);
    ContactPair<2> pair;
    pair.slave = make_surface<2>(model, 1, "boundary");
    pair.master = make_surface<2>(model, 0, "boundary");
    pair.kind = Kind::frictionless;
    pair.search.search_distance = 0.5;
    pair.search.penetration_tolerance = 1e-13;
    set = std::make_unique<ActiveSet<2>>(model, std::vector<ContactPair<2>>{pair});
  }
  /// The square moved down by `drop`.
  [[nodiscard]] Eigen::VectorXd lowered(double drop) const {
    Eigen::VectorXd u = Eigen::VectorXd::Zero(2 * model.num_nodes());
    const model::Body& square = model.bodies[1];
    for (int node = square.first_node; node < square.first_node + square.num_nodes; ++node) u[2 * node + 1] = -drop;
    return u;
  }
  /// A force balance pressing each active slave with `f` along its normal.
  [[nodiscard]] Eigen::VectorXd pressing(double f) const {
    Eigen::VectorXd g = Eigen::VectorXd::Zero(2 * model.num_nodes());
    for (const Constraint<2>& c : set->constraints()) g.segment<2>(2 * c.slave) = f * c.normal;
    return g;
  }
};

TEST(ActiveSet, ASlaveCrossingAFacetIsActivatedHoldingItsStartGapAndReleasedWhenItPulls) {
  SquareOnBlock scene;
  ActiveSet<2>& set = *scene.set;
  const Eigen::VectorXd u_n = scene.lowered(0.0), u_np1 = scene.lowered(0.15);
  const Eigen::VectorXd v_n = Eigen::VectorXd::Zero(u_n.size());
  set.begin_step(1, 0.0, 1e-3, v_n);
  StepContactStats stats;
  HeldCounts counts;
  EXPECT_EQ(set.update(u_n, u_np1, scene.pressing(0.0), stats, counts), SetChange::changed);
  EXPECT_EQ(stats.activations, 2);  // the square's bottom corners
  ASSERT_EQ(set.constraints().size(), 2u);
  for (const Constraint<2>& c : set.constraints()) {
    EXPECT_NEAR(c.gap, 0.1, 1e-14);
    EXPECT_NEAR((c.normal - Vec2(0, 1)).norm(), 0.0, 1e-14);
  }
  EXPECT_NEAR(stats.slave_penetration, 0.05, 1e-14);
  // Solved again, the corners pressing: the set is settled.
  StepContactStats again;
  EXPECT_EQ(set.update(u_n, scene.lowered(0.1), scene.pressing(1.0), again, counts), SetChange::none);
  EXPECT_EQ(again.activations + again.releases, 0);
  EXPECT_NEAR(again.min_active_gap, 0.0, 1e-14);
  set.end_step(1e-3);
  // The next step pulls: both are released, then found behind again and
  // held for the rest of the step (not released twice).
  set.begin_step(2, 1e-3, 1e-3, v_n);
  StepContactStats pull;
  HeldCounts pull_counts;
  EXPECT_EQ(set.update(scene.lowered(0.1), scene.lowered(0.05), scene.pressing(-1.0), pull, pull_counts),
            SetChange::changed);
  EXPECT_EQ(pull.releases, 2);
  EXPECT_EQ(pull_counts.chatter, 2);  // activated one step before
  EXPECT_TRUE(set.constraints().empty());
  StepContactStats back;
  HeldCounts back_counts;
  EXPECT_EQ(set.update(scene.lowered(0.1), scene.lowered(0.12), scene.pressing(0.0), back, back_counts),
            SetChange::changed);
  EXPECT_EQ(back_counts.held, 2);
  StepContactStats kept;
  EXPECT_EQ(set.update(scene.lowered(0.1), scene.lowered(0.1), scene.pressing(-1.0), kept, back_counts),
            SetChange::none);
  EXPECT_EQ(set.constraints().size(), 2u);
}

TEST(ActiveSet, WithImpactsLocatedAStepThatWouldActivateFromFurtherOutIsSplitAtTheCrossing) {
  SquareOnBlock scene;
  ActiveSet<2>& set = *scene.set;
  set.locate_impacts({0.01, 0.01, 0.0});
  const Eigen::VectorXd u_n = scene.lowered(0.0), u_np1 = scene.lowered(0.15);
  Eigen::VectorXd v_n = Eigen::VectorXd::Zero(u_n.size());
  const model::Body& square = scene.model.bodies[1];
  for (int node = square.first_node; node < square.first_node + square.num_nodes; ++node)
    v_n[2 * node + 1] = -0.15 / 1e-3;  // the straight path
  set.begin_step(1, 0.0, 1e-3, v_n);
  // Tolerance 0.01 × the square's facet size (1): arrive at 0.005 of the 0.1 gap.
  const double expected = (0.1 - 0.005) / 0.15;
  EXPECT_NEAR(set.split_fraction(u_n, u_np1), expected, 1e-12);
  StepContactStats stats;
  HeldCounts counts;
  EXPECT_EQ(set.update(u_n, u_np1, scene.pressing(0.0), stats, counts), SetChange::split);
  EXPECT_NEAR(stats.split_fraction, expected, 1e-12);
  EXPECT_TRUE(set.constraints().empty());
  set.allow_splits(false);
  EXPECT_EQ(set.split_fraction(u_n, u_np1), 1.0);
}

}  // namespace
}  // namespace conserve::contact
