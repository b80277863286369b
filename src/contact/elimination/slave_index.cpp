#include "contact/elimination/slave_index.hpp"

#include <cmath>

namespace conserve::contact {

template <int D>
SlaveIndex<D>::SlaveIndex(int num_nodes, const std::vector<ContactPair<D>>& pairs)
    : count_(static_cast<std::size_t>(num_nodes), 0),
      first_pair_(static_cast<std::size_t>(num_nodes), -1),
      first_normal_(static_cast<std::size_t>(num_nodes), Vec<D>::Zero()),
      second_pair_(static_cast<std::size_t>(num_nodes), -1) {
  for (const ContactPair<D>& pr : pairs) kinds_.push_back(pr.kind);
}

template <int D>
void SlaveIndex<D>::rebuild(const std::vector<Constraint<D>>& active) {
  std::fill(count_.begin(), count_.end(), 0);
  std::fill(first_pair_.begin(), first_pair_.end(), -1);
  std::fill(first_normal_.begin(), first_normal_.end(), Vec<D>::Zero());
  std::fill(second_pair_.begin(), second_pair_.end(), -1);
  for (const Constraint<D>& c : active) mark(c);
}

template <int D>
void SlaveIndex<D>::mark(const Constraint<D>& c) {
  const auto s = static_cast<std::size_t>(c.slave);
  if (count_[s]++ == 0)
    first_pair_[s] = c.pair, first_normal_[s] = c.normal;
  else
    second_pair_[s] = c.pair;
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
