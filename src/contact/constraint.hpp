#pragma once
/// Contact pairs and active node-to-segment constraints.
#include <array>
#include <vector>

#include "contact/broad_phase.hpp"
#include "contact/facet.hpp"
#include "contact/search.hpp"
#include "contact/surface.hpp"

namespace conserve::contact {

enum class Kind {
  frictionless,  ///< (47)–(65): zero relative normal mid-point velocity, free slip
  stick,         ///< (35)–(46): the slave moves with a frozen point of the master facet
};

/// A slave surface against a master surface.
template <int D>
struct ContactPair {
  ContactSurface slave;
  ContactSurface master;
  Kind kind = Kind::frictionless;
  SearchSettings search;
  FacetTree<D> tree;  ///< over master facets, refitted before each search
};

/// One active constraint: slave node s tied to master facet m.
template <int D>
struct Constraint {
  int pair = -1;
  int slave = -1;                  ///< global node
  int facet = -1;                  ///< column of the master surface's facets
  std::array<int, D> master{};     ///< global master nodes
  Xi<D> xi = Xi<D>::Zero();        ///< stick: frozen ξ̄; frictionless: ξ_{n+½}
  Vec<D> normal = Vec<D>::Zero();  ///< n_{n+½}, master outward normal at the mid-point
  Tangents<D> tangents = Tangents<D>::Zero();  ///< τ_{n+½}
  Kind kind = Kind::stick;
  double activation_gap = 0.0;  ///< g_N at t_n when activated [m]
};

}  // namespace conserve::contact
