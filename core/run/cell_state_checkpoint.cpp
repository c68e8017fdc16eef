#include "run/cell_state_checkpoint.hpp"

#include <algorithm>

#include "run/checkpoint_recut.hpp"

namespace fibrodem {

namespace {

// "ionic.myocyte." or "myofilament.myocyte.": one prefix per population.
std::string prefix_of(const Population& pop, bool myofilament) {
  return std::string(myofilament ? "myofilament." : "ionic.") + cell_type_name(pop.type) + ".";
}

std::string state_names(const Population& pop) {
  std::string names;
  for (const auto& s : pop.info().states) names += (names.empty() ? "" : ",") + s.name;
  return names;
}

template <class F>
void for_each_population(const CellSystem& system, F&& f) {
  for (const auto& pop : system.populations) f(pop, prefix_of(pop, false), nullptr);
  for (const auto& m : system.myofilaments) f(m.pop, prefix_of(m.pop, true), &m);
}

// A population's cells by tissue number (a checkpoint's numbers, whatever
// the ranks): its own held numbers in one process.
std::vector<int> tissue_cells_of(const CellSystem& system, const Population& pop) {
  if (system.numbering.whole()) return pop.cells;
  std::vector<int> cells(pop.cells.size());
  for (std::size_t k = 0; k < cells.size(); ++k)
    cells[k] = system.numbering.tissue_cell(static_cast<std::size_t>(pop.cells[k]));
  return cells;
}

// The populations' prefixes, in order: which populations a system has.
std::string population_list(const CellSystem& system) {
  std::string list;
  for_each_population(system, [&](const Population&, const std::string& p, const Myofilament*) {
    list += (list.empty() ? "" : " ") + p;
  });
  return list;
}

}  // namespace

void save_cell_states(const CellSystem& system, CheckpointFields& fields) {
  for_each_population(system, [&](const Population& pop, const std::string& p, const Myofilament* m) {
    fields.put_text(p + "model", pop.info().name);
    fields.put_text(p + "version", pop.info().version);
    fields.put_text(p + "states", state_names(pop));
    fields.put(p + "cells", tissue_cells_of(system, pop));
    fields.put(p + "y", pop.y);
    fields.put(p + "inputs", pop.inputs);
    fields.put(p + "outputs", pop.outputs);
    if (m) fields.put(p + "rest_sarcomere_length", m->rest_sarcomere_length);
  });
  fields.put_text("cells.populations", population_list(system));
  fields.put_integer("cells.count", static_cast<long long>(system.numbering.tissue_cells()));
  fields.put("cells.last_step_ms", system.last_step_ms);
}

namespace {

std::string other_cells(const std::string& p) {
  return "its " + p + "cells are not this scene's (another tissue: builder, size, seed?)";
}

// check_same_cells; with same_cells false, all but each population's cells
// being the checkpoint's (a rank's share: load_own_cell_states checks them).
void check_checkpoint_fits(const CellSystem& system, const CheckpointFields& fields, bool same_cells) {
  const long long count = fields.integer("cells.count");
  const std::size_t tissue_cells = system.numbering.tissue_cells();
  if (count != static_cast<long long>(tissue_cells))
    throw CheckpointError("its tissue has " + std::to_string(count) + " cells, this scene's has " +
                          std::to_string(tissue_cells));
  const std::string populations = population_list(system);
  if (fields.text("cells.populations") != populations)
    throw CheckpointError("its cell populations are '" + fields.text("cells.populations") + "', this scene's are '" +
                          populations + "'");
  for_each_population(system, [&](const Population& pop, const std::string& p, const Myofilament*) {
    if (fields.text(p + "model") != pop.info().name)
      throw CheckpointError("its " + p + "model is " + fields.text(p + "model") + ", this scene's is " +
                            pop.info().name);
    if (fields.text(p + "states") != state_names(pop))
      throw CheckpointError("its " + p + "states are (" + fields.text(p + "states") + "), model " + pop.info().name +
                            " " + pop.info().version + " has (" + state_names(pop) + ")");
    if (same_cells && fields.ints(p + "cells") != tissue_cells_of(system, pop)) throw CheckpointError(other_cells(p));
  });
}

}  // namespace

void check_same_cells(const CellSystem& system, const CheckpointFields& fields) {
  check_checkpoint_fits(system, fields, true);
}

// One population's: its prefix ("ionic.myocyte."), fields and pick of its cells.
struct CellStatesRecut::Picked {
  std::string prefix;
  std::vector<std::string> fields;
  CellPick pick;
};

CellStatesRecut::CellStatesRecut(const CellSystem& system, const CheckpointFields& checkpoint, bool states_only) {
  check_checkpoint_fits(system, checkpoint, false);
  for_each_population(system, [&](const Population& pop, const std::string& p, const Myofilament* m) {
    std::vector<std::string> fields = {p + "y"};
    if (!states_only) {
      fields.insert(fields.end(), {p + "inputs", p + "outputs"});
      if (m) fields.push_back(p + "rest_sarcomere_length");
    }
    populations_.push_back(
        {p, std::move(fields), CellPick(tissue_cells_of(system, pop), system.numbering.tissue_cells())});
  });
}

CellStatesRecut::~CellStatesRecut() = default;

void CellStatesRecut::take(const CheckpointFields& part, int r) {
  for (Picked& pop : populations_) pop.pick.take(part, r, part.ints(pop.prefix + "cells"), pop.fields);
}

bool CellStatesRecut::complete() const {
  return std::all_of(populations_.begin(), populations_.end(), [](const Picked& pop) { return pop.pick.complete(); });
}

void CellStatesRecut::put_into(CheckpointFields& out) const {
  for (const Picked& pop : populations_) {
    out.put(pop.prefix + "cells", pop.pick.cells());
    pop.pick.put_into(out);
  }
}

void CellStatesRecut::load_states(CellSystem& system) {
  std::size_t k = 0;
  auto load = [&](Population& pop) {
    Picked& picked = populations_.at(k++);
    pop.y = picked.pick.release_rows(picked.prefix + "y");
    if (pop.y.size() != pop.n_states() * pop.size()) throw CheckpointError(other_cells(picked.prefix));
  };
  for (auto& pop : system.populations) load(pop);
  for (auto& m : system.myofilaments) load(m.pop);
  system.voltage_fresh = false;
  system.gather_voltage();
}

void load_cell_states(CellSystem& system, const CheckpointFields& fields, bool everything) {
  check_same_cells(system, fields);
  auto load = [&](Population& pop, const std::string& p, Myofilament* m) {
    fields.read_into(p + "y", pop.y);
    if (!everything) return;
    fields.read_into(p + "inputs", pop.inputs);
    fields.read_into(p + "outputs", pop.outputs);
    if (m) fields.read_into(p + "rest_sarcomere_length", m->rest_sarcomere_length);
  };
  for (auto& pop : system.populations) load(pop, prefix_of(pop, false), nullptr);
  for (auto& m : system.myofilaments) load(m.pop, prefix_of(m.pop, true), &m);
  if (everything) system.last_step_ms = fields.number("cells.last_step_ms");
  system.voltage_fresh = false;
  system.gather_voltage();
}

}  // namespace fibrodem
