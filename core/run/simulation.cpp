#include "run/simulation.hpp"

#include <spdlog/sinks/basic_file_sink.h>
#include <spdlog/sinks/null_sink.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <omp.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "coupling/gap_junction.hpp"
#include "integrate/cell_system.hpp"
#include "integrate/integrator.hpp"
#include "integrate/stability.hpp"
#include "mechanics/mechanics_solver.hpp"
#include "io/csv_writer.hpp"
#include "io/tissue_picture.hpp"
#include "io/vtk_writer.hpp"
#include "measure/conduction_velocity.hpp"
#include "run/population_setup.hpp"

namespace fibrodem {
namespace fs = std::filesystem;

namespace {

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
  std::string name() const { return strain >= 0 ? variable : variable + "_" + std::to_string(cell); }
};

std::string list_names(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

}  // namespace

struct Simulation::Impl : StepObserver {
  Scene scene;
  RunOptions options;
  std::shared_ptr<PluginRegistry> registry;
  Tissue tissue;
  ProcessPlan plan;
  CellSystem system;
  std::unique_ptr<Integrator> integrator;
  std::shared_ptr<spdlog::logger> log;

  std::vector<TraceColumn> columns;
  bool traces_need_outputs = false;
  std::vector<double> times;
  std::vector<std::vector<double>> samples;  // per column
  long long next_sample_index = 0;
  std::vector<BeatBiomarkers> beats;
  std::unique_ptr<BiomarkerTracker> tracker;

  fs::path out;
  CsvWriter traces_csv, biomarkers_csv;
  std::vector<std::string> warnings;  // found at set-up, logged when the run starts
  StabilityEstimate stability;
  std::string status = "set up";
  std::string error;
  double wall_s = 0;
  long long steps = 0;
  long long snapshots_taken = 0;
  std::unique_ptr<MechanicsSolver> mechanics;
  double mechanics_step_ms = 0, mechanics_time_ms = 0, mechanics_seconds = 0;
  std::vector<double> length_ratio;
  std::array<double, 3> peak_strain{0, 0, 0};
  static constexpr const char* kStrainNames[3] = {"eps_xx", "eps_yy", "eps_xy"};
  std::chrono::steady_clock::time_point started, last_progress, last_flush;

  Impl(const Scene& s, std::shared_ptr<PluginRegistry> r, RunOptions o)
      : scene(s), options(o), registry(std::move(r)) {
    if (!registry) registry = std::make_shared<PluginRegistry>();
    // One thread unless asked: on a shared machine, OpenMP's spinning threads
    // can cost more than they bring (set OMP_WAIT_POLICY=PASSIVE there).
    if (scene.solver.threads > 0) omp_set_num_threads(scene.solver.threads);
    make_logger();
    tissue = scene.tissue->build(scene.seed);
    plan = plan_processes(scene, tissue);
    build_populations();
    derive_contraction_from_traces();
    build_myofilaments();
    build_coupling();
    build_mechanics();
    system.stimulus = Stimulus(scene.stimuli, tissue);
    resolve_traces();
    build_lookup_tables();
    integrator = make_integrator(scene.solver);
    check_explicit_stability();
  }

  // solver.lookup_tables: a table of the voltage_only gates' rates per ionic
  // population whose model marks any (after every parameter change above).
  void build_lookup_tables() {
    if (!scene.solver.lookup_tables) return;
    for (auto& pop : system.populations) {
      std::string note = std::string("lookup tables: ") + cell_type_name(pop.type) + " model " + pop.info().name;
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

  void make_logger() {
    std::vector<spdlog::sink_ptr> sinks;
    if (options.console_log) sinks.push_back(std::make_shared<spdlog::sinks::stderr_color_sink_mt>());
    if (sinks.empty()) sinks.push_back(std::make_shared<spdlog::sinks::null_sink_mt>());
    log = std::make_shared<spdlog::logger>("fibrodem", sinks.begin(), sinks.end());
    log->set_pattern("[%H:%M:%S.%e] [%l] %v");
    log->set_level(spdlog::level::info);
  }

  void build_populations() {
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
      system.populations.push_back(make_population(type, spec->second.ionic, ModelKind::ionic, *registry));
    }
    system.where.resize(tissue.cell_count());
    for (std::size_t cell = 0; cell < tissue.cell_count(); ++cell) {
      const int p = population_of.at(tissue.type[cell]);
      system.where[cell] = {p, system.populations[p].cells.size()};
      system.populations[p].cells.push_back(static_cast<int>(cell));
    }
    for (auto& pop : system.populations) pop.reset();
    system.V_mV.assign(tissue.cell_count(), 0.0);
    system.i_ext_pA.assign(tissue.cell_count(), 0.0);
  }

  void build_coupling() {
    if (!plan.has("coupling")) return;
    std::vector<double> capacitance(tissue.cell_count());
    for (std::size_t cell = 0; cell < tissue.cell_count(); ++cell)
      capacitance[cell] = system.populations[system.where[cell].first].capacitance_pF;
    system.coupler = std::make_unique<GapJunctionCoupler>(tissue, scene.coupling.D_m_nS,
                                                          scene.coupling.D_f_nS, capacitance);
    system.coupled_pairs = tissue.cell_edges;
    system.implicit_coupling = scene.coupling.scheme == "implicit" && scene.solver.method != "cvode";
    if (scene.coupling.dt_ms > 0 && scene.solver.method != "cvode") {
      const double ratio = scene.coupling.dt_ms / scene.solver.dt_ms;
      if (ratio < 1 - 1e-9 || std::abs(ratio - std::round(ratio)) > 1e-6 * ratio)
        throw ManifestError("coupling.dt_ms", "expected a multiple of solver.dt_ms (" +
                                                  format_number(scene.solver.dt_ms) + " ms), got " +
                                                  format_number(scene.coupling.dt_ms));
      system.coupling_every = static_cast<int>(std::lround(ratio));
    }
  }

  // Without a list of effects, a traced variable of a cell type's myofilament
  // model calls for contraction.
  void derive_contraction_from_traces() {
    if (scene.effects_listed || plan.has("contraction")) return;
    for (const auto& var : scene.output.traces.variables)
      for (const auto& cell : scene.output.traces.cells) {
        if (cell >= static_cast<int>(tissue.cell_count())) continue;
        const Population& host = system.populations[system.where[cell].first];
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

  // One myofilament population per cell type that names one, over the same cells.
  void build_myofilaments() {
    if (!plan.has("contraction")) return;
    for (std::size_t p = 0; p < system.populations.size(); ++p) {
      Population& host = system.populations[p];
      const CellTypeSpec& spec = scene.cells.at(host.type);
      if (!spec.myofilament) continue;
      Myofilament m;
      m.pop = make_population(host.type, *spec.myofilament, ModelKind::myofilament, *registry);
      m.pop.cells = host.cells;
      m.pop.reset();
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
    if (plan.has("mechano_electric_feedback")) {
      system.sac.on = true;
      system.sac.G_nS = scene.mechano_electric.G_SAC_nS;
      system.sac.E_mV = scene.mechano_electric.E_SAC_mV;
      system.sac.lambda_max = scene.mechano_electric.lambda_max;
    }
  }

  // Troponin buffering of the myofilament model enters the host's Ca balance
  // as an input flux; the host's own troponin buffer is switched off so that
  // troponin is not counted twice.
  void connect_calcium_feedback(Population& host, Myofilament& m, const CellTypeSpec& spec) {
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

  // DEM tissue mechanics: cells' lengths from their myofilaments drive it;
  // nothing flows back to the cells.
  void build_mechanics() {
    if (!plan.has("mechanics")) return;
    try {
      mechanics = make_mechanics_solver(tissue, scene.mechanics);
    } catch (const std::invalid_argument& e) {
      throw ManifestError("mechanics", e.what());
    }
    mechanics_step_ms = mechanics->step_ms();
    length_ratio.assign(tissue.cell_count(), 1.0);
  }

  void resolve_traces() {
    const TraceSpec& spec = scene.output.traces;
    if (mechanics)  // the tissue strain is always traced with mechanics
      for (int k = 0; k < 3; ++k) columns.push_back({kStrainNames[k], 0, 0, 0, false, false, 0, k});
    for (std::size_t i = 0; i < spec.cells.size(); ++i) {
      const int cell = spec.cells[i];
      if (cell >= static_cast<int>(tissue.cell_count()))
        throw ManifestError(index_path("output.traces.cells", i),
                            "cell " + std::to_string(cell) + " does not exist (the tissue has " +
                                std::to_string(tissue.cell_count()) + " cells)");
      for (std::size_t j = 0; j < spec.variables.size(); ++j) {
        const std::string& var = spec.variables[j];
        if (is_strain_variable(var)) {
          if (!mechanics)
            throw ManifestError(index_path("output.traces.variables", j),
                                "\"" + var + "\" is the tissue strain, which needs the effect mechanics");
          continue;
        }
        const auto [p, local] = system.where[cell];
        TraceColumn col{var, cell, p, local, false, false, -1};
        if (!find_column(system.populations[p], col))
          for (std::size_t m = 0; m < system.myofilaments.size(); ++m)
            if (system.myofilaments[m].host == p && find_column(system.myofilaments[m].pop, col)) {
              col.myofilament = true;
              col.population = static_cast<int>(m);
            }
        if (col.index < 0) {
          std::vector<std::string> names;
          system.for_each_part(cell, [&](const Population& pop, std::size_t) {
            for (const auto& s : pop.info().states) names.push_back(s.name);
            for (const auto& o : pop.info().outputs) names.push_back(o.name);
          });
          throw ManifestError(index_path("output.traces.variables", j),
                              "\"" + var + "\" is neither a state nor an output of the models of cell " +
                                  std::to_string(cell) + " (" + system.populations[p].info().name +
                                  (plan.has("contraction") ? "" : "; myofilament models are loaded only with contraction") +
                                  "); they have: " + list_names(names));
        }
        traces_need_outputs = traces_need_outputs || col.is_output;
        columns.push_back(col);
      }
    }
    samples.assign(columns.size(), {});
    if (scene.solver.method != "cvode") {
      for (const auto& [value, path] : {std::pair{spec.every_ms, "output.traces.every_ms"},
                                        std::pair{spec.from_ms, "output.traces.from_ms"}}) {
        const double steps_per = value / scene.solver.dt_ms;
        if (std::abs(steps_per - std::round(steps_per)) > 1e-6 * std::max(1.0, steps_per))
          throw ManifestError(path, "expected a multiple of solver.dt_ms (" +
                                        format_number(scene.solver.dt_ms) + " ms) for a fixed-step "
                                        "method, got " + format_number(value));
      }
    }
  }

  static bool find_column(const Population& pop, TraceColumn& col) {
    col.index = find_state(pop.info(), col.variable);
    col.is_output = col.index < 0;
    if (col.is_output) col.index = find_output(pop.info(), col.variable);
    return col.index >= 0;
  }

  void check_explicit_stability() {
    if (scene.solver.method == "cvode") return;
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

  // ---- the run --------------------------------------------------------------

  void open_outputs() {
    if (scene.output.dir.empty()) return;
    out = scene.output.dir;
    fs::create_directories(out);
    auto file_sink = std::make_shared<spdlog::sinks::basic_file_sink_mt>((out / "run.log").string(), true);
    file_sink->set_pattern("[%Y-%m-%d %H:%M:%S.%e] [%l] %v");
    log->sinks().push_back(file_sink);
    std::vector<std::string> header = {"t_ms"};
    for (const auto& c : columns) header.push_back(c.name());
    traces_csv = CsvWriter(out / "traces.csv", header);
    biomarkers_csv = CsvWriter(out / "biomarkers.csv",
                               {"cell", "type", "beat", "activation_ms", "rmp_mV", "apo_mV", "apd90_ms",
                                "dvdt_max_mV_per_ms"});
    if (scene.output.tissue_picture) {
      PictureOptions picture;
      picture.title = scene.name + ": " + std::to_string(tissue.count(CellType::myocyte)) + " myocytes, " +
                      std::to_string(tissue.count(CellType::fibroblast)) + " fibroblasts";
      write_tissue_png(tissue, out / "tissue.png", nullptr, picture);
      write_tissue_vtk(tissue, out / "tissue.vtk");
    }
    write_summary();
  }

  void log_setup() {
    log->info("scene '{}': {} cells ({} myocytes, {} fibroblasts), {} particles, {} cell-graph edges",
              scene.name, tissue.cell_count(), tissue.count(CellType::myocyte),
              tissue.count(CellType::fibroblast), tissue.particles.size(), tissue.cell_edges.size());
    for (const auto& p : plan.built) log->info("process built: {} ({})", p.name, p.reason);
    for (const auto& note : plan.notes) log->info("{}", note);
    system.for_each_population([&](const Population& pop) {
      log->info("{}: {} model {} {}{}, {} cells x {} states", cell_type_name(pop.type),
                pop.info().kind == ModelKind::ionic ? "ionic" : "myofilament", pop.info().name, pop.info().version,
                pop.variant.empty() ? "" : ", variant " + pop.variant, pop.size(), pop.n_states());
    });
    if (mechanics)
      log->info("mechanics: DEM, contact law {}, step {:.4g} ms (stable {:.4g} ms), subcycled against the "
                "cells' steps", scene.mechanics.contact_law, mechanics_step_ms, mechanics->stable_step_ms());
    if (system.sac.on)
      log->info("stretch-activated current: G = {} nS, E = {} mV, lambda_max = {}", system.sac.G_nS, system.sac.E_mV,
                system.sac.lambda_max);
    if (system.coupler)
      log->info("coupling: gap junctions, D_m = {} nS, D_f = {} nS, {}, updated every {} cell step(s)",
                scene.coupling.D_m_nS, scene.coupling.D_f_nS,
                system.implicit_coupling ? "backward Euler (split)" : "explicit", system.coupling_every);
    log->info("integrator: {}; {} threads", integrator->describe(), omp_get_max_threads());
    for (const auto& w : warnings) log->warn("{}", w);
  }

  double next_sample_ms() const override {
    if (columns.empty()) return std::numeric_limits<double>::infinity();
    const double t = scene.output.traces.from_ms +
                     static_cast<double>(next_sample_index) * scene.output.traces.every_ms;
    return t <= scene.duration_ms + kTimeEpsilon_ms ? t : std::numeric_limits<double>::infinity();
  }

  void on_sample(double t) override {
    if (traces_need_outputs) {
      system.evaluate(t, t);
    }
    times.push_back(t);
    if (traces_csv.is_open()) traces_csv.cell(t);
    for (std::size_t i = 0; i < columns.size(); ++i) {
      const TraceColumn& c = columns[i];
      const Population& pop = c.myofilament ? system.myofilaments[c.population].pop : system.populations[c.population];
      const double value = c.strain >= 0 ? mechanics->strain()[c.strain]
                           : c.is_output ? pop.outputs[c.index * pop.size() + c.local]
                                         : pop.y[c.index * pop.size() + c.local];
      samples[i].push_back(value);
      if (traces_csv.is_open()) traces_csv.cell(value);
    }
    if (traces_csv.is_open()) traces_csv.end_row();
    ++next_sample_index;
  }

  void on_step(double t_old, double t_new, const double* dVdt) override {
    ++steps;
    check_states(t_new);
    system.gather_voltage();
    tracker->step(t_old, t_new, system.V_mV.data(), dVdt);
    advance_mechanics(t_new);
    const SnapshotSpec& snap = scene.output.snapshots;
    if (!out.empty() && snap.every_ms > 0) {
      const double next = snap.from_ms + static_cast<double>(snapshots_taken) * snap.every_ms;
      if (t_new >= next - kTimeEpsilon_ms) {
        write_snapshot(t_new);
        ++snapshots_taken;
      }
    }
    const auto now = std::chrono::steady_clock::now();
    if (now - last_flush > std::chrono::seconds(1)) {
      if (traces_csv.is_open()) traces_csv.flush();
      last_flush = now;
    }
    if (options.progress && scene.output.progress_every_s > 0 &&
        std::chrono::duration<double>(now - last_progress).count() >= scene.output.progress_every_s) {
      const double elapsed = std::chrono::duration<double>(now - started).count();
      const double left = elapsed / t_new * (scene.duration_ms - t_new);
      std::fprintf(stderr, "\r  t = %.1f / %.1f ms   %.3g ms simulated per s   about %.0f s left   ",
                   t_new, scene.duration_ms, t_new / elapsed, left);
      std::fflush(stderr);
      last_progress = now;
    }
  }

  // Mechanics at its own step up to t, each step with the cells' present lengths.
  void advance_mechanics(double t) {
    if (!mechanics) return;
    const auto start = std::chrono::steady_clock::now();
    for (double h = mechanics->step_ms(); mechanics_time_ms + h <= t + kTimeEpsilon_ms; h = mechanics->step_ms()) {
      for (std::size_t cell = 0; cell < tissue.cell_count(); ++cell)
        length_ratio[cell] = system.stretch(system.where[cell].first, system.where[cell].second);
      mechanics->set_cell_length_ratios(length_ratio);
      mechanics->step(h);
      mechanics_time_ms += h;
      mechanics_step_ms = std::min(mechanics_step_ms, h);
      const auto strain = mechanics->strain();
      for (int k = 0; k < 3; ++k)
        if (std::abs(strain[k]) > std::abs(peak_strain[k])) peak_strain[k] = strain[k];
    }
    mechanics_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  // The tissue as it is now: deformed particles when mechanics runs.
  Tissue present_tissue(std::vector<std::array<double, 2>>* displacement) const {
    Tissue now = tissue;
    if (!mechanics) return now;
    now.particles = mechanics->particles();
    if (displacement)
      for (std::size_t p = 0; p < now.particles.size(); ++p)
        displacement->push_back({now.particles[p].x_um - tissue.particles[p].x_um,
                                 now.particles[p].y_um - tissue.particles[p].y_um});
    return now;
  }

  // The tissue coloured by membrane potential at time t (the step's end).
  void write_snapshot(double t) const {
    char stem[64];
    std::snprintf(stem, sizeof stem, "snapshot_%09.3f_ms", t);
    if (scene.output.snapshots.png) {
      PictureOptions picture;
      picture.value_label = "V (mV)";
      picture.value_min = -90;
      picture.value_max = 40;
      picture.title = fmt::format("{}   t = {:.1f} ms", scene.name, t);
      // The scale of the undeformed tissue, so that every snapshot shows the
      // deformation at the same magnification.
      const auto box = tissue.bounds_um();
      picture.pixels_per_um = picture.height_px / std::max(box[3] - box[2], 1.0);
      write_tissue_png(present_tissue(nullptr), out / (std::string(stem) + ".png"), &system.V_mV, picture);
    }
    if (scene.output.snapshots.vtk) {
      std::vector<std::array<double, 2>> displacement;
      const Tissue now = present_tissue(&displacement);
      write_tissue_vtk(now, out / (std::string(stem) + ".vtk"), {{"V_mV", system.V_mV}}, false,
                       mechanics ? &displacement : nullptr);
    }
  }

  // Per-cell maps of the last recorded beat: activation time picture and VTK.
  void write_maps() const {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::vector<double> activation(tissue.cell_count(), nan), apd90 = activation, rmp = activation, apo = activation;
    for (const auto& b : beats) {
      activation[b.cell] = b.activation_ms;
      apd90[b.cell] = b.apd90_ms;
      rmp[b.cell] = b.rmp_mV;
      apo[b.cell] = b.apo_mV;
    }
    PictureOptions picture;
    picture.value_label = "activation (ms)";
    picture.title = scene.name + ": activation map, last beat";
    write_tissue_png(tissue, out / "activation_map.png", &activation, picture);
    write_tissue_vtk(tissue, out / "maps.vtk",
                     {{"activation_ms", activation}, {"apd90_ms", apd90}, {"rmp_mV", rmp}, {"apo_mV", apo}}, false);
  }

  // A state outside its physical range (or NaN/Inf) stops the run. The range
  // is widened by round-off (1e-6 relative) and, for CVODE, by its error
  // tolerance: a gate at 1 + 1e-6 after a BDF step at rtol 1e-6 is not a blow-up.
  void check_states(double t) {
    const bool cvode = scene.solver.method == "cvode";
    // Ten times CVODE's local error bound rtol |y| + atol at the bound.
    auto slack = [&](double bound) {
      const double scale = std::max(1.0, std::abs(bound));
      return std::max(1e-6 * scale, cvode ? 10 * (scene.solver.rtol * scale + scene.solver.atol) : 0.0);
    };
    system.for_each_population([&](const Population& pop) {
      const std::size_t n = pop.size();
      const auto& states = pop.info().states;
      for (std::size_t k = 0; k < states.size(); ++k) {
        const double lo = states[k].lower - slack(states[k].lower);
        const double hi = states[k].upper + slack(states[k].upper);
        const double* y = pop.y.data() + k * n;
        for (std::size_t c = 0; c < n; ++c)
          if (!(y[c] >= lo && y[c] <= hi)) blow_up(t, pop, k, c, y[c]);
      }
    });
  }

  [[noreturn]] void blow_up(double t, const Population& pop, std::size_t k, std::size_t c, double value) const {
    std::ostringstream s;
    s << "blow-up at t = " << format_number(t) << " ms: cell " << pop.cells[c] << " ("
      << cell_type_name(pop.type) << ", model " << pop.info().name << "), state '" << pop.info().states[k].name
      << "' = " << format_number(value) << " " << pop.info().states[k].unit << ", expected within ["
      << format_number(pop.info().states[k].lower) << ", " << format_number(pop.info().states[k].upper)
      << "]";
    if (scene.solver.method != "cvode") {
      s << "; " << integrator->describe() << " may be unstable here";
      if (std::isfinite(stability.limit_ms()))
        s << fmt::format(" (estimated explicit stability limit {:.3g} ms, set by {}; a stable step: solver.dt_ms <= {:.3g})",
                         stability.limit_ms(),
                         stability.coupling_limit_ms <= stability.gate_limit_ms ? std::string("the coupling")
                                                                                : stability.fastest_gate,
                         0.5 * stability.limit_ms());
      s << ": try a smaller solver.dt_ms"
        << (system.coupler && !system.implicit_coupling ? ", coupling.scheme \"implicit\"" : "")
        << " or solver.method \"cvode\"";
    }
    throw BlowUpError(s.str());
  }

  void record_beat(const BeatBiomarkers& b) {
    beats.push_back(b);
    if (!biomarkers_csv.is_open()) return;
    biomarkers_csv.cell(static_cast<long long>(b.cell))
        .cell(std::string(cell_type_name(b.type)))
        .cell(static_cast<long long>(b.beat))
        .cell(b.activation_ms)
        .cell(b.rmp_mV)
        .cell(b.apo_mV)
        .cell(b.apd90_ms)
        .cell(b.dvdt_max_mV_per_ms);
    biomarkers_csv.end_row();
    biomarkers_csv.flush();
  }

  void run() {
    started = last_progress = last_flush = std::chrono::steady_clock::now();
    status = "running";
    try {
      open_outputs();
      log_setup();
      tracker = std::make_unique<BiomarkerTracker>(
          tissue.type, system.stimulus.onsets(scene.duration_ms), scene.output.biomarkers_from_ms,
          [this](const BeatBiomarkers& b) { record_beat(b); });
      system.record_rest_lengths();
      system.gather_voltage();
      tracker->start(0.0, system.V_mV.data());
      integrator->advance(system, 0.0, scene.duration_ms, *this);
      tracker->finish();
      if (!out.empty() && scene.output.maps) write_maps();
      status = "completed";
    } catch (const std::exception& e) {
      status = "failed";
      error = e.what();
    }
    if (options.progress) std::fprintf(stderr, "\n");
    wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    if (traces_csv.is_open()) traces_csv.flush();
    for (const auto& pop : system.populations)
      if (pop.table && pop.table->clamp_count() > 0)
        log->warn("lookup tables: {} model {}: V left the table [{:g}, {:g}] mV in {} cell evaluations "
                  "(rates clamped to the table's ends)",
                  cell_type_name(pop.type), pop.info().name, pop.table->v_min(), pop.table->v_max(),
                  pop.table->clamp_count());
    if (mechanics) log->info("mechanics: {}", mechanics->report());
    if (status == "failed") log->error("run failed: {}", error);
    else log->info("run completed: {} ms simulated in {:.3f} s wall, {} steps", scene.duration_ms, wall_s, steps);
    if (!out.empty()) {
      write_summary();
      log->info("outputs in {}", fs::absolute(out).string());
    }
    log->flush();
    if (status == "failed") throw std::runtime_error(error);
  }

  // ---- summary ----------------------------------------------------------------

  json mean_biomarkers() const {
    json means = json::object();
    for (CellType type : {CellType::myocyte, CellType::fibroblast}) {
      const char* fields[] = {"rmp_mV", "apo_mV", "apd90_ms", "dvdt_max_mV_per_ms"};
      double sum[4] = {0, 0, 0, 0};
      int count[4] = {0, 0, 0, 0};
      for (const auto& b : beats) {
        if (b.type != type) continue;
        const double values[4] = {b.rmp_mV, b.apo_mV, b.apd90_ms, b.dvdt_max_mV_per_ms};
        for (int i = 0; i < 4; ++i)
          if (std::isfinite(values[i])) {
            sum[i] += values[i];
            ++count[i];
          }
      }
      if (count[0] == 0) continue;
      json m;
      for (int i = 0; i < 4; ++i) m[fields[i]] = count[i] ? json(sum[i] / count[i]) : json(nullptr);
      m["beats_measured"] = count[0];
      means[cell_type_name(type)] = m;
    }
    return means;
  }

  // Conduction velocity of each beat along the fibre (y). A cell counts as
  // activated when its action potential amplitude reaches 20 mV.
  json conduction() const {
    json per_beat = json::array();
    if (tissue.cell_count() < 2) return per_beat;
    std::vector<bool> stimulated(tissue.cell_count(), false);
    for (const auto& train : system.stimulus.trains())
      for (int c : train.cells) stimulated[c] = true;
    std::map<int, std::vector<ConductionSample>> beats_by_index;
    for (const auto& b : beats)
      beats_by_index[b.beat].push_back(
          {tissue.y_um[b.cell], b.activation_ms, stimulated[b.cell], b.apo_mV - b.rmp_mV >= 20.0});
    for (const auto& [beat, beat_cells] : beats_by_index)
      if (const auto fit = fit_conduction_velocity(beat_cells))
        per_beat.push_back({{"beat", beat}, {"cv_cm_per_s", fit->cv_cm_per_s}, {"r_squared", fit->r_squared},
                            {"cells_used", fit->cells_used}, {"window_um", {fit->from_um, fit->to_um}}});
    return per_beat;
  }

  json summary() const {
    json s;
    s["fibrodem_version"] = FIBRODEM_VERSION;
    s["name"] = scene.name;
    s["status"] = status;
    if (!error.empty()) s["error"] = error;
    s["manifest"] = scene.manifest;
    s["plugins"] = json::array();
    for (const auto& r : registry->loaded())
      s["plugins"].push_back({{"name", r.name}, {"version", r.version}, {"file", r.file.string()},
                              {"sha256", r.sha256}});
    s["effects"] = json::array();
    s["processes"] = json::array();
    for (const auto& p : plan.built) {
      s["effects"].push_back(p.name);
      s["processes"].push_back({{"name", p.name}, {"reason", p.reason}});
    }
    s["notes"] = plan.notes;
    s["warnings"] = warnings;
    s["integrator"] = integrator->describe();
    s["wall_time_s"] = wall_s;
    s["steps"] = steps;
    s["simulated_ms"] = times.empty() ? 0.0 : times.back();
    const auto myocytes = tissue.count(CellType::myocyte), fibroblasts = tissue.count(CellType::fibroblast);
    s["cells"] = {{"myocyte", myocytes}, {"fibroblast", fibroblasts}};
    s["fm_ratio"] = myocytes ? json(static_cast<double>(fibroblasts) / static_cast<double>(myocytes))
                             : json(nullptr);
    s["mean_biomarkers"] = mean_biomarkers();
    s["conduction"] = conduction();
    s["cv_cm_per_s"] = s["conduction"].empty() ? json(nullptr) : s["conduction"].back()["cv_cm_per_s"];
    s["peak_strain"] = mechanics ? json{{"xx", peak_strain[0]}, {"yy", peak_strain[1]}, {"xy", peak_strain[2]}}
                                 : json(nullptr);
    if (mechanics) s["mechanics_step_ms"] = mechanics_step_ms;  // the smallest step taken
    // Where the wall time went (s): the parts of the cell system, mechanics, the rest.
    s["wall_time_by_process_s"] = {{"ionic_models", system.seconds[CellSystem::kIonic]},
                                   {"coupling", system.seconds[CellSystem::kCoupling]},
                                   {"myofilament_models", system.seconds[CellSystem::kMyofilament]},
                                   {"mechanics", mechanics_seconds}};
    return s;
  }

  void write_summary() const {
    const fs::path tmp = out / "summary.json.tmp";
    {
      std::ofstream f(tmp, std::ios::trunc);
      f << summary().dump(2) << '\n';
    }
    fs::rename(tmp, out / "summary.json");  // atomic: never a half-written summary
  }
};

Simulation::Simulation(const Scene& scene, std::shared_ptr<PluginRegistry> registry, RunOptions options)
    : impl_(std::make_unique<Impl>(scene, std::move(registry), options)) {}
Simulation::~Simulation() = default;

void Simulation::run() { impl_->run(); }
const Tissue& Simulation::tissue() const { return impl_->tissue; }
const ProcessPlan& Simulation::processes() const { return impl_->plan; }
const std::vector<BeatBiomarkers>& Simulation::biomarkers() const { return impl_->beats; }
const std::vector<double>& Simulation::trace_times() const { return impl_->times; }
json Simulation::summary() const { return impl_->summary(); }
std::string Simulation::integrator_description() const { return impl_->integrator->describe(); }

std::vector<std::string> Simulation::trace_column_names() const {
  std::vector<std::string> names;
  for (const auto& c : impl_->columns) names.push_back(c.name());
  return names;
}
const std::vector<std::vector<double>>& Simulation::trace_samples() const { return impl_->samples; }

const std::vector<double>& Simulation::trace(const std::string& variable, int cell) const {
  for (std::size_t i = 0; i < impl_->columns.size(); ++i)
    if (impl_->columns[i].variable == variable && impl_->columns[i].cell == cell) return impl_->samples[i];
  throw std::out_of_range("no trace of '" + variable + "' for cell " + std::to_string(cell) +
                          " (add it to output.traces)");
}

}  // namespace fibrodem
