#include "run/resource_estimate.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include <fmt/format.h>

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

// Sample count of a series every `every_ms` from `from_ms` to the end.
double samples(double duration_ms, double from_ms, double every_ms) {
  return every_ms > 0 && duration_ms >= from_ms ? std::floor((duration_ms - from_ms) / every_ms) + 1 : 0;
}

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

ResourceEstimate estimate_resources(const Scene& scene, const Tissue& tissue, const CellSystem& system,
                                    bool mechanics) {
  ResourceEstimate e;
  const SolverSpec& solver = scene.solver;
  double states = 0, cells = static_cast<double>(system.cell_count());
  for (const auto& pop : system.populations) states += static_cast<double>(pop.size() * pop.n_states());
  for (const auto& m : system.myofilaments) states += static_cast<double>(m.pop.size() * m.pop.n_states());
  // y, a, b per state, plus what the integrator keeps per state.
  const double per_state = solver.method == "adaptive" ? 9 : solver.method == "rush_larsen2" ? 5 : 3;
  e.memory.push_back({fmt::format("cell states: {:.0f} x {:g} arrays", states, per_state), 8 * per_state * states,
                      "a smaller tissue"});
  if (solver.method == "cvode") {
    const std::string linear = solver.linear_solver;
    const bool dense = linear == "dense" || (linear == "auto" && states <= 200);
    e.memory.push_back({dense ? fmt::format("CVODE dense Jacobian {:.0f}^2", states)
                              : fmt::format("CVODE vectors and linear solver, {:.0f} states", states),
                        dense ? 16 * states * states : 8 * 40 * states,
                        dense ? "solver.linear_solver \"band\" or \"krylov\"" : "a smaller tissue"});
  }
  if (system.coupler) {
    const double edges = static_cast<double>(system.coupled_pairs.size());
    // The Laplacian (2 entries an edge and a diagonal, 12 bytes each, in
    // compressed rows); with an implicit solve the conjugate gradients' work:
    // 8 vectors of one double a cell (coupling/coupling_cg.hpp).
    const bool implicit = system.implicit_coupling || solver.method == "adaptive";
    e.memory.push_back({fmt::format("coupling: {:.0f} edges{}", edges, implicit ? ", CG vectors" : ""),
                        12 * (2 * edges + cells) + 4 * cells + (implicit ? 64 : 8) * cells, "a smaller tissue"});
  }
  // The rest, measured (peak RSS of the Fig. 3 in-series EP scene, adaptive,
  // 200 ms, at 3k, 52k and 208k cells: this estimate within 20 % of each):
  // the program, its libraries and plugins; the tissue and the run's
  // bookkeeping (biomarkers, inputs, tiles), by particle; and the pictures,
  // maps and report drawn from it.
  const double particles = static_cast<double>(tissue.particles.size());
  e.memory.push_back({"program and libraries", 25e6, ""});
  e.memory.push_back({fmt::format("tissue and run bookkeeping: {:.0f} particles", particles), 235 * particles,
                      "a smaller tissue"});
  const auto& out = scene.output;
  const bool drawn = samples(scene.duration_ms, out.snapshots.from_ms, out.snapshots.every_ms) > 0;
  if (out.tissue_picture || out.maps || out.report || (drawn && out.snapshots.png))
    e.memory.push_back({"pictures, maps and report", 745 * particles,
                        "output.tissue_picture, output.maps, output.report false; output.snapshots.png false"});
  const auto& tr = scene.output.traces;
  const double trace_samples = samples(scene.duration_ms, tr.from_ms, tr.every_ms);
  double columns = mechanics ? 3 : 0;
  for (const auto& block : tr.blocks) columns += static_cast<double>(block.cells.size() * block.variables.size());
  e.memory.push_back({fmt::format("traces: {:.0f} columns x {:.0f} samples", columns, trace_samples),
                      8 * columns * trace_samples, "output.traces: fewer cells or variables, or a larger every_ms"});
  if (const auto& re = scene.output.reentry; re.on) {
    // V of every cell at every sample, as float, and the spectrum's bins.
    const double frames = samples(scene.duration_ms, re.from_ms, re.every_ms);
    const double bins = std::max(0.0, (re.f_max_hz - re.f_min_hz) * frames * re.every_ms / 1000.0) + 1;
    e.memory.push_back({fmt::format("reentry: {:.0f} cells x {:.0f} samples", cells, frames),
                        4 * cells * frames + 16 * cells * bins,
                        "output.reentry: a larger every_ms, a later from_ms, or a smaller tissue"});
  }
  if (mechanics)
    e.memory.push_back({fmt::format("DEM: {} particles, {} bonds", tissue.particles.size(), tissue.bonds.size()),
                        256.0 * static_cast<double>(tissue.particles.size()) +
                            64.0 * static_cast<double>(tissue.bonds.size()),
                        "a smaller tissue"});
  if (!scene.output.dir.empty()) {
    e.output.push_back({"traces.csv", trace_samples * (24 * columns + 24),
                        "output.traces: fewer cells or variables, or a larger every_ms"});
    const auto& snap = scene.output.snapshots;
    const double frames = samples(scene.duration_ms, snap.from_ms, snap.every_ms);
    // A PNG frame: ~60 bytes a particle (measured: 170 kB for 22k particles);
    // VTK: ~120 bytes a particle.
    e.output.push_back({fmt::format("{:.0f} snapshots", frames),
                        frames * ((snap.png ? 60 : 0) + (snap.vtk ? 120 : 0)) * particles,
                        "output.snapshots: a larger every_ms, or png/vtk false"});
    e.output.push_back({"biomarkers, maps, pictures, logs", 200.0 * cells + 300.0 * particles + 1e5, ""});
    if (scene.output.checkpoint.every_ms > 0) {
      // A checkpoint: the states (with inputs and outputs, ~1.5 x), the
      // biomarker trackers (~140 bytes a cell), the traces so far (at most
      // all), DEM bodies, particles and bonds; `keep` of them and one being written.
      const double one = 12 * states + 140 * cells + 8 * columns * trace_samples +
                         (mechanics ? 300 * particles + 110.0 * static_cast<double>(tissue.bonds.size()) : 0.0);
      const int copies = scene.output.checkpoint.keep + 1;
      e.output.push_back({fmt::format("{} checkpoints", copies), copies * one,
                          "output.checkpoint: a smaller keep"});
    }
  }
  return e;
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
