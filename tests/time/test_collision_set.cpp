// The collision set (contact/collision_set.hpp) against a brute-force
// oracle: the same pairs searched with a broad phase that returns every
// master facet. For every slave node of two spheres in contact, and of
// perturbed positions around them, each match the set finds is the
// oracle's, facet and gap bit for bit, and every slave the oracle matches
// to a facet the broad phase offers (its box grown by the search radius
// holds the slave) the set matches to that facet too: the broad phase
// never hides the facet the narrow phase would choose.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <map>
#include <random>

#include "contact/collision_set.hpp"
#include "contact_checks.hpp"
#include "support/contact_scenarios.hpp"

namespace conserve::time {
namespace {

using test::ContactRun;

template <int D>
void check_against_brute_force() {
  ContactRun<D> run(test::glancing_spheres(D, "frictionless", 0.1));
  test::run_until_contact(run, 2, 150);
  const model::Model<D>& model = run.problem.model;
  contact::CollisionSet<D>& set = run.contacts->collisions();
  std::vector<contact::ContactPair<D>> all = set.pairs();
  for (auto& pair : all) pair.search.search_distance = std::numeric_limits<double>::max();  // every facet
  contact::CollisionSet<D> oracle(model, all);
  std::mt19937 rng(31);
  std::normal_distribution<double> jitter(0.0, 2e-3);
  int matches = 0, behind = 0;  // offered oracle matches, and those behind their facet
  for (int trial = 0; trial < 5; ++trial) {
    contact::Positions<D> x = run.positions();
    if (trial > 0)
      for (int n = 0; n < model.num_nodes(); ++n)
        for (int i = 0; i < D; ++i) x(i, n) += jitter(rng);
    std::map<int, contact::Match<D>> found;
    set.for_each_match(x, [&](int, std::size_t, int s, const contact::Match<D>& m) { found.emplace(s, m); });
    // Whether the broad phase offers facet f of pair p to slave s: the
    // facet's box grown by the search radius holds it. A facet it does not
    // offer is one the set cannot choose.
    auto offered = [&](int p, int s, int f) {
      const contact::ContactPair<D>& pair = set.pair(p);
      Eigen::AlignedBox<double, D> box;
      for (int a = 0; a < D; ++a) box.extend(x.col(pair.master.facets(a, f)));
      box.min().array() -= pair.search.search_distance;
      box.max().array() += pair.search.search_distance;
      return box.contains(x.col(s));
    };
    oracle.for_each_match(x, [&](int p, std::size_t, int s, const contact::Match<D>& m) {
      if (!offered(p, s, m.facet)) return;
      const auto it = found.find(s);
      ASSERT_NE(it, found.end()) << "slave " << s << ": the oracle finds facet " << m.facet << " at gap "
                                 << m.projection.gap << ", the set none";
      EXPECT_EQ(it->second.facet, m.facet) << "slave " << s;
      EXPECT_EQ(it->second.projection.gap, m.projection.gap) << "slave " << s;
      ++matches;
      if (m.projection.gap < 0.0) ++behind;
    });
  }
  ASSERT_GT(matches, 20);  // non-vacuous: slaves over the master, some behind it
  EXPECT_GT(behind, 0);
}

TEST(CollisionSet, MatchesTheBruteForceOracle3d) { check_against_brute_force<3>(); }
TEST(CollisionSet, MatchesTheBruteForceOracle2d) { check_against_brute_force<2>(); }

}  // namespace
}  // namespace conserve::time
