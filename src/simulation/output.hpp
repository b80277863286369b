#pragma once
/// What a run writes: the per-step CSV history and VTU snapshots with a
/// PVD time series (points are the current configuration; cells are the
/// bodies' simplices, then the facets of bare rigid surfaces).
#include <filesystem>
#include <memory>
#include <optional>

#include "assembly/assembler.hpp"
#include "contact/method.hpp"
#include "io/history_writer.hpp"
#include "io/vtu_writer.hpp"
#include "simulation/drift.hpp"
#include "simulation/stepper.hpp"
#include "time/diagnostics.hpp"

namespace conserve::simulation {

/// Column names of history.csv, in order: the totals, then each body's
/// linear momentum "L_x:NAME", "L_y:NAME", "L_z:NAME", then each contact
/// pair's force on its slave side "F_x:SLAVE>MASTER", … (surfaces as
/// "body:group"), then per support (a [[boundary]] group "BODY:GROUP" or a
/// rigid body "NAME", model::Support) its reaction "R_x:NAME", …, the
/// reaction's moment about the origin "M_x:NAME", …, the mean
/// displacement of its nodes "u_x:NAME", … and the work it has done since
/// t = 0 "work:NAME", then per free rigid body its angular velocity
/// "w_x:NAME", …. A NaN value (e.g. min_active_gap with no active slave)
/// is written as an empty field.
std::vector<std::string> history_columns(const std::vector<std::string>& body_names = {},
                                         const std::vector<std::string>& pair_names = {},
                                         const std::vector<std::string>& support_names = {},
                                         const std::vector<std::string>& free_names = {},
                                         const std::vector<contact::MethodStatistic>& own = {});

/// On several ranks (solver/ranks.hpp) every rank makes one and calls it
/// alike: rank 0 writes the history and the folder's files, each rank
/// writes its piece of a VTU frame (vtu/step_NNNNNN_RANK.vtu, an equal
/// share of the cells) and rank 0 the frame's .pvtu. A failure on one rank
/// is not collective here: callers wrap the calls in ranks::together().
template <int D>
class OutputWriter {
 public:
  /// Creates `directory` (and vtu/ in it when spec.vtu_every > 0).
  /// `contacts` (may be null) adds the contact columns' values and the
  /// slaves' VTU fields. `resume_time`: a restart at that time [s] keeps
  /// solution.pvd's earlier entries.
  OutputWriter(const assembly::Assembler<D>& assembler, const std::filesystem::path& directory,
               const io::OutputSpec& spec, contact::Method<D>* contacts = nullptr,
               std::optional<double> resume_time = std::nullopt);

  /// Appends the history row of `state` (figures: what the step that
  /// produced it did, an empty record for the initial state; drift: its
  /// relative drifts) and writes a VTU if due.
  void write(const model::State& state, const StepFigures& figures, const Drifts& drift, bool last);
  /// Writes a VTU of `state` (if VTU output is on) without a history row,
  /// e.g. the last converged state of a run that stops.
  void write_snapshot(const model::State& state) {
    if (pvd_) write_vtu(state);
  }
  /// VTU frames written and their bytes.
  [[nodiscard]] std::int64_t frames() const { return frames_; }
  [[nodiscard]] std::uintmax_t frame_bytes() const { return frame_bytes_; }

 private:
  void write_vtu(const model::State& state);
  /// The slaves' fields: contact_normal_force, contact_pressure,
  /// contact_gap, contact_status.
  void add_contact_fields(const model::State& state, io::VtuGrid& grid) const;
  void write_contact_state(const model::State& state) const;
  const assembly::Assembler<D>& assembler_;
  /// The facets of the bodies without cells (bare rigid surfaces), D × n,
  /// written as cells after the model's, and the body of each.
  Eigen::MatrixXi surface_facets_;
  std::vector<int> surface_body_;
  contact::Method<D>* contacts_;
  double last_time_ = 0.0;  ///< time of the last row (the step's length)
  bool contact_state_;
  std::filesystem::path directory_;
  int vtu_every_;
  io::VtuFormat format_;
  std::int64_t frames_ = 0;
  std::uintmax_t frame_bytes_ = 0;  ///< this rank's
  int rank_, ranks_;
  std::optional<io::HistoryWriter> history_;  ///< rank 0's
  std::unique_ptr<io::PvdWriter> pvd_;
};

}  // namespace conserve::simulation
