// The constraint methods' registry: a new method is a folder and one
// entry here.
#include <fmt/format.h>

#include <functional>

#include "contact/elimination/method.hpp"
#include "contact/method.hpp"
#include "contact/penalty/penalty.hpp"
#include "core/error.hpp"

namespace conserve::contact {
namespace {

template <int D>
using Maker = std::function<std::unique_ptr<Method<D>>(const MethodSettings&, const model::Model<D>&,
                                                      const SparseMatrix&, std::vector<ContactPair<D>>)>;

template <int D>
const std::vector<std::pair<std::string, Maker<D>>>& registry() {
  static const std::vector<std::pair<std::string, Maker<D>>> methods = {
      {"elimination",
       [](const MethodSettings& s, const model::Model<D>& m, const SparseMatrix& mass, std::vector<ContactPair<D>> p) {
         return std::make_unique<EliminationMethod<D>>(m, mass, std::move(p), s.gap_tolerance, s.persistent);
       }},
      {"penalty",
       [](const MethodSettings& s, const model::Model<D>& m, const SparseMatrix&, std::vector<ContactPair<D>> p) {
         return std::make_unique<PenaltyMethod<D>>(m, std::move(p), s.penalty, s.conserving);
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
std::unique_ptr<Method<D>> make_method(const MethodSettings& settings, const model::Model<D>& model,
                                       const SparseMatrix& mass, std::vector<ContactPair<D>> pairs) {
  for (const auto& [name, make] : registry<D>())
    if (name == settings.name) return make(settings, model, mass, std::move(pairs));
  throw InputError(fmt::format("unknown contact method '{}' (known: {})", settings.name,
                               fmt::join(method_names(), ", ")));
}

template std::unique_ptr<Method<2>> make_method<2>(const MethodSettings&, const model::Model<2>&, const SparseMatrix&,
                                                   std::vector<ContactPair<2>>);
template std::unique_ptr<Method<3>> make_method<3>(const MethodSettings&, const model::Model<3>&, const SparseMatrix&,
                                                   std::vector<ContactPair<3>>);

}  // namespace conserve::contact
