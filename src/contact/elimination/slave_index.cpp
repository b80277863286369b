#include "contact/elimination/slave_index.hpp"

#include <cmath>

namespace conserve::contact {

template <int D>
SlaveIndex<D>::SlaveIndex(int num_nodes, const std::vector<ContactPair<D>>& pairs)
    : count_(static_cast<std::size_t>(num_nodes), 0),
      first_pair_(static_cast<std::size_t>(num_nodes), -1),
      first_normal_(static_cast<std::size_t>(num_nodes), Vec<D>::Zero()) {
  for (const ContactPair<D>& pr : pairs) {
    kinds_.push_back(pr.kind);
    active_in_.emplace_back(pr.slave.nodes.size(), 0);
  }
}

template <int D>
void SlaveIndex<D>::rebuild(const std::vector<Constraint<D>>& active, const std::vector<ContactPair<D>>& pairs) {
  std::fill(count_.begin(), count_.end(), 0);
  std::fill(first_pair_.begin(), first_pair_.end(), -1);
  std::fill(first_normal_.begin(), first_normal_.end(), Vec<D>::Zero());
  for (auto& flags : active_in_) std::fill(flags.begin(), flags.end(), 0);
  for (const Constraint<D>& c : active) mark(c, pairs);
}

template <int D>
void SlaveIndex<D>::mark(const Constraint<D>& c, const std::vector<ContactPair<D>>& pairs) {
  const auto s = static_cast<std::size_t>(c.slave);
  if (count_[s]++ == 0) first_pair_[s] = c.pair, first_normal_[s] = c.normal;
  const int i = pairs[static_cast<std::size_t>(c.pair)].slave.local_node(c.slave);
  if (i >= 0) active_in_[static_cast<std::size_t>(c.pair)][static_cast<std::size_t>(i)] = 1;
}

template <int D>
bool SlaveIndex<D>::can_hold(int p, int s, const Vec<D>& normal) const {
  const auto n = static_cast<std::size_t>(s);
  if (count_[n] == 0) return true;
  if (count_[n] > 1 || first_pair_[n] == p) return false;
  return kinds_[static_cast<std::size_t>(p)] == Kind::frictionless &&
         kinds_[static_cast<std::size_t>(first_pair_[n])] == Kind::frictionless &&
         std::abs(normal.dot(first_normal_[n])) < kParallelCosine;
}

template class SlaveIndex<2>;
template class SlaveIndex<3>;

}  // namespace conserve::contact
