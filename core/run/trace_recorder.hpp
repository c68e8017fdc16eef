// Traces (output.traces): chosen states and outputs of chosen cells, the
// tissue strain when mechanics runs, and the integrator's step (variable
// "dt_ms", once, not per cell) if listed, sampled during the run into memory and,
// with an output directory, into traces.csv (one row per sample time).
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "integrate/cell_system.hpp"
#include "io/checkpoint_file.hpp"
#include "io/csv_writer.hpp"
#include "mechanics/mechanics_solver.hpp"
#include "scene/scene.hpp"

namespace fibrodem {

// A traced quantity: a state or an output of one cell.
struct TraceColumn {
  std::string variable;
  int cell = 0;
  int population = 0;
  std::size_t local = 0;
  bool is_output = false;
  bool myofilament = false;  // population indexes CellSystem::myofilaments
  int index = 0;
  int strain = -1;           // >= 0: the tissue strain component (no cell)
  bool step = false;         // the integrator's last step, dt_ms (no cell)
  std::string unit;          // as the model declares it ("mV", "mM"); "1" for strain
  std::string name() const { return strain >= 0 || step ? variable : variable + "_" + std::to_string(cell); }
};

class TraceRecorder {
 public:
  TraceRecorder() = default;
  // Resolves the scene's output.traces against the built cell system: the
  // strain columns first (with_mechanics), then each cell's variables. Throws
  // ManifestError naming the JSON path for a cell that does not exist, a
  // variable no model of the cell has, a strain without mechanics, or (fixed
  // step methods) sampling times off the step grid. `contraction`: whether the
  // myofilament models are loaded (the error message says so when not).
  TraceRecorder(const Scene& scene, CellSystem& system, bool with_mechanics, bool contraction);

  // Creates traces.csv with its header (t_ms, then the column names).
  void open_csv(const std::filesystem::path& file);
  void flush_csv();
  // The samples taken and the next one due, and traces.csv's length, for a
  // checkpoint; load() also reopens traces.csv cut back to that length.
  void save(CheckpointFields& fields);
  void load(const CheckpointFields& fields, const std::filesystem::path& csv_file);

  // The next time a sample is due (+inf: none; no columns, or past the end).
  double next_sample_ms() const;
  // Records every column at t (the populations hold the state at t).
  // `mechanics` must be given when strain columns were resolved.
  void sample(double t, CellSystem& system, const MechanicsSolver* mechanics);

  // A run split over ranks (docs/guide/parallel.md): each rank records the columns
  // of its own cells (and dt_ms; rank 0, which steps the mechanics, the
  // strain too); rank 0 merges them at the end. What a rank sends: its
  // columns as text (a line "variable\tcell\tunit\tstep" each) and its
  // samples as numbers (the times, then each column's samples).
  std::string packed_columns() const;
  std::vector<double> packed_samples() const;
  // Rank 0: every rank's packed columns and samples (in rank order) taken as
  // this recorder's, in the order one process records them (`spec`'s).
  void merge(const TraceSpec& spec, const std::vector<std::string>& columns_by_rank,
             const std::vector<std::vector<double>>& samples_by_rank);
  // traces.csv whole, from the samples held (after merge()).
  void write_csv(const std::filesystem::path& file);

  const std::vector<TraceColumn>& columns() const { return columns_; }
  std::vector<std::string> column_names() const;
  // Each traced variable's unit, as the models declare it (summary.json
  // "trace_units", so a plot of traces.csv can label its axes).
  json units() const;
  const std::vector<double>& times() const { return times_; }
  const std::vector<std::vector<double>>& samples() const { return samples_; }
  // Samples of a traced variable of a cell (the tissue-wide strain and dt_ms:
  // cell 0); throws std::out_of_range if it was not traced.
  const std::vector<double>& trace(const std::string& variable, int cell) const;

 private:
  void add_cell_columns(const TraceBlock& spec, CellSystem& system, bool with_mechanics, bool contraction);
  static void check_sampling_grid(const TraceSpec& spec, const SolverSpec& solver);

  std::vector<TraceColumn> columns_;
  bool need_outputs_ = false;  // some column is a model output: evaluate before sampling
  double from_ms_ = 0, every_ms_ = 0, until_ms_ = 0;
  long long next_sample_index_ = 0;
  std::vector<double> times_;
  std::vector<std::vector<double>> samples_;  // per column
  CsvWriter csv_;
};

}  // namespace fibrodem
