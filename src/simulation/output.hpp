#pragma once
/// What a run writes: the per-step CSV history and VTU snapshots with a
/// PVD time series (points are the current configuration).
#include <filesystem>
#include <memory>

#include "assembly/assembler.hpp"
#include "io/history_writer.hpp"
#include "io/vtu_writer.hpp"
#include "solver/newton.hpp"
#include "time/diagnostics.hpp"

namespace conserve::simulation {

/// Column names of history.csv, in order.
std::vector<std::string> history_columns();

template <int D>
class OutputWriter {
 public:
  /// Creates `directory` (and vtu/ in it when vtu_every > 0).
  OutputWriter(const assembly::Assembler<D>& assembler, const std::filesystem::path& directory, int vtu_every);

  /// Appends the history row of `state` (report: the Newton solve that
  /// produced it, none for the initial state) and writes a VTU if due.
  void write(const model::State& state, const time::Diagnostics& d, const solver::NewtonReport* report, bool last);

 private:
  void write_vtu(const model::State& state);
  const assembly::Assembler<D>& assembler_;
  std::filesystem::path directory_;
  int vtu_every_;
  io::HistoryWriter history_;
  std::unique_ptr<io::PvdWriter> pvd_;
};

}  // namespace conserve::simulation
