#pragma once
/// The collision set: which slave node lies behind or in front of which
/// master facet, shared by every constraint method (issue 46). Per contact
/// pair, the slave surface's nodes are searched against the master
/// surface's facets (broad phase, closest-point projection and the rules of
/// contact/search.hpp), and the pair the other way round only to measure
/// how far master nodes are behind slave facets. It holds the search's
/// trees and frames but no contact state: which constraints are active is
/// the constraint method's (contact/elimination/active_set.hpp for elimination).
#include <optional>
#include <unordered_map>
#include <vector>

#include "contact/constraint.hpp"
#include "contact/search.hpp"
#include "model/model.hpp"

namespace conserve::contact {

/// The deepest node behind a facet found by CollisionSet::slave_penetration
/// or CollisionSet::master_penetration.
struct Penetration {
  double depth = 0.0;  ///< ≥ 0 [m]
  int node = -1;       ///< global node, −1 if none
};

template <int D>
class CollisionSet {
 public:
  CollisionSet(const model::Model<D>& model, std::vector<ContactPair<D>> pairs);

  [[nodiscard]] bool empty() const { return pairs_.empty(); }
  [[nodiscard]] int size() const { return static_cast<int>(pairs_.size()); }
  [[nodiscard]] const std::vector<ContactPair<D>>& pairs() const { return pairs_; }
  [[nodiscard]] const ContactPair<D>& pair(int p) const { return pairs_[static_cast<std::size_t>(p)]; }

  /// Moves pair p's search to positions x (its tree refitted, its facets'
  /// frames dropped): match() then answers for x.
  void refit(int p, const Positions<D>& x) { pairs_[static_cast<std::size_t>(p)].refit(x); }

  /// The master facet slave `pair(p).slave.nodes[i]` is behind or in front
  /// of at positions x (pair p refitted to x), if the slave is over the
  /// master surface (over_surface()); given the step's start x_n, also a
  /// facet beyond the border that the slave entered through the surface in
  /// the step. `slave_normal`: the slave's outward node normal at x.
  [[nodiscard]] std::optional<Match<D>> match(int p, std::size_t i, const Positions<D>& x, const Vec<D>& slave_normal,
                                              const Positions<D>* x_n = nullptr) const {
    return match_in(pair(p), i, x, slave_normal, x_n);
  }

  /// Calls visit(p, i, slave node, match) for every slave that is not
  /// prescribed and has a master facet at positions x (match(), with x_n if
  /// given), pair by pair, each pair refitted to x first.
  /// Pairs whose surfaces' boxes (the master's enlarged by the search
  /// distance) hold no slave node are skipped before their search is
  /// refitted: with many bodies ([general_contact]) most pairs are apart.
  template <class Visit>
  void for_each_match(const Positions<D>& x, Visit&& visit, const Positions<D>* x_n = nullptr) {
    std::vector<std::size_t> near;
    candidates(x, candidates_);
    for (const int p : candidates_) {
      const ContactPair<D>& pr = pair(p);
      near_slaves(pr, x, near);
      if (near.empty()) continue;
      refit(p, x);
      const std::vector<Vec<D>> normals = node_normals<D>(pr.slave, x);
      for (const std::size_t i : near) {
        const int s = pr.slave.nodes[i];
        if (prescribed_[static_cast<std::size_t>(s)] && !pr.slave_driven()) continue;
        if (const auto m = match_in(pr, i, x, normals[i], x_n)) visit(p, i, s, *m);
      }
    }
  }

  /// The scene's broad phase: the pairs (ascending) whose two surfaces'
  /// boxes at x, each enlarged by the largest search distance it is
  /// searched with, overlap (sweep and prune along the axis the boxes'
  /// centres spread most on), and every self-contact pair. Its cost grows
  /// with the surfaces' nodes and the overlapping pairs, not with the
  /// pairs listed: a pair that is apart is never looked at.
  void candidates(const Positions<D>& x, std::vector<int>& out) const;

  /// The slave nodes (local) of `pair` within the box of its master
  /// surface's nodes at x enlarged by the search distance.
  static void near_slaves(const ContactPair<D>& pair, const Positions<D>& x, std::vector<std::size_t>& out);

  /// The deepest slave node behind a master facet at positions x, by
  /// match()'s rules (with x_n, also a facet beyond the border entered
  /// through in the step); depth 0 and node −1 if none.
  [[nodiscard]] Penetration slave_penetration(const Positions<D>& x, const Positions<D>* x_n = nullptr);
  /// The other way: the deepest master node (prescribed ones included)
  /// behind a facet of its pair's slave surface at positions x (the step
  /// from x_n). Node-to-segment contact holds slaves only: a master finer
  /// than its slave may sink its nodes into the slave's facets.
  [[nodiscard]] Penetration master_penetration(const Positions<D>& x, const Positions<D>& x_n);

  /// Both of the above per pair at positions x (the step from x_n if
  /// given): pair p's deepest slave behind a master facet and deepest
  /// master node behind a slave facet (the run summary's per-body figures).
  struct PairPenetration {
    Penetration slave;
    Penetration master;
  };
  [[nodiscard]] std::vector<PairPenetration> pair_penetrations(const Positions<D>& x,
                                                               const Positions<D>* x_n = nullptr);

  /// The longest edge of the slave facets at slave node `slave` of pair
  /// `p` in the reference configuration [m].
  [[nodiscard]] double facet_size(int p, int slave) const;

 private:
  /// for_each_match for the pairs the other way round (reversed_): visit(p,
  /// master node, match on a slave facet of pair p), prescribed nodes too.
  template <class Visit>
  void for_each_reversed_match(const Positions<D>& x, Visit&& visit, const Positions<D>* x_n);
  [[nodiscard]] static std::optional<Match<D>> match_in(const ContactPair<D>& pair, std::size_t i,
                                                        const Positions<D>& x, const Vec<D>& slave_normal,
                                                        const Positions<D>* x_n);
  std::vector<ContactPair<D>> pairs_;
  /// Per pair, the pair the other way round (master nodes against slave
  /// facets), searched only for master_penetration.
  std::vector<ContactPair<D>> reversed_;
  /// Per pair, per slave node (local): the longest edge of its slave facets
  /// in the reference configuration [m].
  std::vector<std::vector<double>> facet_size_;
  /// Per node: some dof prescribed (never a slave, but of a second pass
  /// whose slaves are a driven body's, ContactPair::slave_driven).
  std::vector<char> prescribed_;
  /// The broad phase's surfaces (each once, by name): their nodes, the
  /// largest search distance each is a master with (either way round), and
  /// per pair of surfaces (slave · count + master) the pairs between them.
  std::vector<std::vector<int>> surface_nodes_;
  std::vector<double> surface_margin_;
  std::unordered_map<std::size_t, std::vector<int>> between_;
  std::vector<int> candidates_;  ///< for_each_match's scratch
};

}  // namespace conserve::contact
