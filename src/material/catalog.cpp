/// The laws `[body.material] model` can name: one line each.
#include <fmt/format.h>

#include "core/error.hpp"
#include "material/law.hpp"
#include "material/mooney_rivlin.hpp"
#include "material/neo_hookean.hpp"
#include "material/svk_law.hpp"

namespace conserve::material {

const std::map<std::string, LawInfo>& law_catalog() {
  static const std::map<std::string, LawInfo> catalog = {
      {"svk", svk_info()},
      {"neo_hookean", neo_hookean_info()},
      {"mooney_rivlin", mooney_rivlin_info()},
  };
  return catalog;
}

std::shared_ptr<const Law> make_law(const std::string& model, const std::map<std::string, double>& parameters) {
  const auto it = law_catalog().find(model);
  if (it == law_catalog().end()) throw InputError(fmt::format("unknown material model '{}'", model));
  return it->second.make(parameters);
}

}  // namespace conserve::material
