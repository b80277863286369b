#include "simulation/checkpoint.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <sstream>
#include <string_view>
#include <system_error>

#include "core/bytes.hpp"
#include "core/error.hpp"

namespace conserve::simulation {
namespace {

constexpr std::string_view kMagic = "conserve-checkpoint";
/// 2: 64-bit step and counters, the fingerprint's named entries instead of
/// one hash. 3: the constraints' activation step and normal force. 4: the
/// end of a step cut short at an impact. 5: the count of constraint-steps
/// under the rate condition (48) in the run's totals. 6: no end of a cut
/// step (the steps after one go on at the full Δt). 7: the push-outs and
/// their work in the run's totals. 8: the crease pairs formed
/// (contact::ActiveSet::crease) in the run's totals. 9: the constraints'
/// given-up push-outs (contact::Constraint::hold) and their count in the
/// run's totals. 10: the constraints' force at the start of their last
/// step and the lengths of the last two steps (located releases).
/// 13: the contact method's state as its own bytes (contact::Method::save).
/// 14: a penalty force's pair and whole vector; the state's load work.
/// 15: the state's work of each support and released energy; the drifts'
/// deviations instead of their ratios. 16: the integrator's state. 17:
/// the contact's release and activation times (contact::ImpactLocation);
/// the free rigid bodies' motions. 18: the state's friction dissipation;
/// the constraints' friction μ and slip regularization (Coulomb). 19:
/// the run statistics as every run's, then the contact method's own.
/// 20: the integrator keeps the kept tangent's first contraction.
constexpr std::uint32_t kVersion = 20;

using Writer = ByteWriter;
using Reader = ByteReader;

void write_totals(Writer& w, const RunTotals& t) {
  w.doubles(t.drift.deviation.data(), t.drift.deviation.size());
  w.value(t.drift.energy_reference);
  w.value(t.drift.momentum_reference);
  const std::vector<std::string> keys = t.statistics.keys();
  w.value(static_cast<std::uint64_t>(keys.size()));
  for (std::size_t k = 0; k < keys.size(); ++k) {
    w.text(keys[k]);
    w.value(t.statistics.accumulated[k]);
  }
  w.value(t.statistics.steps);
}

/// The run statistics, key by key, into `statistics` (the run's, with its
/// contact method's own): a checkpoint with other statistics is refused
/// naming the first that differs.
RunTotals read_totals(Reader& r, RunStatistics statistics) {
  RunTotals t{.drift = {}, .statistics = std::move(statistics)};
  r.doubles(t.drift.deviation.data(), t.drift.deviation.size(), "the deviations");
  t.drift.energy_reference = r.value<double>();
  t.drift.momentum_reference = r.value<double>();
  const std::vector<std::string> keys = t.statistics.keys();
  const auto count = r.value<std::uint64_t>();
  if (count != keys.size())
    r.fail(fmt::format("it holds {} run statistics, this run keeps {} (restart with the conserve and the "
                       "contact method that wrote it, or run from the start)",
                       count, keys.size()));
  for (std::size_t k = 0; k < keys.size(); ++k) {
    const std::string key = r.text(256);
    if (key != keys[k])
      r.fail(fmt::format("its run statistic {} is '{}' where this run keeps '{}' (restart with the conserve "
                         "and the contact method that wrote it, or run from the start)",
                         k, key, keys[k]));
    t.statistics.accumulated[k] = r.value<double>();
  }
  t.statistics.steps = r.value<double>();
  return t;
}

void write_fingerprint(Writer& w, const Fingerprint& f) {
  w.value(static_cast<std::uint64_t>(f.size()));
  for (const auto& e : f) {
    w.text(e.name);
    w.value(e.hash);
    w.text(e.value);
  }
}

Fingerprint read_fingerprint(Reader& r) {
  constexpr std::uint64_t kMostEntries = 1 << 20;
  constexpr std::size_t kLongest = 1 << 16;
  const auto count = r.value<std::uint64_t>();
  if (count > kMostEntries) r.fail("too many fingerprint entries");
  Fingerprint f(count);
  for (auto& e : f) {
    e.name = r.text(kLongest);
    e.hash = r.value<std::uint64_t>();
    e.value = r.text(kLongest);
  }
  return f;
}

std::string slurp(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in)
    throw InputError(
        fmt::format("{}: cannot open the checkpoint (expected a file written by conserve run)", file.string()));
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace


std::filesystem::path checkpoint_path(const std::filesystem::path& output_directory, std::int64_t step) {
  return output_directory / "checkpoints" / fmt::format("ckpt_{:06d}.bin", step);
}

int prune_checkpoints(const std::filesystem::path& output_directory, std::int64_t current_step, int keep) {
  if (keep <= 0) return 0;
  const auto folder = output_directory / "checkpoints";
  std::vector<std::int64_t> older;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(folder, ec)) {
    const std::string name = entry.path().filename().string();
    // "ckpt_" + six to eighteen digits + ".bin"
    if (name.size() < 15 || name.size() > 27 || !name.starts_with("ckpt_") || !name.ends_with(".bin")) continue;
    const std::string digits = name.substr(5, name.size() - 9);
    if (!std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; })) continue;
    const std::int64_t step = std::stoll(digits);
    if (step < current_step) older.push_back(step);
  }
  std::sort(older.begin(), older.end(), std::greater<>());
  int deleted = 0;
  for (std::size_t i = static_cast<std::size_t>(keep - 1); i < older.size(); ++i)
    deleted += std::filesystem::remove(checkpoint_path(output_directory, older[i]), ec) ? 1 : 0;
  return deleted;
}

template <int D>
void write_checkpoint(const std::filesystem::path& file, const Checkpoint<D>& c) {
  Writer w;
  w.value(kMagic.size());
  for (char ch : kMagic) w.value(ch);
  w.value(kVersion);
  w.value(static_cast<std::int32_t>(D));
  write_fingerprint(w, c.fingerprint);
  w.value(static_cast<std::int64_t>(c.state.step));
  w.value(c.state.time);
  w.doubles(c.state.u.data(), c.state.u.size());
  w.doubles(c.state.v.data(), c.state.v.size());
  w.value(c.state.load_work);
  w.value(static_cast<std::uint64_t>(c.state.support_work.size()));
  w.doubles(c.state.support_work.data(), c.state.support_work.size());
  w.value(c.state.released);
  w.value(c.state.dissipated);
  w.value(static_cast<std::uint64_t>(c.state.rigid.size()));
  for (const model::RigidBodyState& b : c.state.rigid) {
    w.doubles(b.center.data(), 3);
    w.doubles(b.velocity.data(), 3);
    w.doubles(b.rotation.data(), 9);
    w.doubles(b.spin.data(), 3);
  }
  w.value(c.control.dt);
  w.value(static_cast<std::int32_t>(c.control.good_steps));
  w.value(static_cast<std::int64_t>(c.control.cutbacks));
  w.value(c.control.last_dt);
  w.value(c.control.previous_dt);
  write_totals(w, c.totals);
  w.text(c.contact);
  w.text(c.integrator);

  std::error_code ec;
  std::filesystem::create_directories(file.parent_path(), ec);
  if (ec) throw Error(fmt::format("cannot create {}: {}", file.parent_path().string(), ec.message()));
  auto temporary = file;
  temporary += ".tmp";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out.write(w.bytes().data(), static_cast<std::streamsize>(w.bytes().size()));
    if (!out.flush()) throw Error(fmt::format("{}: write failed", temporary.string()));
  }
  std::filesystem::rename(temporary, file, ec);
  if (ec) throw Error(fmt::format("{}: cannot rename into place: {}", file.string(), ec.message()));
}

template <int D>
Checkpoint<D> read_checkpoint(const std::filesystem::path& file, const Fingerprint& expected,
                              const model::Model<D>& model, RunStatistics statistics) {
  Reader r(slurp(file), file.string());
  std::string magic(r.value<std::size_t>() == kMagic.size() ? kMagic.size() : 0, ' ');
  for (char& ch : magic) ch = r.value<char>();
  if (magic != kMagic) r.fail("not a conserve checkpoint");
  if (const auto version = r.value<std::uint32_t>(); version != kVersion)
    r.fail(
        fmt::format("format version {}, this conserve reads version {} only (restart with the conserve that "
                    "wrote it, or run from the start)",
                    version, kVersion));
  if (r.value<std::int32_t>() != D) r.fail(fmt::format("not of a {}D scenario", D));
  Checkpoint<D> c;
  c.fingerprint = read_fingerprint(r);
  if (const std::string difference = first_difference(c.fingerprint, expected); !difference.empty())
    r.fail("written by another scenario: " + difference);
  c.state.step = r.value<std::int64_t>();
  c.state.time = r.value<double>();
  c.state.u.resize(model.num_dofs());
  c.state.v.resize(model.num_dofs());
  r.doubles(c.state.u.data(), c.state.u.size(), "the displacement");
  r.doubles(c.state.v.data(), c.state.v.size(), "the velocity");
  c.state.load_work = r.value<double>();
  if (r.value<std::uint64_t>() != model.prescribed.supports.size()) r.fail("the supports differ from the scenario's");
  c.state.support_work.resize(model.prescribed.supports.size());
  r.doubles(c.state.support_work.data(), c.state.support_work.size(), "the supports' work");
  c.state.released = r.value<double>();
  c.state.dissipated = r.value<double>();
  if (r.value<std::uint64_t>() != model.free_bodies.size()) r.fail("the free bodies differ from the scenario's");
  c.state.rigid.resize(model.free_bodies.size());
  for (model::RigidBodyState& b : c.state.rigid) {
    r.doubles(b.center.data(), 3, "a free body's centre");
    r.doubles(b.velocity.data(), 3, "a free body's velocity");
    r.doubles(b.rotation.data(), 9, "a free body's rotation");
    r.doubles(b.spin.data(), 3, "a free body's spin");
  }
  c.control.dt = r.value<double>();
  c.control.good_steps = r.value<std::int32_t>();
  c.control.cutbacks = r.value<std::int64_t>();
  c.control.last_dt = r.value<double>();
  c.control.previous_dt = r.value<double>();
  c.totals = read_totals(r, std::move(statistics));
  // The contact method's state: at most a few hundred bytes a node.
  c.contact = r.text(static_cast<std::size_t>(model.num_nodes()) * 1024 + 1024, true);
  // The integrator's: at most two tangents' states of three vectors each.
  c.integrator = r.text(static_cast<std::size_t>(model.num_dofs()) * 6 * sizeof(double) + 4096, true);
  if (!r.at_end()) r.fail("trailing bytes after the integrator's state");
  if (c.state.step < 0 || c.control.cutbacks < 0 || !(c.control.dt > 0.0) || !(c.control.last_dt >= 0.0) ||
      !(c.control.previous_dt >= 0.0))
    r.fail("bad step or step size");
  return c;
}

template void write_checkpoint<2>(const std::filesystem::path&, const Checkpoint<2>&);
template void write_checkpoint<3>(const std::filesystem::path&, const Checkpoint<3>&);
template Checkpoint<2> read_checkpoint<2>(const std::filesystem::path&, const Fingerprint&, const model::Model<2>&,
                                          RunStatistics);
template Checkpoint<3> read_checkpoint<3>(const std::filesystem::path&, const Fingerprint&, const model::Model<3>&,
                                          RunStatistics);

}  // namespace conserve::simulation
