#include "run/resource_estimate.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <utility>

#include <fmt/format.h>

#include "integrate/adaptive.hpp"
#include "integrate/integrator.hpp"
#include "io/tissue_imprint.hpp"
#include "measure/biomarkers.hpp"
#include "run/over_ranks.hpp"
#include "scene/effects.hpp"
#include "tissue/coordinate_bisection.hpp"
#include "tissue/tissue_builder.hpp"
#include "util/manifest_error.hpp"

namespace fibrodem {

namespace {

std::string size_text(double bytes) {
  if (bytes >= 1e9) return fmt::format("{:.3g} GB", bytes / 1e9);
  if (bytes >= 1e6) return fmt::format("{:.3g} MB", bytes / 1e6);
  return fmt::format("{:.3g} kB", bytes / 1e3);
}

double sum(const std::vector<ResourceEstimate::Part>& parts) {
  double total = 0;
  for (const auto& p : parts) total += p.bytes;
  return total;
}

const ResourceEstimate::Part& largest(const std::vector<ResourceEstimate::Part>& parts) {
  return *std::max_element(parts.begin(), parts.end(),
                           [](const auto& a, const auto& b) { return a.bytes < b.bytes; });
}

// A tissue picture (tissue.png, a snapshot's PNG, the activation map): an
// RGB24 surface 1500 pixels high (PictureOptions::height_px) as wide as the
// tissue's aspect asks, with margins and the colour bar, and a quarter more
// for the PNG encoder's rows and output (sheet 1 cm: 10.4 MB surface, 2.6 MB
// encoder).
constexpr double kPictureHeightPx = 1560;
double picture_width_px(const Tissue& tissue) {
  const auto box = tissue.bounds_um();
  const double aspect = box[3] > box[2] ? std::max(box[1] - box[0], 1.0) / (box[3] - box[2]) : 1.0;
  return std::min(32767.0, 1500 * aspect + 150);
}
double picture_bytes(const Tissue& tissue) { return 1.25 * 4 * picture_width_px(tissue) * kPictureHeightPx; }

// A snapshot's PNG: ~8 bytes a particle on small tissues (170 kB for 22k
// particles; Fig. 3's 16,653: 44 kB), but never more than a byte a pixel (a
// palette's index) of the picture, whose size does not grow with the tissue
// (a 5 x 5 cm sheet's frame: 12-19 kB for 5.9 M particles).
double png_frame_bytes(const Tissue& tissue) {
  return std::min(8.0 * static_cast<double>(tissue.built_particles()), picture_width_px(tissue) * kPictureHeightPx);
}

// A snapshot's VTK file: legacy text ~120 bytes a particle; XML PolyData
// (io/vtk_xml_writer.hpp) at most its raw binary arrays, 33 bytes a particle
// (points 12, radius 4, cell 4, type 1, V 4, vertex connectivity and offsets
// 8) before zlib, which leaves 6-8 (Fig. 3: 7.5; a 5 x 5 cm sheet: 6).
// With mechanics, the cells' five strain fields add per particle 5 numbers
// of ~16 characters as text, or 5 Float32 before zlib.
double vtk_frame_bytes(const std::string& vtk_format, double particles, bool mechanics) {
  const bool xml = vtk_format == "xml";
  return ((xml ? 33.0 : 120.0) + (mechanics ? (xml ? 20.0 : 80.0) : 0.0)) * particles;
}

// Sample count of a series every `every_ms` from `from_ms` to the end.
double samples(double duration_ms, double from_ms, double every_ms) {
  return every_ms > 0 && duration_ms >= from_ms ? std::floor((duration_ms - from_ms) / every_ms) + 1 : 0;
}

// The program's own pages beside its heap: code, libraries, plugins, thread
// stacks, the allocator's arenas (peak RSS less peak heap: 30 MB on the
// Fig. 3 scene, 36 MB on sheet 1 cm).
constexpr double kProgramBytes = 30e6;

}  // namespace

double ResourceEstimate::memory_bytes() const { return sum(memory); }
double ResourceEstimate::output_bytes() const { return sum(output); }

std::string ResourceEstimate::describe() const {
  std::string s = "memory ~" + size_text(memory_bytes()) + " (";
  for (std::size_t i = 0; i < memory.size(); ++i)
    s += (i ? "; " : "") + memory[i].what + " " + size_text(memory[i].bytes);
  s += ")";
  if (output.empty()) return s;  // nothing written (validate, library use)
  s += ", output ~" + size_text(output_bytes()) + " (";
  for (std::size_t i = 0; i < output.size(); ++i)
    s += (i ? "; " : "") + output[i].what + " " + size_text(output[i].bytes);
  return s + ")";
}


// The terms below are measured, each on what it counts, with heaptrack (peak
// heap by allocation site) and /usr/bin/time -f %M (peak RSS) on:
//   sheet 1 cm:   fibrotic_sheet 10 x 10 mm, 10 % patchy fibroblasts (33,496
//                 cells, 214,372 particles, 99,483 edges, no bonds), colman +
//                 maleckar_active2, solver auto (adaptive), 30 ms, maps,
//                 snapshots every 5 ms, report;
//   sheet 2.5 cm: the same 25 x 25 mm (210,940 cells), 20 ms;
//   scale sheets: examples/scale/sheet_2p5cm.json (no fibrosis, colman,
//                 VTK XML, snapshots every 20 ms) at 10 x 10 mm (33,496
//                 cells, 234,472 particles) and 25 x 25 mm (210,940 cells,
//                 1,476,580 particles), 30 ms;
//   Fig. 3:       examples/fig3_in_series_ep.json (3,129 cells, 16,653
//                 particles with DEM bonds, rush_larsen, 500 ms) and
//                 10 mm wide (tissue.width_mm=10: 27,435 cells, 144,063
//                 particles, 30 ms).
// The run's peak is either while it steps (states, the integrator's work
// arrays, the coupling) or while the maps are written, after the run has
// freed its stepping work (Simulation::Impl::release_run_buffers); the
// report is read from disk row by row and stays below both.
namespace {

// What the estimate counts from: this process's share of the scene, once.
struct Counts {
  const Scene& scene;
  const Tissue& tissue;
  const CellSystem& system;
  bool mechanics = false, split = false, gathers = false;
  // `cells`: this process's own (every cell in one process); `tissue_cells`:
  // the tissue's, of which rank 0 gathers what it writes; `held`: a split
  // rank's own cells and ghosts.
  double tissue_cells = 0, cells = 0, held = 0, gathered_cells = 0, states = 0;
  // y per state, its inputs and outputs and the populations' per-cell
  // parameters: 12.5 bytes a state; and 16 more for a and b where the
  // integrator reads them from the populations (CVODE, second-order
  // Rush-Larsen). Sheet 1 cm: 23.7 MB for 830,692 states with a and b.
  double state_bytes = 0;
  double particles = 0, built_particles = 0, bonds = 0, edges = 0;
  CellLayoutKept layout{};
  double onsets = 0, beats = 0;
  double trace_samples = 0, columns = 0;

  // The tissue as built: its particles, bonds, cell graph and cells, with
  // the vectors' spare capacity: 1.07 x these sizes on sheet 1 cm (8.98 MB,
  // reserved), 1.75 x on Fig. 3 widened (13.2 MB, grown by doubling).
  // Split over ranks, what a rank keeps of the cell graph and the cells'
  // centres once the run has started: 20 bytes a cell with the centres
  // (type, centre and the cell's place in the ranks' order), 1 without
  // (the type: a rank other than 0 without mechanics frees the rest).
  double tissue_bytes(double with_particles, double with_bonds, bool graph, bool centres, double spare = 1.5) const {
    return spare * (sizeof(Particle) * with_particles + sizeof(Bond) * with_bonds +
                    (graph ? sizeof(std::pair<int, int>) * edges : 0.0) + (centres ? 20.0 : 1.0) * tissue_cells);
  }
  // A checkpoint's bytes: the states (with inputs and outputs, ~1.5 x), the
  // biomarker trackers (~124 bytes a cell), the traces so far (at most all),
  // DEM bodies, particles and bonds.
  double checkpoint_bytes(double of_states, double of_cells, double trace_values) const {
    return 12 * of_states + 124 * of_cells + 8 * trace_values +
           (mechanics ? 300 * particles + 110.0 * static_cast<double>(tissue.bonds.size()) : 0.0);
  }
  // With several beats each cell's beats are kept while the run steps; with
  // one, only once the stepping's work is freed.
  bool beats_while_stepping() const { return onsets > 1; }
};

Counts count_scene(const Scene& scene, const Tissue& tissue, const CellSystem& system, bool mechanics, int rank,
                   int ranks) {
  Counts c{scene, tissue, system};
  c.mechanics = mechanics;
  c.split = ranks > 1;
  c.gathers = rank == 0;
  c.tissue_cells = static_cast<double>(tissue.cell_count());
  for (const auto& pop : system.populations) c.cells += static_cast<double>(pop.size());
  if (!c.split) c.cells = c.tissue_cells;  // (a tissue's cells are all in populations; a test's system may have none)
  c.held = static_cast<double>(system.numbering.held());
  c.gathered_cells = c.gathers ? c.tissue_cells : c.cells;
  for (const auto& pop : system.populations) c.states += static_cast<double>(pop.size() * pop.n_states());
  for (const auto& m : system.myofilaments) c.states += static_cast<double>(m.pop.size() * m.pop.n_states());
  c.state_bytes = reads_population_derivatives(scene.solver.method) ? 28.5 : 12.5;
  c.particles = static_cast<double>(tissue.particles.size() + tissue.collagen.size());
  c.built_particles = static_cast<double>(tissue.built_particles());  // (what the files show)
  c.bonds = static_cast<double>(tissue.bonds.size() + tissue.collagen_bonds.size());
  c.edges = static_cast<double>(tissue.cell_edges.size());
  c.layout = cell_layout_kept(rank, ranks, plan_processes(scene, tissue).has("mechanics"), scene.output.reentry.on);
  c.onsets = static_cast<double>(system.stimulus.onsets(scene.duration_ms).size());
  c.beats = std::max(1.0, c.onsets);
  const auto& tr = scene.output.traces;
  c.trace_samples = samples(scene.duration_ms, tr.from_ms, tr.every_ms);
  c.columns = mechanics ? 3 : 0;
  for (const auto& block : tr.blocks) c.columns += static_cast<double>(block.cells.size() * block.variables.size());
  return c;
}

// What the run holds from set-up to its end: the program, the cells'
// states, the tissue, a split rank's per-cell arrays, rank 0's imprint and
// the biomarker trackers.
void add_held_throughout(ResourceEstimate& e, const Counts& c) {
  e.memory.push_back({"program, libraries, plugins and threads", kProgramBytes, ""});
  e.memory.push_back({fmt::format("cell states: {:.0f}", c.states), c.state_bytes * c.states, "a smaller tissue"});
  const CellLayoutKept& layout = c.layout;
  const char* freed = layout.graph ? "" : layout.centres ? ", its graph freed" : ", its graph and centres freed";
  // (A tissue holding part of its cells holds their list and types alone,
  // freed with the centres.)
  const double tissue_bytes =
      c.tissue.cells_partial()
          ? (layout.centres ? static_cast<double>(sizeof(CellCentre) + sizeof(CellType)) * c.held : 0.0)
          : c.tissue_bytes(c.particles, c.bonds, layout.graph, layout.centres);
  e.memory.push_back({fmt::format("tissue: {:.0f} particles, {:.0f} bonds, {:.0f} cells{}{}", c.particles, c.bonds,
                                  c.tissue_cells, c.tissue.cells_partial() ? ", held in part" : "", freed),
                      tissue_bytes, "a smaller tissue"});
  // Split over ranks, a rank holds its own cells' and its ghosts' potential,
  // stimulus current, place (population, index) and tissue number
  // (CellSystem::numbering): 28 bytes a held cell (in one process they are
  // counted with the cell states).
  if (c.split)
    e.memory.push_back({fmt::format("{:.0f} held cells' potential, stimulus current and place", c.held),
                        28 * c.held, "a smaller tissue"});
  if (const TissueImprint* imprint = c.tissue.imprint())
    e.memory.push_back({"the particles' imprint, for the pictures and VTK files", static_cast<double>(imprint->bytes()),
                        "a smaller tissue"});
  // The biomarker tracker's per-cell state (88 bytes a cell, and its cell
  // type in a byte) and a BeatBiomarkers a cell and beat (room reserved for
  // them all at the first); scale sheet 2.5 cm: 18.8 and 13.5 MB.
  const double beats_bytes = sizeof(BeatBiomarkers) * c.cells * c.beats;
  e.memory.push_back({fmt::format("biomarkers: {:.0f} cells x {:.0f} beats", c.cells, c.beats),
                      89 * c.cells + (c.beats_while_stepping() ? beats_bytes : 0.0), "a smaller tissue"});
}

// What the integrator keeps per state: adaptive the saved start, and the
// linear forms' a and b of each state but a coupled potential, which has 2
// doubles a cell instead (the membrane term, the solve's vector);
// second-order Rush-Larsen 2 arrays; CVODE its vectors or Jacobian; the
// first-order methods none beyond the populations'.
void add_integrator(std::vector<ResourceEstimate::Part>& stepping, const Counts& c) {
  const SolverSpec& solver = c.scene.solver;
  const CellSystem& system = c.system;
  if (solver.method == "adaptive") {
    // Bytes of a and b of each state kept: in float or double, as the
    // integrator keeps a population's (myofilaments' at their own rtol).
    const auto form_bytes = [&](bool myofilament) {
      using A = AdaptiveIntegrator;
      return A::float_history(A::population_rtol(solver.rtol, myofilament)) ? 8.0 : 16.0;
    };
    double kept_forms = 0, forms_bytes = 0;  // states whose a, b the integrator keeps
    for (const auto& pop : system.populations) {
      double kept = static_cast<double>(pop.n_states());
      if (system.coupler && pop.voltage_state >= 0) kept -= 1;
      kept_forms += kept * static_cast<double>(pop.size());
      forms_bytes += form_bytes(false) * kept * static_cast<double>(pop.size());
    }
    for (const auto& m : system.myofilaments) {
      const double kept = static_cast<double>(m.pop.size() * m.pop.n_states());
      kept_forms += kept;
      forms_bytes += form_bytes(true) * kept;
    }
    stepping.push_back({fmt::format("integrator: {:.0f} states, a and b of {:.0f}", c.states, kept_forms),
                        8 * c.states + forms_bytes + (system.coupler ? 16 * c.cells : 0.0), "a smaller tissue"});
  } else if (solver.method == "rush_larsen2") {
    stepping.push_back({fmt::format("integrator: {:.0f} states x 2 arrays", c.states), 16 * c.states,
                        "a smaller tissue"});
  }
  if (solver.method == "cvode") {
    const std::string linear = solver.linear_solver;
    const bool dense = linear == "dense" || (linear == "auto" && c.states <= 200);
    stepping.push_back({dense ? fmt::format("CVODE dense Jacobian {:.0f}^2", c.states)
                              : fmt::format("CVODE vectors and linear solver, {:.0f} states", c.states),
                        dense ? 16 * c.states * c.states : 8 * 40 * c.states,
                        dense ? "solver.linear_solver \"band\" or \"krylov\"" : "a smaller tissue"});
  }
}

// The coupled pairs of this process's rows (split over ranks: about its
// share of the tissue's).
double coupling_pairs(const Counts& c) {
  return static_cast<double>(c.tissue.built_cell_edges()) * c.cells / std::max(1.0, c.tissue_cells);
}

// The coupling, held once by the conjugate gradients (0 without coupling).
double coupling_bytes(const Counts& c) {
  if (!c.system.coupler) return 0;
  // The Laplacian (2 entries an edge, 12 bytes each, in slices padded to
  // their longest row, ~ the size of compressed rows with the diagonal),
  // the CG's 6 other vectors of a double a cell (1/C, and x, r, z, p, q;
  // A's diagonal and M^-1 are computed where read) and each row's length
  // and diagonal place (two ints), built with the coupler, explicit or not
  // (coupling/coupling_cg.hpp); the coupled pairs are the tissue's own
  // list, counted with it. Scale sheet 10 x 10 mm: L in compressed rows
  // measures 2.93 MB, 12 bytes x (2 pairs + cells) 2.79.
  return 12 * (2 * coupling_pairs(c) + c.cells) + 56 * c.cells;
}

// Freed at the end of the stepping: the integrator's work, the coupling,
// the re-entry samples, a picture being drawn.
std::vector<ResourceEstimate::Part> stepping_parts(const Counts& c) {
  std::vector<ResourceEstimate::Part> stepping;
  add_integrator(stepping, c);
  if (c.system.coupler)
    stepping.push_back(
        {fmt::format("coupling: {:.0f} edges", coupling_pairs(c)), coupling_bytes(c), "a smaller tissue"});
  const Scene& scene = c.scene;
  if (const auto& re = scene.output.reentry; re.on && c.gathers) {
    // V of every cell at every sample, as float (with mechanics its fibre
    // stretch too, run/strain_fields.hpp), and the spectrum's bins.
    const double frames = samples(scene.duration_ms, re.from_ms, re.every_ms);
    // (one spectrum over the bins of both bands, measure/dominant_frequency.hpp)
    const double band_hz = std::max(re.f_max_hz, re.clinical_f_max_hz) - std::min(re.f_min_hz, re.clinical_f_min_hz);
    const double bins = std::max(0.0, band_hz * frames * re.every_ms / 1000.0) + 1;
    stepping.push_back({fmt::format("reentry: {:.0f} cells x {:.0f} samples{}", c.tissue_cells, frames,
                                    c.mechanics ? " (V and fibre stretch)" : ""),
                        (c.mechanics ? 8 : 4) * c.tissue_cells * frames + 16 * c.tissue_cells * bins,
                        "output.reentry: a larger every_ms, a later from_ms, or a smaller tissue"});
  }
  // A picture drawn on the background thread while the cells step
  // (tissue.png as the stepping starts, each snapshot's PNG). The VTK files
  // are streamed to disk: 64 kB buffers whatever the tissue.
  const bool pictures_while_stepping =
      c.gathers && (scene.output.tissue_picture || (scene.output.snapshots.every_ms > 0 && scene.output.snapshots.png));
  if (pictures_while_stepping)
    stepping.push_back({"a picture being drawn", picture_bytes(c.tissue),
                        "output.snapshots.png false and output.tissue_picture false"});
  return stepping;
}

// After the stepping: a one-beat run's biomarkers, kept as the stepping
// ends; the maps: four per-cell fields, the activation map's picture (the
// VTK file is streamed). Only what exceeds the stepping's freed work adds
// to the peak.
void add_after_stepping(ResourceEstimate& e, const Counts& c, double stepping_bytes) {
  const double gathered_beats_bytes = sizeof(BeatBiomarkers) * c.gathered_cells * c.beats;
  const double beats_after = c.beats_while_stepping() ? 0.0 : gathered_beats_bytes;
  if (beats_after > 0) {
    e.memory.push_back({"the beat's biomarkers, beyond the stepping's freed work",
                        std::max(0.0, beats_after - stepping_bytes), "a smaller tissue"});
  }
  if (c.scene.output.maps && c.gathers) {
    const double maps = 32 * c.tissue_cells + picture_bytes(c.tissue);
    e.memory.push_back(
        {fmt::format("maps: {:.0f} cells, beyond the stepping's freed work", c.tissue_cells),
         std::max(0.0, beats_after + maps - stepping_bytes) - std::max(0.0, beats_after - stepping_bytes),
         "output.maps false"});
  }
}

// The traces held, the DEM, its exchanges over ranks, and a checkpoint
// while it is written.
void add_traces_dem_checkpoint(ResourceEstimate& e, const Counts& c) {
  e.memory.push_back({fmt::format("traces: {:.0f} columns x {:.0f} samples", c.columns, c.trace_samples),
                      8 * c.columns * c.trace_samples,
                      "output.traces: fewer cells or variables, or a larger every_ms"});
  if (c.mechanics) e.memory.push_back(dem_memory(c.tissue));
  // The DEM split over ranks: its halo, the bodies shared at each list
  // rebuild and, at a checkpoint, every contact's state gathered on rank 0
  // (the sheet above: ~30 bytes a particle and a bond).
  if (c.mechanics && c.split && !c.scene.mechanics.multirate)
    e.memory.push_back({"the DEM's exchanges over ranks",
                        30.0 * (c.built_particles + static_cast<double>(c.tissue.built_bonds())),
                        "a smaller tissue"});
  // A checkpoint while it is written: its fields, each array copied once
  // (streamed to the file from there: io/checkpoint_file.hpp), this rank's part.
  if (c.scene.output.checkpoint.every_ms > 0)
    e.memory.push_back({"a checkpoint while it is written",
                        c.checkpoint_bytes(c.states, c.cells, c.columns * c.trace_samples),
                        "output.checkpoint: none, or a smaller tissue"});
}

// A rank of a split run may peak at set-up (run/simulation_ranks.cpp):
// - where it builds the whole tissue, then frees its particles before
//   the stepping (rank 0 with the particles' imprint made);
// - when the partition is cut, with every cell, its centre and graph
//   (a rank other than 0 cut without the whole graph: the part it
//   keeps, its own cells' and ghosts' centres, and neither a part nor a
//   place in the ranks' order a cell),
//   and the partitioner's own work: for rcb the centres it collects at
//   once (CoordinateCuts::kCollectBudget) and every cell's part, 4 bytes
//   (without the whole graph, none: the builder's kind of each slot, a
//   byte, while the graph goes by), 104 bytes a cell for Scotch's copies
//   of the graph (heaptrack on the 846,279-cell sheet: 88 MB), with the
//   particles where the DEM is to be built;
// - when its coupling is assembled (coupling/gap_junction.cpp), beside
//   the graph it holds, its cells' states and its held cells' arrays,
//   with three ints of every held cell while the rows are made.
// Built cell by cell (fibrotic_sheet), the cells' vectors are reserved
// to their size: counted without tissue_bytes's spare capacity. What
// exceeds the rest of the estimate is added.
void add_set_up_over_ranks(ResourceEstimate& e, const Counts& c) {
  const Scene& scene = c.scene;
  const Tissue& tissue = c.tissue;
  const bool built_whole = c.mechanics || !scene.tissue || !scene.tissue->builds_cells_alone();
  const TissueImprint* imprint = tissue.imprint();
  double build = 0;
  if (tissue.particles_released() && built_whole)
    build = kProgramBytes + c.tissue_bytes(c.built_particles, static_cast<double>(tissue.built_bonds()), true, true) +
            (imprint ? static_cast<double>(imprint->bytes()) : 0.0);
  // (Cut without the whole graph, a rank holds every cell's type, the
  // centres of its own cells and ghosts, and no ranks' order of the cells.)
  const double cells_held = tissue.graph_partial()
                                ? sizeof(std::pair<int, int>) * c.edges + c.tissue_cells + sizeof(CellCentre) * c.held
                                : c.tissue_bytes(c.mechanics ? c.particles : 0.0, c.mechanics ? c.bonds : 0.0, true,
                                                 true, built_whole ? 1.5 : 1.0);
  const PartitionMethod method = scene.solver.partition;
  const double partitioner = method == PartitionMethod::scotch
                                 ? 104.0 * c.tissue_cells
                                 : (tissue.graph_partial() ? 1.0 : 4.0) * c.tissue_cells +
                                       static_cast<double>(CoordinateCuts::kCandidateBytes * CoordinateCuts::kCollectBudget);
  const double cut = kProgramBytes + cells_held + partitioner;
  const double assembly = c.system.coupler ? kProgramBytes + cells_held + c.state_bytes * c.states + 28 * c.held +
                                                 coupling_bytes(c) + 12 * c.held
                                           : 0.0;
  const double beyond = std::max(0.0, std::max({build, cut, assembly}) - e.memory_bytes());
  if (beyond > 0)
    e.memory.push_back(
        {"the set-up (the tissue built, cut over the ranks, its coupling assembled), beyond the stepping's", beyond,
         method == PartitionMethod::scotch ? "solver.partition: rcb" : "a smaller tissue"});
}

// What the run writes to its folder.
void add_outputs(ResourceEstimate& e, const Counts& c) {
  const Scene& scene = c.scene;
  e.output.push_back({"traces.csv", c.trace_samples * (24 * c.columns + 24),
                      "output.traces: fewer cells or variables, or a larger every_ms"});
  const auto& snap = scene.output.snapshots;
  const double frames = samples(scene.duration_ms, snap.from_ms, snap.every_ms);
  e.output.push_back({fmt::format("{:.0f} snapshots", frames),
                      frames * ((snap.png ? png_frame_bytes(c.tissue) : 0.0) +
                                (snap.strain && c.mechanics ? png_frame_bytes(c.tissue) : 0.0) +
                                (snap.vtk ? vtk_frame_bytes(scene.output.vtk_format, c.built_particles, c.mechanics)
                                          : 0.0)),
                      "output.snapshots: a larger every_ms, or png/vtk/strain false"});
  e.output.push_back(
      {"biomarkers, maps, pictures, logs", 200.0 * c.tissue_cells + 300.0 * c.built_particles + 1e5, ""});
  if (scene.output.checkpoint.every_ms <= 0) return;
  // `keep` checkpoints and one being written (split over ranks: every
  // rank's part, in the one folder).
  const double all_states = c.split ? c.states * c.tissue_cells / std::max(1.0, c.cells) : c.states;
  const double one = c.checkpoint_bytes(all_states, c.tissue_cells, c.columns * c.trace_samples);
  const int copies = scene.output.checkpoint.keep + 1;
  e.output.push_back({fmt::format("{} checkpoints", copies), copies * one, "output.checkpoint: a smaller keep"});
  // The re-entry samples beside them (run/frame_log.hpp): a float a cell a
  // sample, with mechanics the fibre stretch's too.
  if (const auto& re = scene.output.reentry; re.on) {
    const double kept = samples(scene.duration_ms, re.from_ms, re.every_ms);
    e.output.push_back({fmt::format("re-entry samples beside the checkpoints: {:.0f}", kept),
                        kept * (c.mechanics ? 2 : 1) * (4 * c.tissue_cells + 8),
                        "output.reentry: a larger every_ms or a later from_ms"});
  }
}

}  // namespace

ResourceEstimate estimate_resources(const Scene& scene, const Tissue& tissue, const CellSystem& system,
                                    bool mechanics, int rank, int ranks) {
  const Counts c = count_scene(scene, tissue, system, mechanics, rank, ranks);
  ResourceEstimate e;
  add_held_throughout(e, c);
  double stepping_bytes = 0;
  for (auto& part : stepping_parts(c)) stepping_bytes += part.bytes, e.memory.push_back(std::move(part));
  add_after_stepping(e, c, stepping_bytes);
  add_traces_dem_checkpoint(e, c);
  if (c.split) add_set_up_over_ranks(e, c);
  if (!scene.output.dir.empty()) add_outputs(e, c);
  return e;
}

// (As built: a rank of a split run keeps the whole DEM after freeing the
// tissue's own particles.) Measured by heaptrack on a 12 x 18 mm
// fibrotic_sheet of 72,787 myocytes (509,509 particles, 506,618 bonds,
// 579,120 unbonded contacts listed; 273 MB in the DEM): per particle its
// body's share, its place in the bodies' index and the contact detector's
// grid, 182 bytes; per contact (bond or listed unbonded pair) its set's
// entry, index and incidence, 167 bytes; the list holds ~1.14 unbonded
// pairs a particle. So 370 bytes a particle and 170 a bond.
ResourceEstimate::Part dem_memory(const Tissue& tissue) {
  const std::size_t particles = tissue.built_particles(), bonds = tissue.built_bonds();
  return {fmt::format("DEM: {} particles, {} bonds", particles, bonds),
          370.0 * static_cast<double>(particles) + 170.0 * static_cast<double>(bonds), "a smaller tissue"};
}

void check_dem_memory(const Tissue& tissue, double available_memory) {
  const ResourceEstimate::Part dem = dem_memory(tissue);
  if (dem.bytes > 0.9 * available_memory)
    throw ManifestError("tissue", fmt::format("mechanics on this tissue needs about {} for the {} alone, more than "
                                              "the {} of memory available: try a smaller tissue, or leave mechanics "
                                              "out of effects",
                                              size_text(dem.bytes), dem.what, size_text(available_memory)));
}

void check_resources(const ResourceEstimate& estimate, double available_memory, double available_disk) {
  if (estimate.memory_bytes() > 0.9 * available_memory) {
    const auto& big = largest(estimate.memory);
    throw ManifestError("resources", fmt::format("this scene needs about {} of memory, more than the {} available; "
                                                 "the largest part is {} ({}): try {}. Estimate: {}",
                                                 size_text(estimate.memory_bytes()), size_text(available_memory),
                                                 big.what, size_text(big.bytes), big.remedy, estimate.describe()));
  }
  if (!estimate.output.empty() && estimate.output_bytes() > available_disk) {
    const auto& big = largest(estimate.output);
    throw ManifestError("resources", fmt::format("this scene writes about {}, more than the {} free on the output "
                                                 "disk; the largest part is {} ({}): try {}",
                                                 size_text(estimate.output_bytes()), size_text(available_disk),
                                                 big.what, size_text(big.bytes), big.remedy));
  }
}

double available_memory_bytes() {
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  double kb = 0;
  std::string unit;
  while (meminfo >> key >> kb >> unit)
    if (key == "MemAvailable:") return kb * 1024;
  return std::numeric_limits<double>::infinity();
}

double available_disk_bytes(const std::filesystem::path& dir) {
  std::error_code error;
  const auto space = std::filesystem::space(dir, error);
  return error ? std::numeric_limits<double>::infinity() : static_cast<double>(space.available);
}

}  // namespace fibrodem
