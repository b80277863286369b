// Contact-search benchmarks: bounding-volume tree build and refit over a
// master surface of ~10k, ~100k and ~1M triangles (a wavy sheet
// z = 0.05 sin(6πx) sin(4πy) on [0,1]², surface only), and the search of
// 10 000 slave points a quarter of an element above it (query + projection,
// as find_master does). Run:
//   ./build/release/bench/conserve_bench --benchmark_filter=Contact
// `per_query` is the time per slave point [s].
#include <benchmark/benchmark.h>

#include <cmath>
#include <map>
#include <memory>

#include "contact/search.hpp"

namespace conserve {
namespace {

constexpr int kSlaveSide = 100;  // 100 × 100 slave points

double wave(double x, double y, double phase) {
  const double pi = std::acos(-1.0);
  return 0.05 * std::sin(6 * pi * x + phase) * std::sin(4 * pi * y);
}

/// The master sheet (n × n squares, two triangles each, normals up) and
/// the slave points above it.
struct Sheet {
  int n = 0;
  contact::ContactSurface surface;
  contact::Positions<3> x;      ///< master nodes
  contact::Positions<3> moved;  ///< the same nodes, the wave shifted (for refit)
  std::vector<Vec3> slaves;
  contact::SearchSettings settings;

  explicit Sheet(int facets) : n(static_cast<int>(std::lround(std::sqrt(facets / 2.0)))) {
    const double h = 1.0 / n;
    const auto id = [&](int i, int j) { return i + (n + 1) * j; };
    x.resize(3, (n + 1) * (n + 1));
    moved.resize(3, x.cols());
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        x.col(id(i, j)) << i * h, j * h, wave(i * h, j * h, 0.0);
        moved.col(id(i, j)) << i * h, j * h, wave(i * h, j * h, 0.3);
      }
    surface.facets.resize(3, 2 * n * n);
    for (int j = 0, f = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        surface.facets.col(f++) << id(i, j), id(i + 1, j), id(i + 1, j + 1);
        surface.facets.col(f++) << id(i, j), id(i + 1, j + 1), id(i, j + 1);
      }
    contact::build_adjacency(surface, 3);
    for (int j = 0; j < kSlaveSide; ++j)
      for (int i = 0; i < kSlaveSide; ++i) {
        const double sx = (i + 0.37) / kSlaveSide, sy = (j + 0.61) / kSlaveSide;
        slaves.emplace_back(sx, sy, wave(sx, sy, 0.0) + 0.25 * h);
      }
    settings.search_distance = h;  // one element size
  }

  static Sheet& get(int facets) {
    static std::map<int, std::unique_ptr<Sheet>> cache;
    auto& sheet = cache[facets];
    if (!sheet) sheet = std::make_unique<Sheet>(facets);
    return *sheet;
  }
};

void BM_ContactTreeBuild(benchmark::State& st) {
  Sheet& sheet = Sheet::get(static_cast<int>(st.range(0)));
  contact::FacetTree<3> tree;
  for (auto _ : st) {
    tree.build(sheet.surface.facets, sheet.x);
    benchmark::ClobberMemory();
  }
  st.counters["facets"] = sheet.surface.num_facets();
}

void BM_ContactTreeRefit(benchmark::State& st) {
  Sheet& sheet = Sheet::get(static_cast<int>(st.range(0)));
  contact::FacetTree<3> tree;
  tree.build(sheet.surface.facets, sheet.x);
  bool flip = false;
  for (auto _ : st) {
    tree.refit((flip = !flip) ? sheet.moved : sheet.x);
    benchmark::ClobberMemory();
  }
  st.counters["facets"] = sheet.surface.num_facets();
}

/// Broad phase alone: candidates per slave point.
void BM_ContactQuery(benchmark::State& st) {
  Sheet& sheet = Sheet::get(static_cast<int>(st.range(0)));
  contact::FacetTree<3> tree;
  tree.build(sheet.surface.facets, sheet.x);
  std::vector<int> out;
  std::size_t candidates = 0;
  for (auto _ : st) {
    candidates = 0;
    for (const auto& p : sheet.slaves) {
      tree.query(p, sheet.settings.search_distance, out);
      candidates += out.size();
    }
    benchmark::DoNotOptimize(candidates);
  }
  const auto queries = static_cast<double>(sheet.slaves.size());
  st.counters["per_query"] =
      benchmark::Counter(queries, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  st.counters["candidates"] = static_cast<double>(candidates) / queries;
}

/// Query + projection + the selection rules: find_master for every slave.
void BM_ContactFindMaster(benchmark::State& st) {
  Sheet& sheet = Sheet::get(static_cast<int>(st.range(0)));
  contact::FacetTree<3> tree;
  tree.build(sheet.surface.facets, sheet.x);
  int matched = 0;
  for (auto _ : st) {
    matched = 0;
    for (const auto& p : sheet.slaves)
      matched += contact::find_master<3>(p, sheet.surface, tree, sheet.x, sheet.settings).has_value();
    benchmark::DoNotOptimize(matched);
  }
  st.counters["per_query"] =
      benchmark::Counter(static_cast<double>(sheet.slaves.size()),
                         benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  st.counters["matched"] = matched;
}

BENCHMARK(BM_ContactTreeBuild)->Arg(10'000)->Arg(100'000)->Arg(1'000'000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ContactTreeRefit)->Arg(10'000)->Arg(100'000)->Arg(1'000'000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ContactQuery)->Arg(10'000)->Arg(100'000)->Arg(1'000'000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ContactFindMaster)->Arg(10'000)->Arg(100'000)->Arg(1'000'000)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace conserve
