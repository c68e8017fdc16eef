// A run split over the ranks of an mpirun (docs/guide/parallel.md): the tissue's
// cell graph is partitioned (every rank computes the same partition from the
// same tissue), each rank's populations and per-cell arrays hold its own
// cells and their ghosts alone (tissue/cell_numbering.hpp), the gap currents
// read the ghosts' potentials refreshed by a halo exchange, and at the
// end rank 0 gathers the beats and traces and writes every file as one
// process would. With a fixed step and explicit coupling each cell's update
// reads its own states, its stimulus and its neighbours' potentials, summed
// in the same order as in one process, so the potentials, and everything
// measured from them, have the same bits on any number of ranks. An
// implicit coupling solve (the adaptive method's) sums over the ranks
// (run/coupling_over_ranks.hpp): the same bits for the same number of
// ranks, within the solve's tolerance of one process's.
#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

#include "io/tissue_imprint.hpp"
#include "run/beat_gather.hpp"
#include "run/over_ranks.hpp"
#include "run/rank_reductions.hpp"
#include "run/run_summary.hpp"
#include "run/simulation_impl.hpp"
#include "scene/effects.hpp"
#include "tissue/cell_numbering.hpp"
#include "tissue/cell_partition.hpp"
#include "tissue/tissue_builder.hpp"
#include "util/json_reader.hpp"

namespace fibrodem {

// After the solver is chosen: a scene the split cannot take stops here (the
// command line checks the same before anything is written); then this
// rank's share of the cells.
void Simulation::Impl::split_over_ranks() {
  if (!split.ranks) return;
  const std::vector<std::string> unsupported = unsupported_over_ranks(scene, scene.solver.method);
  if (!unsupported.empty()) throw std::runtime_error(refusal_over_ranks("run", split.ranks->size(), unsupported));
  // (Cut as the tissue was built, holding part of its graph: build_tissue.
  // Each cell's part is then read from the cuts, none held; the layout's
  // counts alone, which is all a rank other than 0 without mechanics keeps.)
  std::size_t cut_edges = 0;
  if (split.cut) {
    const CoordinateCuts& cuts = split.cut->cuts;
    split.share = rank_cells(
        tissue, cuts.parts(), [&](int cell) { return part_by_cuts(cuts, tissue, cell); }, split.ranks->rank());
    split.layout = rank_layout_counts(cuts.sizes());
    cut_edges = split.cut->cut_edges;
  } else {
    const CellPartition partition = partition_cells(tissue, split.ranks->size(), scene.solver.partition);
    split.share = rank_cells(tissue, partition, split.ranks->rank());
    split.layout = rank_layout(partition);
    cut_edges = partition.cut_edges(tissue);
  }
  system.numbering = CellNumbering(tissue.cell_count(), split.share);
  const std::vector<int>& sizes = split.layout.counts;
  plan.notes.push_back(
      fmt::format("split over {} MPI ranks ({}): {} to {} cells a rank, {} of {} cell-graph "
                  "edges between ranks; rank {}: {} cells, {} ghost cells from {} ranks",
                  split.ranks->size(), scene.solver.partition == PartitionMethod::scotch ? "Scotch" : "rcb",
                  *std::min_element(sizes.begin(), sizes.end()), *std::max_element(sizes.begin(), sizes.end()),
                  cut_edges, tissue.built_cell_edges(), split.ranks->rank(), split.share.owned.size(),
                  split.share.ghosts.size(), split.share.neighbours.size()));
}

// What rank 0 of a split run without mechanics keeps the particles for:
// a file their imprint cannot give ("" if none).
std::string Simulation::Impl::particles_kept_on_rank0_for() const {
  if (scene.output.tissue_picture) return "output.tissue_picture's tissue.vtp shows the bonds";
  if (scene.output.vtk_format != "xml") return "the legacy VTK files are written from them";
  return "";
}

// A rank other than 0 neither steps the DEM nor draws the tissue: of it, it
// keeps the cells, their centres and graph. Rank 0 of a run without
// mechanics, whose particles stay where they were built, keeps their
// imprint too (io/tissue_imprint.hpp), when every file it writes can be
// made from it. Without mechanics, a builder that makes the cells alone
// (TissueBuilder::build_cells) spares every rank the whole tissue's
// particles and bonds, rank 0 imprinting them one by one as the builder
// hands them over, and a rank other than 0 cut by rcb the whole cell graph
// and every cell's centre (build_part_of_graph); otherwise a rank builds
// the whole tissue and frees it.
void Simulation::Impl::build_tissue() {
  const TissueBuilder& builder = *scene.tissue;
  // (Whether the plan builds mechanics is a property of the scene alone.)
  if (!split.ranks || plan_processes(scene, Tissue{}).has("mechanics") ||
      (split.ranks->rank() == 0 && !particles_kept_on_rank0_for().empty())) {
    tissue = builder.build(scene.seed);
  } else if (split.ranks->rank() != 0 && builder.builds_cells_alone() &&
             scene.solver.partition == PartitionMethod::rcb) {
    build_part_of_graph();
  } else if (split.ranks->rank() != 0) {
    tissue = builder.build_cells(scene.seed);
  } else if (!builder.builds_cells_alone()) {
    tissue = builder.build(scene.seed);
    tissue.release_particles(imprint_tissue(tissue));
  } else {
    tissue = builder.build_cells(scene.seed);
    TissueImprinter imprinter(tissue.bounds_um(), tissue.type);
    builder.for_each_particle(scene.seed, [&imprinter](const Particle& p) { imprinter.add(p); });
    tissue.release_particles(imprinter.finish());
  }
}

// A rank other than 0 of a run without mechanics, cut by the cells'
// centres, never holds every cell's centre nor the whole cell graph: the
// builder hands the cells and the graph's edges over one at a time
// (TissueBuilder::stream_cells), as often as the cut asks; the tissue keeps
// its own cells and ghosts (their types and centres) and the edges with one
// of its cells at an end, and reads any other cell from the stream until
// the run starts. As the whole graph goes by, where the coupling's
// regions and map hold its junctions is counted, for build_coupling's check.
void Simulation::Impl::build_part_of_graph() {
  std::shared_ptr<const CellStream> cells = scene.tissue->stream_cells(scene.seed);
  tissue = cells->cell_types();
  split.coupling_places.emplace(scene.coupling.regions, scene.coupling.field ? &*scene.coupling.field : nullptr);
  CouplingPlaces& places = *split.coupling_places;
  const bool placed = !scene.coupling.regions.empty() || scene.coupling.field;
  split.cut = cut_without_graph(
      tissue, split.ranks->size(), split.ranks->rank(), std::move(cells),
      placed ? VisitCellEdge([&places](const CellCentre& a, const CellCentre& b) { places.count(a, b); }) : nullptr);
}

// With mechanics, once the DEM, set up on every rank for the same refusals,
// has been built, a rank other than 0 frees the particles and bonds (on a
// sheet of myocytes 7 particles and 7 bonds a cell, 280 bytes of its ~330).
// Rank 0's choice goes to run.log.
void Simulation::Impl::release_particles_over_ranks() {
  if (!split.ranks) return;
  if (split.ranks->rank() != 0) {
    if (!tissue.particles_released()) tissue.release_particles();
    return;
  }
  if (plan.has("mechanics")) return;  // (the pictures show the tissue deformed)
  const std::string keeps = particles_kept_on_rank0_for();
  if (!keeps.empty()) {
    plan.notes.push_back("rank 0 keeps the tissue's particles: " + keeps + " (docs/guide/parallel.md)");
    return;
  }
  plan.notes.push_back(fmt::format(
      "rank 0 keeps the imprint of the tissue's {} particles for its pictures and VTK files ({:.1f} MB), not the "
      "particles and bonds{}",
      tissue.built_particles(), static_cast<double>(tissue.imprint()->bytes()) / 1e6,
      scene.tissue->builds_cells_alone() ? "; every rank built the cells without them" : ""));
}

// Once the run has started (its coupling built, a checkpoint's parts found
// by the partition, the stimulus's cells chosen), a rank reads the tissue's
// cell graph and its cells' centres only where cell_layout_kept says
// (run/over_ranks.hpp): it frees the rest (24 and 16 bytes a cell on a brick
// sheet) before the stepping's arrays are made, and a rank other than 0
// without mechanics every cell's place in the ranks' order (4 bytes).
void Simulation::Impl::release_cell_layout_over_ranks() {
  if (!split.ranks) return;
  const CellLayoutKept kept = cell_layout_kept(split.ranks->rank(), split.ranks->size(), plan.has("mechanics"),
                                               scene.output.reentry.on);
  if (!kept.centres) tissue.release_centres();
  // (With mechanics every rank reads every rank's cells: the DEM split, its
  // strain, or the cells' lengths gathered on rank 0.)
  if (split.ranks->rank() != 0 && !plan.has("mechanics")) split.layout.keep_counts_only();
  if (kept.graph) return;
  system.coupled_pairs = {};  // (a view of them, read by CVODE alone, which does not run split)
  tissue.keep_part_of_graph({}, tissue.built_cell_edges());
}

// The gap currents of this rank's cells read their ghosts' potentials (the
// coupler, this rank's rows with the others': build_coupling); the adaptive
// step control takes every rank's error and stop.
void Simulation::Impl::connect_ranks() {
  if (!split.ranks) return;
  split.reductions = std::make_shared<RankReductions>(*split.ranks);
  system.largest_over_ranks = [reductions = split.reductions](double mine) { return reductions->largest(mine); };
  if (!system.coupler) return;
  split.halo =
      std::make_unique<HaloExchange>(*split.ranks, numbered_from_ghost(split.share, split.share.owned.size()));
  system.refresh_ghost_voltages = [h = split.halo.get()](double* V_mV) { h->refresh(V_mV); };
}

// The biomarker tracker: of every cell in one process; split over ranks, of
// this rank's own cells only (each cell's measures read its own potentials
// only, so they have the same bits), numbered as in the tissue. Its cells
// are the first of the held ones (CellSystem::numbering): it reads the
// per-cell arrays as they are.
std::unique_ptr<BiomarkerTracker> Simulation::Impl::make_tracker() {
  std::vector<CellType> types = split.ranks ? tissue.types_of(split.share.owned) : tissue.type;
  auto made = std::make_unique<BiomarkerTracker>(std::move(types), system.stimulus.onsets(scene.duration_ms),
                                                 scene.output.biomarkers_from_ms,
                                                 [this](const BeatBiomarkers& b) { record_beat(b); });
  if (split.ranks) made->number_cells(split.share.owned);
  if (scene.output.rmp_method == "pre_upstroke")
    made->use_pre_upstroke_rmp(scene.output.rmp_window_ms, scene.output.rmp_gap_ms);
  return made;
}

// The tracker's index where a range of held cells starts or ends
// (0 <= cell_edge <= held cells): split over ranks its cells are the own
// cells, the first of the held ones, not the ghosts after them.
std::size_t Simulation::Impl::tracked_edge(std::size_t cell_edge) const {
  return std::min(cell_edge, system.numbering.own());
}

// output.traces as this rank records it: its own cells only (a cell that
// does not exist stays, for the same error on every rank), and the strain
// on rank 0 only, which steps the mechanics (run/mechanics_over_ranks.hpp).
Scene Simulation::Impl::scene_of_own_traces() const {
  Scene own = scene;
  const bool strain_elsewhere = plan.has("mechanics") && split.ranks->rank() != 0;
  for (auto& block : own.output.traces.blocks) {
    if (strain_elsewhere) std::erase_if(block.variables, is_strain_variable);
    block.cells.erase(std::remove_if(block.cells.begin(), block.cells.end(),
                                     [&](int cell) {
                                       return cell >= 0 && static_cast<std::size_t>(cell) < tissue.cell_count() &&
                                              !system.numbering.owns(cell);
                                     }),
                      block.cells.end());
  }
  return own;
}

// A model output is traced by evaluating the owner's cells at the sample,
// which would exchange potentials on that rank alone: not yet split.
// (Decided from the models of the cells' types, the same on every rank.)
void Simulation::Impl::refuse_traced_outputs() const {
  if (!split.ranks) return;
  const std::map<int, CellType> traced_type = types_of_traced_cells();
  for (const auto& block : scene.output.traces.blocks)
    for (std::size_t j = 0; j < block.variables.size(); ++j)
      for (int cell : block.cells) {
        if (!traced_type.contains(cell)) continue;  // (not in the tissue)
        const Population& pop = population_of_type(traced_type.at(cell));
        const std::string& var = block.variables[j];
        if (find_state(pop.info(), var) < 0 && find_output(pop.info(), var) >= 0)
          throw ManifestError(index_path(block.path + ".variables", j),
                              "\"" + var + "\" is an output of model " + pop.info().name +
                                  ", which a run split over MPI ranks cannot trace yet (states can be traced)");
      }
}

// V of every cell, by tissue number, on rank 0 (each rank's own cells'
// values gathered, their bytes unchanged); empty on the other ranks.
// Collective: every rank calls it at the same time. (At snapshot times,
// not every step.)
std::vector<double> Simulation::Impl::voltage_of_every_cell() {
  std::vector<double> gathered, V;
  gather_by_cell(*split.ranks, split.layout, system.V_mV.data(), gathered, V);
  return V;
}

// Rank 0 takes every rank's beats (in one process's order: by beat, then
// cell) and traces, and writes biomarkers.csv and traces.csv.
void Simulation::Impl::gather_from_ranks() {
  if (!split.ranks) return;
  if (mechanics) mechanics->solver().count_on_rank0();  // (split: for its report)
  gather_beats_on_rank0(*split.ranks, beats);
  const std::vector<std::string> columns_by_rank = split.ranks->gather_text(traces.packed_columns());
  const std::vector<std::vector<double>> samples_by_rank = split.ranks->gather(traces.packed_samples());
  if (split.ranks->rank() != 0) return;
  // (A beat of a cell is unique: the order is the stable sort's, without its buffer of every beat.)
  std::sort(beats.begin(), beats.end(), in_beat_order);
  for (const auto& b : beats) write_biomarker_row(b);
  traces.merge(scene.output.traces, columns_by_rank, samples_by_rank);
  if (!out.empty()) traces.write_csv(out / "traces.csv");
}

// A rank other than 0 whose run failed (a blow-up on its cells, a model
// fault) writes summary.json itself, "failed" with its error and its rank,
// before the command line ends the job: rank 0, which writes the folder,
// waits for it at the next exchange and never learns of the failure. Only
// what every rank knows is in it (the scene, the time reached); the
// measurements, which rank 0 gathers at the end, are not.
void Simulation::Impl::leave_failed_summary() {
  if (!writes_folder) return;
  try {
    write_summary(run_folder, summary());
  } catch (const std::exception& e) {
    log->error("summary.json of the failed run cannot be written: {}", e.what());
  }
}

}  // namespace fibrodem
