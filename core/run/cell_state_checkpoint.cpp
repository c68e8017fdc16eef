#include "run/cell_state_checkpoint.hpp"

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
    fields.put(p + "cells", pop.cells);
    fields.put(p + "y", pop.y);
    fields.put(p + "inputs", pop.inputs);
    fields.put(p + "outputs", pop.outputs);
    if (m) fields.put(p + "rest_sarcomere_length", m->rest_sarcomere_length);
  });
  fields.put_text("cells.populations", population_list(system));
  fields.put_integer("cells.count", static_cast<long long>(system.cell_count()));
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
  if (count != static_cast<long long>(system.cell_count()))
    throw CheckpointError("its tissue has " + std::to_string(count) + " cells, this scene's has " +
                          std::to_string(system.cell_count()));
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
    if (same_cells && fields.ints(p + "cells") != pop.cells) throw CheckpointError(other_cells(p));
  });
}

// Where each cell of population `p` ("ionic.myocyte.") is in a checkpoint's parts.
CellPlaces population_places(const std::vector<CheckpointFields>& parts, const std::string& p, std::size_t tissue_cells) {
  std::vector<std::vector<int>> cells_of_part;
  for (const auto& part : parts) cells_of_part.push_back(part.ints(p + "cells"));
  return CellPlaces(cells_of_part, tissue_cells);
}

}  // namespace

void check_same_cells(const CellSystem& system, const CheckpointFields& fields) {
  check_checkpoint_fits(system, fields, true);
}

void load_own_cell_states(CellSystem& system, const std::vector<CheckpointFields>& parts) {
  check_checkpoint_fits(system, parts.at(0), false);
  auto pick = [&](Population& pop, const std::string& p) {
    pop.y = population_places(parts, p, system.cell_count()).rows(parts, p + "y", pop.cells);
    if (pop.y.size() != pop.n_states() * pop.size()) throw CheckpointError(other_cells(p));
  };
  for (auto& pop : system.populations) pick(pop, prefix_of(pop, false));
  for (auto& m : system.myofilaments) pick(m.pop, prefix_of(m.pop, true));
  system.voltage_fresh = false;
  system.gather_voltage();
}

void recut_cell_states(const std::vector<CheckpointFields>& parts, const CellSystem& system, CheckpointFields& out) {
  check_checkpoint_fits(system, parts.at(0), false);
  for_each_population(system, [&](const Population& pop, const std::string& p, const Myofilament* m) {
    const CellPlaces places = population_places(parts, p, system.cell_count());
    out.put(p + "cells", pop.cells);
    for (const char* field : {"y", "inputs", "outputs"}) out.put(p + field, places.rows(parts, p + field, pop.cells));
    if (m) out.put(p + "rest_sarcomere_length", places.rows(parts, p + "rest_sarcomere_length", pop.cells));
  });
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
