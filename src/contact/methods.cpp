// The constraint methods' registry: a new method is a folder and one
// entry here.
#include <fmt/format.h>

#include <functional>

#include "contact/elimination/method.hpp"
#include "contact/lagrange/method.hpp"
#include "contact/method.hpp"
#include "contact/penalty/penalty.hpp"
#include "core/error.hpp"

namespace conserve::contact {
namespace {

/// [active_set]'s impact location: onset gap_tolerance, cluster
/// cluster_tolerance, over a window of kClusterWindow of the scenario's steps.
ImpactLocation impact_location(const io::Scenario& s) {
  constexpr double kClusterWindow = 2.0;
  const io::ActiveSetSpec& a = s.active_set;
  if (!a.locate_impacts) return {};
  return {.onset = a.gap_tolerance, .cluster = a.cluster_tolerance, .window = kClusterWindow * s.time.step};
}

template <int D>
using Maker = std::function<std::unique_ptr<Method<D>>(const io::Scenario&, const model::Model<D>&,
                                                      const SparseMatrix&, std::vector<ContactPair<D>>)>;

template <int D>
const std::vector<std::pair<std::string, Maker<D>>>& registry() {
  static const std::vector<std::pair<std::string, Maker<D>>> methods = {
      {"elimination",
       [](const io::Scenario& s, const model::Model<D>& m, const SparseMatrix& mass, std::vector<ContactPair<D>> p) {
         return std::make_unique<EliminationMethod<D>>(m, mass, std::move(p), impact_location(s),
                                                       s.active_set.scheme == io::ContactScheme::persistent);
       }},
      {"lagrange",
       [](const io::Scenario& s, const model::Model<D>& m, const SparseMatrix& mass, std::vector<ContactPair<D>> p) {
         return std::make_unique<LagrangeMethod<D>>(m, mass, std::move(p), impact_location(s),
                                                    s.active_set.scheme == io::ContactScheme::persistent);
       }},
      {"penalty",
       [](const io::Scenario& s, const model::Model<D>& m, const SparseMatrix&, std::vector<ContactPair<D>> p) {
         std::vector<double> penalty;
         for (const ContactPair<D>& pair : p) penalty.push_back(s.contacts[static_cast<std::size_t>(pair.contact)].penalty);
         return std::make_unique<PenaltyMethod<D>>(m, std::move(p), penalty,
                                                   s.contacts.front().penalty_force == io::PenaltyForce::conserving);
       }},
  };
  return methods;
}

}  // namespace

std::vector<std::string> method_names() {
  std::vector<std::string> names;
  for (const auto& [name, make] : registry<3>()) names.push_back(name);
  return names;
}

template <int D>
std::unique_ptr<Method<D>> make_method(const io::Scenario& scenario, const model::Model<D>& model,
                                       const SparseMatrix& mass, std::vector<ContactPair<D>> pairs) {
  const std::string name = scenario.contacts.empty() ? "elimination" : scenario.contacts.front().method;
  for (const auto& [known, make] : registry<D>())
    if (known == name) return make(scenario, model, mass, std::move(pairs));
  throw InputError(fmt::format("unknown contact method '{}' (known: {})", name, fmt::join(method_names(), ", ")));
}

template std::unique_ptr<Method<2>> make_method<2>(const io::Scenario&, const model::Model<2>&, const SparseMatrix&,
                                                   std::vector<ContactPair<2>>);
template std::unique_ptr<Method<3>> make_method<3>(const io::Scenario&, const model::Model<3>&, const SparseMatrix&,
                                                   std::vector<ContactPair<3>>);

}  // namespace conserve::contact
