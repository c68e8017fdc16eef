#include "run/trace_recorder.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "model/population.hpp"
#include "scene/effects.hpp"
#include "util/json_reader.hpp"
#include "util/manifest_error.hpp"
#include "stimulus/stimulus.hpp"

namespace fibrodem {

namespace {

constexpr const char* kStrainNames[3] = {"eps_xx", "eps_yy", "eps_xy"};
constexpr const char* kStepVariable = "dt_ms";

std::string list_names(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

// Points col at variable's state, else its output, in pop; false if neither.
bool find_column(const Population& pop, TraceColumn& col) {
  col.index = find_state(pop.info(), col.variable);
  col.is_output = col.index < 0;
  if (col.is_output) col.index = find_output(pop.info(), col.variable);
  if (col.index < 0) return false;
  col.unit = col.is_output ? pop.info().outputs[static_cast<std::size_t>(col.index)].unit
                           : pop.info().states[static_cast<std::size_t>(col.index)].unit;
  return true;
}

}  // namespace

TraceRecorder::TraceRecorder(const Scene& scene, CellSystem& system, bool with_mechanics, bool contraction)
    : from_ms_(scene.output.traces.from_ms),
      every_ms_(scene.output.traces.every_ms),
      until_ms_(scene.duration_ms) {
  if (with_mechanics)  // the tissue strain is always traced with mechanics
    for (int k = 0; k < 3; ++k) columns_.push_back({kStrainNames[k], 0, 0, 0, false, false, 0, k, false, "1"});
  const auto vars = scene.output.traces.all_variables();
  if (std::find(vars.begin(), vars.end(), kStepVariable) != vars.end())
    columns_.push_back({kStepVariable, 0, 0, 0, false, false, 0, -1, true, "ms"});
  for (const auto& block : scene.output.traces.blocks) add_cell_columns(block, system, with_mechanics, contraction);
  samples_.assign(columns_.size(), {});
  if (scene.solver.fixed_step()) check_sampling_grid(scene.output.traces, scene.solver);
}

void TraceRecorder::add_cell_columns(const TraceBlock& spec, CellSystem& system, bool with_mechanics,
                                     bool contraction) {
  for (std::size_t i = 0; i < spec.cells.size(); ++i) {
    const int cell = spec.cells[i];
    const std::size_t tissue_cells = system.numbering.tissue_cells();
    if (cell >= static_cast<int>(tissue_cells))
      throw ManifestError(index_path(spec.path + ".cells", i),
                          "cell " + std::to_string(cell) + " does not exist (the tissue has " +
                              std::to_string(tissue_cells) + " cells)");
    // (Split over ranks, the scene's traces are this rank's own cells': held.)
    const auto held = static_cast<std::size_t>(system.numbering.held_cell(cell));
    for (std::size_t j = 0; j < spec.variables.size(); ++j) {
      const std::string& var = spec.variables[j];
      if (var == kStepVariable) continue;  // one column for the whole tissue
      if (is_strain_variable(var)) {
        if (!with_mechanics)
          throw ManifestError(index_path(spec.path + ".variables", j),
                              "\"" + var + "\" is the tissue strain, which needs the effect mechanics");
        continue;
      }
      const auto [p, local] = system.where[held];
      TraceColumn col;
      col.variable = var;
      col.cell = cell;
      col.population = p;
      col.local = local;
      col.index = -1;  // not found yet
      if (!find_column(system.populations[p], col))
        for (std::size_t m = 0; m < system.myofilaments.size(); ++m)
          if (system.myofilaments[m].host == p && find_column(system.myofilaments[m].pop, col)) {
            col.myofilament = true;
            col.population = static_cast<int>(m);
          }
      if (col.index < 0) {
        std::vector<std::string> names;
        system.for_each_part(held, [&](const Population& pop, std::size_t) {
          for (const auto& s : pop.info().states) names.push_back(s.name);
          for (const auto& o : pop.info().outputs) names.push_back(o.name);
        });
        throw ManifestError(index_path(spec.path + ".variables", j),
                            "\"" + var + "\" is neither a state nor an output of the models of cell " +
                                std::to_string(cell) + " (" + system.populations[p].info().name +
                                (contraction ? "" : "; myofilament models are loaded only with contraction") +
                                "); they have: " + list_names(names));
      }
      need_outputs_ = need_outputs_ || col.is_output;
      // A column two blocks both ask for is recorded once.
      if (std::none_of(columns_.begin(), columns_.end(), [&](const TraceColumn& c) { return c.name() == col.name(); }))
        columns_.push_back(col);
    }
  }
}

// A fixed-step method samples at step ends only: every_ms and from_ms must lie
// on the step grid.
void TraceRecorder::check_sampling_grid(const TraceSpec& spec, const SolverSpec& solver) {
  for (const auto& [value, path] : {std::pair{spec.every_ms, "output.traces.every_ms"},
                                    std::pair{spec.from_ms, "output.traces.from_ms"}}) {
    const double steps_per = value / solver.dt_ms;
    if (std::abs(steps_per - std::round(steps_per)) > 1e-6 * std::max(1.0, steps_per))
      throw ManifestError(path, "expected a multiple of solver.dt_ms (" + format_number(solver.dt_ms) +
                                    " ms) for a fixed-step method, got " + format_number(value));
  }
}

void TraceRecorder::open_csv(const std::filesystem::path& file) {
  std::vector<std::string> header = {"t_ms"};
  for (const auto& c : columns_) header.push_back(c.name());
  csv_ = CsvWriter(file, header);
}

void TraceRecorder::flush_csv() {
  if (csv_.is_open()) csv_.flush();
}

void TraceRecorder::save(CheckpointFields& fields) {
  fields.put_integer("traces.next_sample", next_sample_index_);
  fields.put("traces.t_ms", times_);
  for (std::size_t i = 0; i < columns_.size(); ++i) fields.put("traces.column." + columns_[i].name(), samples_[i]);
  if (csv_.is_open()) fields.put_integer("traces.csv_bytes", static_cast<long long>(csv_.bytes_written()));
}

void TraceRecorder::load(const CheckpointFields& fields, const std::filesystem::path& csv_file) {
  times_ = fields.numbers("traces.t_ms");
  next_sample_index_ = fields.integer("traces.next_sample");
  if (next_sample_index_ != static_cast<long long>(times_.size()))  // one sample per index, none skipped
    throw CheckpointError("its traces hold " + std::to_string(times_.size()) + " samples but say the next is number " +
                          std::to_string(next_sample_index_));
  for (std::size_t i = 0; i < columns_.size(); ++i)
    samples_[i] = fields.numbers("traces.column." + columns_[i].name(), static_cast<long long>(times_.size()));
  if (!csv_file.empty())
    csv_ = CsvWriter::resume(csv_file, static_cast<std::uintmax_t>(fields.integer("traces.csv_bytes")));
}

double TraceRecorder::next_sample_ms() const {
  if (columns_.empty()) return std::numeric_limits<double>::infinity();
  const double t = from_ms_ + static_cast<double>(next_sample_index_) * every_ms_;
  return t <= until_ms_ + kTimeEpsilon_ms ? t : std::numeric_limits<double>::infinity();
}

void TraceRecorder::sample(double t, CellSystem& system, const MechanicsSolver* mechanics) {
  if (need_outputs_) {
    system.evaluate(t, t);
  }
  times_.push_back(t);
  if (csv_.is_open()) csv_.cell(t);
  for (std::size_t i = 0; i < columns_.size(); ++i) {
    const TraceColumn& c = columns_[i];
    const Population& pop = c.myofilament ? system.myofilaments[c.population].pop : system.populations[c.population];
    const double value = c.step          ? system.last_step_ms
                         : c.strain >= 0 ? mechanics->strain()[c.strain]
                         : c.is_output ? pop.outputs[c.index * pop.size() + c.local]
                                       : pop.y[c.index * pop.size() + c.local];
    samples_[i].push_back(value);
    if (csv_.is_open()) csv_.cell(value);
  }
  if (csv_.is_open()) csv_.end_row();
  ++next_sample_index_;
}

std::string TraceRecorder::packed_columns() const {
  std::string text;
  for (const auto& c : columns_)
    text += c.variable + "\t" + std::to_string(c.cell) + "\t" + c.unit + "\t" + (c.step ? "1" : "0") + "\n";
  return text;
}

std::vector<double> TraceRecorder::packed_samples() const {
  std::vector<double> packed(times_);
  for (const auto& column : samples_) packed.insert(packed.end(), column.begin(), column.end());
  return packed;
}

void TraceRecorder::merge(const TraceSpec& spec, const std::vector<std::string>& columns_by_rank,
                          const std::vector<std::vector<double>>& samples_by_rank) {
  // Every rank's columns by name, with their samples; the times from any
  // rank that sampled (all sample at the same times).
  std::map<std::string, std::pair<TraceColumn, std::vector<double>>> found;
  std::vector<double> times;
  for (std::size_t r = 0; r < columns_by_rank.size(); ++r) {
    std::istringstream lines(columns_by_rank[r]);
    std::vector<TraceColumn> columns;
    for (std::string line; std::getline(lines, line);) {
      std::istringstream fields(line);
      TraceColumn c;
      std::string cell, step;
      std::getline(fields, c.variable, '\t');
      std::getline(fields, cell, '\t');
      std::getline(fields, c.unit, '\t');
      std::getline(fields, step, '\t');
      c.cell = std::stoi(cell);
      c.step = step == "1";
      for (int k = 0; k < 3; ++k)  // (rank 0's, which steps the mechanics)
        if (c.variable == kStrainNames[k]) c.strain = k;
      columns.push_back(c);
    }
    if (columns.empty()) continue;
    const std::vector<double>& packed = samples_by_rank[r];
    const std::size_t count = packed.size() / (columns.size() + 1);
    if (times.empty()) times.assign(packed.begin(), packed.begin() + static_cast<long>(count));
    for (std::size_t k = 0; k < columns.size(); ++k) {
      const auto from = packed.begin() + static_cast<long>((k + 1) * count);
      found.emplace(columns[k].name(), std::make_pair(columns[k], std::vector<double>(from, from + static_cast<long>(count))));
    }
  }
  // One process's order: the strain, dt_ms, then each block's cells'
  // variables, each once.
  columns_.clear();
  samples_.clear();
  auto take = [&](const std::string& name) {
    auto it = found.find(name);
    if (it == found.end()) return;
    columns_.push_back(it->second.first);
    samples_.push_back(std::move(it->second.second));
    found.erase(it);
  };
  for (const char* strain : kStrainNames) take(strain);
  take(kStepVariable);
  for (const auto& block : spec.blocks)
    for (int cell : block.cells)
      for (const auto& var : block.variables) take(var + "_" + std::to_string(cell));
  times_ = std::move(times);
  next_sample_index_ = static_cast<long long>(times_.size());
}

void TraceRecorder::write_csv(const std::filesystem::path& file) {
  open_csv(file);
  for (std::size_t s = 0; s < times_.size(); ++s) {
    csv_.cell(times_[s]);
    for (const auto& column : samples_) csv_.cell(column[s]);
    csv_.end_row();
  }
  csv_.flush();
}

std::vector<std::string> TraceRecorder::column_names() const {
  std::vector<std::string> names;
  for (const auto& c : columns_) names.push_back(c.name());
  return names;
}

json TraceRecorder::units() const {
  json units = json::object();
  for (const auto& c : columns_)
    if (!units.contains(c.variable)) units[c.variable] = c.unit;
  return units;
}

const std::vector<double>& TraceRecorder::trace(const std::string& variable, int cell) const {
  for (std::size_t i = 0; i < columns_.size(); ++i)
    if (columns_[i].variable == variable && columns_[i].cell == cell) return samples_[i];
  throw std::out_of_range("no trace of '" + variable + "' for cell " + std::to_string(cell) +
                          " (add it to output.traces)");
}

}  // namespace fibrodem
