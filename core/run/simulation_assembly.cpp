// The scene assembled (Simulation's set-up, in the order simulation.cpp
// calls it): the solver and threads, the cell populations and their settling,
// myofilaments and calcium feedback, gap-junction coupling, the mechanics,
// lookup tables, an initial state, and the checks of stability and resources.
#include <omp.h>
#include <spdlog/sinks/null_sink.h>
#include <spdlog/sinks/stdout_color_sinks.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "coupling/gap_junction.hpp"
#include "integrate/method_choice.hpp"
#include "run/cell_state_checkpoint.hpp"
#include "run/checkpoint_recut.hpp"
#include "run/coupling_over_ranks.hpp"
#include "run/population_setup.hpp"
#include "run/settle.hpp"
#include "run/simulation_impl.hpp"

namespace fibrodem {
namespace {

// solver.threads "auto" shares the work between cores from this many cells on
// (two blocks of cells: 2 threads run a colman strand 1.47x faster at 512 cells;
// docs/topics/performance.md#how).
constexpr std::size_t kCellsForThreads = 2 * kCellsPerBlock;

}  // namespace

void Simulation::Impl::make_logger() {
  std::vector<spdlog::sink_ptr> sinks;
  if (options.console_log) sinks.push_back(std::make_shared<spdlog::sinks::stderr_color_sink_mt>());
  if (sinks.empty()) sinks.push_back(std::make_shared<spdlog::sinks::null_sink_mt>());
  log = std::make_shared<spdlog::logger>("fibrodem", sinks.begin(), sinks.end());
  log->set_pattern("[%H:%M:%S.%e] [%l] %v");
  log->flush_on(spdlog::level::warn);  // a warning reaches run.log at once (and once a second: on_step)
  log->set_level(spdlog::level::info);
}

// solver.method "auto": the method and its settings for the scene's size
// and solver.accuracy; everything after sees the method chosen.
void Simulation::Impl::choose_solver() {
  if (scene.solver.method != "auto") return;
  const MethodChoice choice = choose_method(scene.solver, tissue.cell_count());
  scene.solver = choice.solver;
  solver_choice = choice.why;
  plan.notes.push_back("solver.method auto: " + choice.why);
}

// solver.threads: as asked, or ("auto") every core once the tissue has
// enough blocks of cells to share; a smaller scene runs on one thread, where
// waking a second costs more than it brings.
void Simulation::Impl::use_threads() {
  const int cores = std::max(1, omp_get_num_procs());
  int threads = scene.solver.threads;
  std::string why = "solver.threads = " + std::to_string(threads);
  if (threads == 0) {
    threads = cores;
    why = "solver.threads = 0: every core";
  } else if (threads < 0) {
    // (Split over ranks: this rank's cells.)
    const std::size_t cells = split.ranks ? split.share.owned.size() : tissue.cell_count();
    const bool large = cells >= kCellsForThreads;
    threads = large ? cores : 1;
    why = fmt::format("solver.threads auto: {} cells {} {} ({} cores)", cells, large ? ">=" : "<",
                      kCellsForThreads, cores);
  }
  // auto on several cores: measured step by step against one thread, in
  // case other jobs hold the cores (model/thread_governor.hpp).
  if (scene.solver.threads < 0 && threads > 1) {
    system.thread_governor().adapt(threads);
    why += "; one thread instead while it measures faster";
  } else {
    system.thread_governor().use(threads);
  }
  plan.notes.push_back(fmt::format("threads: {} ({})", threads, why));
}

void Simulation::Impl::build_populations() {
  std::map<CellType, int> population_of;
  for (CellType type : {CellType::myocyte, CellType::fibroblast}) {
    const std::size_t count = tissue.count(type);
    const auto spec = scene.cells.find(type);
    if (count == 0) {
      if (spec != scene.cells.end())
        plan.notes.push_back(std::string("cells.") + cell_type_name(type) +
                             " not loaded: the tissue has no " + cell_type_name(type));
      continue;
    }
    if (spec == scene.cells.end())
      throw ManifestError(std::string("cells.") + cell_type_name(type),
                          "the tissue has " + std::to_string(count) + " " + cell_type_name(type) +
                              "(s) but the manifest gives them no cell model");
    population_of[type] = static_cast<int>(system.populations.size());
    system.populations.push_back(make_population(type, spec->second.ionic, ModelKind::ionic, *registry, &warnings));
    settle(system.populations.back(), spec->second);
  }
  // The held cells (CellSystem::numbering: in one process the tissue's;
  // split over ranks this rank's own, then its ghosts). A ghost is in no
  // population here (its type's population is named, for its capacitance;
  // every rank has one population per cell type of the tissue, possibly
  // empty).
  if (!split.ranks) system.numbering = CellNumbering(tissue.cell_count());
  const std::size_t held = system.numbering.held(), own = system.numbering.own();
  system.where.resize(held);
  for (std::size_t c = 0; c < held; ++c) {
    const int p = population_of.at(tissue.type_of(system.numbering.tissue_cell(c)));
    if (c >= own) {
      system.where[c] = {p, std::numeric_limits<std::uint32_t>::max()};
      continue;
    }
    system.where[c] = {p, static_cast<std::uint32_t>(system.populations[p].cells.size())};
    system.populations[p].cells.push_back(static_cast<int>(c));
  }
  // (a and b for the whole population only for an integrator that reads them)
  const bool derivatives = reads_population_derivatives(scene.solver.method);
  for (auto& pop : system.populations) pop.reset(derivatives);
  system.V_mV.assign(held, 0.0);
  system.i_ext_pA.assign(held, 0.0);
}

// The ionic population of a cell type of the tissue (every rank has one).
const Population& Simulation::Impl::population_of_type(CellType type) const {
  for (const Population& pop : system.populations)
    if (pop.type == type) return pop;
  throw std::logic_error(std::string("no population of ") + cell_type_name(type) + " cells");
}

// cells.TYPE.settle: the type's model alone before t = 0 (run/settle.hpp);
// every cell of the type then starts from the settled states.
void Simulation::Impl::settle(Population& pop, const CellTypeSpec& spec) {
  if (spec.settle.ms <= 0) return;
  try {
    SettleResult settled = settle_cell(pop, spec.settle);
    pop.initial_state = std::move(settled.states);
    plan.notes.push_back(settled.note);
  } catch (const std::runtime_error& e) {
    throw ManifestError(join_path(spec.path, "settle"), e.what());
  }
}

// The type of each cell output.traces names (of those in the tissue), read
// at once: a rank holding part of the cells reads those it does not hold
// from the builder, in one pass (Tissue::types_of).
std::map<int, CellType> Simulation::Impl::types_of_traced_cells() const {
  std::vector<int> cells;
  for (const auto& block : scene.output.traces.blocks)
    for (int cell : block.cells)
      if (cell >= 0 && static_cast<std::size_t>(cell) < tissue.cell_count()) cells.push_back(cell);
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  const std::vector<CellType> types = tissue.types_of(cells);
  std::map<int, CellType> type_of;
  for (std::size_t k = 0; k < cells.size(); ++k) type_of.emplace(cells[k], types[k]);
  return type_of;
}

// Without a list of effects, a traced variable of a cell type's myofilament
// model calls for contraction.
void Simulation::Impl::derive_contraction_from_traces() {
  if (scene.effects_listed || plan.has("contraction")) return;
  const std::map<int, CellType> traced_type = types_of_traced_cells();
  for (const auto& block : scene.output.traces.blocks) {
    for (const auto& var : block.variables)
      for (const auto& cell : block.cells) {
        if (!traced_type.contains(cell)) continue;  // (not in the tissue)
        const Population& host = population_of_type(traced_type.at(cell));
        const auto& spec = scene.cells.at(host.type);
        if (!spec.myofilament || find_state(host.info(), var) >= 0 || find_output(host.info(), var) >= 0) continue;
        const ModelInfo& info = registry->load(spec.myofilament->model)->info();
        if (find_state(info, var) >= 0 || find_output(info, var) >= 0) {
          plan.built.push_back({"contraction", "output.traces records " + var + " of the myofilament model " + info.name});
          plan.notes.erase(std::remove_if(plan.notes.begin(), plan.notes.end(),
                                          [](const std::string& n) { return n.rfind("myofilament model", 0) == 0 ||
                                                                            n.find("calcium_feedback") != std::string::npos; }),
                           plan.notes.end());
          return;
        }
      }
  }
}

// One myofilament population per cell type that names one, over the same cells.
void Simulation::Impl::build_myofilaments() {
  if (!plan.has("contraction")) return;
  for (std::size_t p = 0; p < system.populations.size(); ++p) {
    Population& host = system.populations[p];
    const CellTypeSpec& spec = scene.cells.at(host.type);
    if (!spec.myofilament) continue;
    Myofilament m;
    m.pop = make_population(host.type, *spec.myofilament, ModelKind::myofilament, *registry, &warnings);
    m.pop.cells = host.cells;
    m.pop.reset(reads_population_derivatives(scene.solver.method));
    m.host = static_cast<int>(p);
    m.host_ca_state = find_state(host.info(), "Ca_i");
    if (m.host_ca_state < 0)
      throw ManifestError(join_path(spec.path, "myofilament"),
                          "the myofilament model needs the host's cytosolic Ca, but model " + host.info().name +
                              " has no state Ca_i");
    m.sarcomere_output = find_output(m.pop.info(), "sarcomere_length");
    if (spec.calcium_feedback) connect_calcium_feedback(host, m, spec);
    system.myofilaments.push_back(std::move(m));
  }
  if (plan.has("mechano_electric_feedback")) connect_stretch_activated_current();
}

// The stretch-activated current on the populations of the cell types that
// mechano_electric_feedback.cell_types lists (by default every type with a
// myofilament model); with the sarcomere's stretch, a listed type needs a
// myofilament model (the tissue's stretch: build_mechanics).
void Simulation::Impl::connect_stretch_activated_current() {
  const MechanoElectricSpec& mef = scene.mechano_electric;
  system.sac.on = true;
  system.sac.G_nS = mef.G_SAC_nS;
  system.sac.E_mV = mef.E_SAC_mV;
  system.sac.lambda_max = mef.lambda_max;
  system.sac.host_on.assign(system.populations.size(), 0);
  auto has_myofilament = [&](CellType type) {
    const auto spec = scene.cells.find(type);
    return spec != scene.cells.end() && spec->second.myofilament.has_value();
  };
  for (std::size_t p = 0; p < system.populations.size(); ++p) {
    const CellType type = system.populations[p].type;
    system.sac.host_on[p] = mef.cell_types_listed ? mef.listed(type) : has_myofilament(type);
  }
  if (!mef.cell_types_listed || mef.stretch == StretchSource::tissue) return;
  for (std::size_t t = 0; t < kCellTypeNames.size(); ++t) {
    const auto type = static_cast<CellType>(t);
    if (!mef.listed(type)) continue;
    if (!has_myofilament(type))
      throw ManifestError("mechano_electric_feedback.cell_types",
                          std::string("the stretch-activated current of ") + kCellTypeNames[t] +
                              " cells needs their stretch, but cells." + kCellTypeNames[t] +
                              " has no myofilament model");
  }
}

// Troponin buffering of the myofilament model enters the host's Ca balance
// as an input flux; the host's own troponin buffer is switched off so that
// troponin is not counted twice.
void Simulation::Impl::connect_calcium_feedback(Population& host, Myofilament& m, const CellTypeSpec& spec) {
  const std::string path = join_path(spec.path, "calcium_feedback");
  for (std::size_t k = 0; k < host.info().inputs.size(); ++k)
    if (host.info().inputs[k].name == kTroponinFluxInput) m.host_trpn_input = static_cast<int>(k);
  if (m.host_trpn_input < 0)
    throw ManifestError(path, "model " + host.info().name + " takes no troponin flux (input " +
                                  kTroponinFluxInput + "), so calcium feedback cannot reach it");
  m.trpn_flux_output = find_output(m.pop.info(), "dTRPN_Ca_dt");
  if (m.trpn_flux_output < 0)
    throw ManifestError(path, "myofilament model " + m.pop.info().name + " offers no output dTRPN_Ca_dt");
  const int own_buffer = find_parameter(host.info(), "troponin_buffer_scale");
  if (own_buffer >= 0) {
    host.params[own_buffer] = 0.0;
    plan.notes.push_back("calcium feedback: " + host.info().name + "'s own troponin buffer switched off "
                         "(troponin_buffer_scale = 0); troponin is " + m.pop.info().name + "'s");
  }
}

// A plugin earlier on the search path (plugin_path, FIBRODEM_PLUGIN_PATH)
// hides any of the same name after it, such as a bundled one.
void Simulation::Impl::warn_of_shadowed_plugins() {
  for (const auto& record : registry->loaded())
    for (const auto& hidden : record.shadowed)
      warnings.push_back("plugin " + record.name + " loaded from " + record.file.string() + " hides " +
                         hidden.string() + ", of the same name later on the search path");
}

void Simulation::Impl::build_coupling() {
  if (!plan.has("coupling")) return;
  std::vector<double> capacitance(system.cell_count());  // by held cell
  for (std::size_t c = 0; c < capacitance.size(); ++c)
    capacitance[c] = system.populations[system.where[c].first].capacitance_pF;
  const CouplingField* field = scene.coupling.field ? &*scene.coupling.field : nullptr;
  // Split over ranks, this rank's rows only (run/coupling_over_ranks.hpp);
  // a rank holding part of the graph checks the regions and map as the whole
  // graph went by (build_part_of_graph).
  if (split.coupling_places) split.coupling_places->check(tissue);
  if (split.ranks)
    system.coupler = std::make_unique<CouplingOverRanks>(tissue, scene.coupling.conductances(), capacitance,
                                                         scene.coupling.regions, field, *split.ranks, split.share,
                                                         system.numbering);
  else
    system.coupler = std::make_unique<GapJunctionCoupler>(tissue, scene.coupling.conductances(), capacitance,
                                                          scene.coupling.regions, field);
  system.coupled_pairs = tissue.cell_edges;
  // (CVODE takes the coupling into its implicit solve; the adaptive method
  // takes each cell's own potential in it exponentially.)
  system.implicit_coupling =
      (scene.coupling.scheme == "implicit" && scene.solver.fixed_step()) || scene.solver.method == "adaptive";
  if (scene.coupling.dt_ms > 0 && scene.solver.method == "adaptive")
    throw ManifestError("coupling.dt_ms", "applies to the fixed-step methods only (solver.method \"adaptive\" "
                                          "takes the coupling at every step)");
  if (scene.coupling.dt_ms > 0 && scene.solver.fixed_step()) {
    const double ratio = scene.coupling.dt_ms / scene.solver.dt_ms;
    if (ratio < 1 - 1e-9 || std::abs(ratio - std::round(ratio)) > 1e-6 * ratio)
      throw ManifestError("coupling.dt_ms", "expected a multiple of solver.dt_ms (" +
                                                format_number(scene.solver.dt_ms) + " ms), got " +
                                                format_number(scene.coupling.dt_ms));
    system.coupling_every = static_cast<int>(std::lround(ratio));
  }
}
// DEM tissue mechanics: cells' lengths from their myofilaments drive it;
// back to the cells flows their fibre stretch if the stretch-activated
// current reads it. Split over ranks, each rank steps its own cells' bodies
// (docs/guide/parallel.md, "The DEM over ranks") and takes its own cells'
// strain for output.reentry's fibre-stretch frames, unless it steps light
// bodies in substeps (multirate): rank 0 alone then keeps it (built on
// every rank: a spec it refuses stops every rank alike).
void Simulation::Impl::build_mechanics() {
  if (!plan.has("mechanics")) return;
  const bool tissue_stretch =
      plan.has("mechano_electric_feedback") && scene.mechano_electric.stretch == StretchSource::tissue;
  strain_fields = make_strain_fields(tissue, scene.output, plan.notes);
  const bool dem_split = split.ranks && !scene.mechanics.multirate;
  // (Split, a cell's fibre stretch reads its own and its neighbours' bodies,
  // which its rank steps or holds as ghosts.)
  if (tissue_stretch && split.ranks && !dem_split)
    throw ManifestError("mechano_electric_feedback.stretch",
                        "\"tissue\" over ranks needs the DEM split over them, which mechanics.multirate keeps on "
                        "rank 0: run it in one process, or use \"sarcomere\" over ranks");
  check_dem_memory(tissue, available_memory_bytes());  // before the DEM allocates it
  mechanics = std::make_unique<MechanicsCoupling>(tissue, scene.mechanics);
  if (tissue_stretch) {
    mechanics->track_fibre_stretch(tissue);
    system.sac.tissue_stretch = &mechanics->fibre_stretch();
  }
  if (!split.ranks) return;
  if (dem_split) {
    mechanics->split_over_ranks(*split.ranks, split.layout);
    plan.notes.push_back("mechanics split over the ranks: each steps its own cells' bodies");
    // (The snapshots' strain is rank 0's, from every body gathered then.)
    if (strain_fields && scene.output.reentry.on) strain_fields->split_over(*split.ranks, split.layout);
    else if (split.ranks->rank() != 0) strain_fields.reset();
    return;
  }
  plan.notes.push_back("mechanics on rank 0 alone: mechanics.multirate is not split over ranks");
  mechanics_over_ranks =
      std::make_unique<MechanicsOverRanks>(*split.ranks, split.layout);
  if (split.ranks->rank() != 0) mechanics.reset(), strain_fields.reset();
}

// solver.lookup_tables: a table of the voltage_only gates' rates per ionic
// population whose model marks any (after every parameter change above).
void Simulation::Impl::build_lookup_tables() {
  if (!scene.solver.use_lookup_tables()) return;
  for (auto& pop : system.populations) {
    std::string note = std::string("lookup tables") +
                       (scene.solver.lookup_tables ? "" : " (the default for fixed-step methods)") + ": " +
                       cell_type_name(pop.type) + " model " + pop.info().name;
    if (pop.use_lookup_table()) {
      std::string names;
      for (int k : pop.table->gates()) names += (names.empty() ? "" : " ") + pop.info().states[k].name;
      note += ": " + std::to_string(pop.table->gates().size()) + " voltage-only gates (" + names + ") from V = " +
              fmt::format("{:g}", pop.table->v_min()) + " to " + fmt::format("{:g}", pop.table->v_max()) +
              " mV every " + fmt::format("{:g}", pop.table->step()) + " mV, linear interpolation";
    } else {
      note += ": no voltage-only gates, evaluated exactly";
    }
    plan.notes.push_back(note);
  }
}

// initial_state: the cells start from another run's checkpoint (the same
// tissue and models, or a CheckpointError naming what differs).
void Simulation::Impl::start_from_initial_state() {
  if (scene.initial_state.from.empty()) return;
  const std::string path = "initial_state.from";
  try {
    const FoundCheckpoint found = find_checkpoint(scene.initial_state.from, scene.initial_state.time_ms);
    try {
      // Split over ranks, or from a split run's checkpoint (every rank's part
      // beside it), the cells' states are taken cell by cell from its parts.
      if (split.ranks || ranks_of_checkpoint(found.fields) > 1) {
        CellStatesRecut states(system, found.fields, true);
        take_checkpoint_parts(
            found.file, found.fields, checkpoint_parts_of_own_cells(found.fields),
            [&states] { return states.complete(); },
            [&states](const CheckpointFields& part, int r) { states.take(part, r); });
        states.load_states(system);
      } else
        load_cell_states(system, found.fields, false);
    } catch (const CheckpointError& e) {
      throw CheckpointError("checkpoint " + found.file.string() + " does not fit this scene: " + e.what());
    }
    plan.notes.push_back(fmt::format("initial_state: the cells' states of {} (t = {:g} ms there)",
                                     found.file.string(), found.fields.number("run.time_ms")));
  } catch (const CheckpointError& e) {
    throw ManifestError(path, e.what());
  }
}

void Simulation::Impl::check_explicit_stability() {
  if (!scene.solver.fixed_step()) return;
  stability = estimate_explicit_stability(system, scene.solver.method == "euler",
                                          system.coupler && !system.implicit_coupling);
  const double dt = scene.solver.dt_ms;
  if (dt > stability.coupling_limit_ms)
    warnings.push_back(fmt::format("solver.dt_ms = {} ms exceeds the stability limit of explicit coupling, "
                                   "{:.4g} ms (2/lambda, Gershgorin bound): expect a blow-up; use dt <= {:.3g} ms "
                                   "or coupling.scheme \"implicit\"",
                                   dt, stability.coupling_limit_ms, 0.5 * stability.limit_ms()));
  if (dt > stability.gate_limit_ms)
    warnings.push_back(fmt::format("solver.dt_ms = {} ms exceeds the forward-Euler stability limit of the fastest "
                                   "gate, {:.4g} ms ({}): expect a blow-up; use dt <= {:.3g} ms or solver.method "
                                   "\"rush_larsen\"",
                                   dt, stability.gate_limit_ms, stability.fastest_gate, 0.5 * stability.limit_ms()));
}

// Before anything large is allocated (integrator buffers, traces, CVODE's
// matrices): a scene that cannot fit is refused with the estimate.
void Simulation::Impl::guard_resources() {
  resources = estimate_resources(scene, tissue, system, mechanics != nullptr, split.ranks ? split.ranks->rank() : 0,
                                 split.ranks ? split.ranks->size() : 1);
  check_resources(resources, available_memory_bytes(),
                  scene.output.dir.empty() ? std::numeric_limits<double>::infinity()
                                           : available_disk_bytes(scene.output.dir));
  plan.notes.push_back("resources: " + resources.describe());
}

}  // namespace fibrodem
