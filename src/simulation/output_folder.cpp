#include "simulation/output_folder.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.hpp"

namespace conserve::simulation {
namespace {

/// Files with one name per run: rewritten from the start by a fresh run.
constexpr std::array kRunFiles = {"history.csv", "steps.csv", "cutbacks.log", "scenario.toml", "solution.pvd"};
/// Files that describe a whole run: stale as soon as a run starts.
constexpr std::array kWholeRunFiles = {"summary.json",     "energy.png",  "momentum.png", "body_momentum.png",
                                       "contact.png",      "drift.png",   "snapshots.png"};

/// Per-step files: the folder, the name's prefix and suffix around the step number.
struct PerStep {
  std::string_view folder, prefix, suffix;
};
constexpr std::array kPerStepFiles = {PerStep{"vtu", "step_", ".vtu"}, PerStep{"vtu", "step_", ".pvtu"},
                                      PerStep{"vtu", "contact_", ".vtu"},
                                      PerStep{"checkpoints", "ckpt_", ".bin"}, PerStep{"", "snapshot_", ".png"}};

/// The step number of `name` if it is `prefix` + digits + (anything) + `suffix`.
std::optional<std::int64_t> step_of(std::string_view name, const PerStep& kind) {
  if (!name.starts_with(kind.prefix) || !name.ends_with(kind.suffix)) return std::nullopt;
  const std::string_view rest = name.substr(kind.prefix.size());
  const std::size_t digits = std::find_if(rest.begin(), rest.end(), [](char c) { return c < '0' || c > '9'; }) -
                             rest.begin();
  if (digits == 0 || digits > 18) return std::nullopt;
  return std::stoll(std::string(rest.substr(0, digits)));
}

}  // namespace

int clear_earlier_run(const std::filesystem::path& dir, std::optional<std::int64_t> restart_step) {
  namespace fs = std::filesystem;
  int removed = 0;
  const auto remove = [&](const fs::path& file) {
    std::error_code ec;
    if (!fs::is_regular_file(file, ec)) return;
    if (!fs::remove(file, ec) || ec)
      throw Error(fmt::format("cannot remove {} of an earlier run from the output folder: {}", file.string(),
                              ec ? ec.message() : "not removed"));
    ++removed;
  };
  for (const char* name : kWholeRunFiles) remove(dir / name);
  if (!restart_step)
    for (const char* name : kRunFiles) remove(dir / name);
  for (const PerStep& kind : kPerStepFiles) {
    std::error_code ec;
    const fs::path folder = kind.folder.empty() ? dir : dir / kind.folder;
    std::vector<fs::path> stale;
    for (const auto& entry : fs::directory_iterator(folder, ec)) {
      const auto step = step_of(entry.path().filename().string(), kind);
      if (step && (!restart_step || *step > *restart_step)) stale.push_back(entry.path());
    }
    for (const fs::path& file : stale) remove(file);
  }
  return removed;
}

}  // namespace conserve::simulation
