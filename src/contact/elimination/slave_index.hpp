#pragma once
/// Which active constraints each slave node holds (docs/theory.md, "Two
/// constraints on one slave"): a slave holds at most two, and two only
/// when both are frictionless and their facets are not near-parallel (a
/// node on two slave surfaces, or at a crease of one master surface).
#include <cstddef>
#include <vector>

#include "contact/constraint.hpp"

namespace conserve::contact {

/// Two constraints of different pairs on one slave node whose facet
/// normals are closer to parallel than this (|n₁·n₂|) are not held
/// together: the second is not activated (the two gaps would fix the
/// slave's motion badly).
inline constexpr double kParallelCosine = 0.9;

template <int D>
class SlaveIndex {
 public:
  /// For `num_nodes` nodes and the contact `pairs` (their kinds and slave
  /// surfaces are read here; the index keeps no reference).
  SlaveIndex(int num_nodes, const std::vector<ContactPair<D>>& pairs);

  /// The index of `active` anew (constraints of `pairs`, as at construction).
  void rebuild(const std::vector<Constraint<D>>& active);
  /// Records constraint c of `pairs`.
  void mark(const Constraint<D>& c);

  /// Active constraints node s is the slave of (0–2).
  [[nodiscard]] int count(int s) const { return count_[static_cast<std::size_t>(s)]; }
  /// The pair of the first of them (−1 if none).
  [[nodiscard]] int first_pair(int s) const { return first_pair_[static_cast<std::size_t>(s)]; }
  /// Whether slave node s holds a constraint of pair p.
  [[nodiscard]] bool active_in(int p, int s) const {
    const auto n = static_cast<std::size_t>(s);
    return (count_[n] > 0 && first_pair_[n] == p) || (count_[n] > 1 && second_pair_[n] == p);
  }
  /// Whether slave node s may take a constraint of pair p whose facet has
  /// normal `normal`: when it holds none, or holds one frictionless
  /// constraint of another pair whose normal is not near-parallel
  /// (|n·n′| < kParallelCosine) and p is frictionless too.
  [[nodiscard]] bool can_hold(int p, int s, const Vec<D>& normal) const;

 private:
  std::vector<Kind> kinds_;           ///< per pair
  std::vector<char> count_;           ///< per node
  std::vector<int> first_pair_;       ///< per node
  std::vector<Vec<D>> first_normal_;  ///< per node: its first constraint's normal
  std::vector<int> second_pair_;      ///< per node: the pair of its second constraint
};

}  // namespace conserve::contact
