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
#include <csignal>
#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <type_traits>
#include <sstream>

#include "coupling/gap_junction.hpp"
#include "integrate/cell_system.hpp"
#include "integrate/integrator.hpp"
#include "integrate/stability.hpp"
#include "integrate/method_choice.hpp"
#include "run/cell_state_checkpoint.hpp"
#include "run/checkpoint_dir.hpp"
#include "run/interrupt.hpp"
#include "run/output_dir.hpp"
#include "run/resource_estimate.hpp"
#include "run/settle.hpp"
#include "mechanics/mechanics_solver.hpp"
#include "io/background_writer.hpp"
#include "io/csv_writer.hpp"
#include "run/population_setup.hpp"
#include "run/run_summary.hpp"
#include "run/tissue_snapshots.hpp"
#include "run/trace_recorder.hpp"
#include "report/run_report.hpp"

namespace fibrodem {
namespace fs = std::filesystem;

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// Adds the wall time of its scope to a total [s] (summary.json wall_time_by_process_s).
class ScopeTimer {
 public:
  explicit ScopeTimer(double& total) : total_(total), start_(Clock::now()) {}
  ~ScopeTimer() { total_ += seconds_since(start_); }
  ScopeTimer(const ScopeTimer&) = delete;
  ScopeTimer& operator=(const ScopeTimer&) = delete;

 private:
  double& total_;
  Clock::time_point start_;
};

// solver.threads "auto" shares the work between cores from this many cells on
// (two blocks of cells: 2 threads run a colman strand 1.47x faster at 512 cells;
// README "Speed").
constexpr std::size_t kCellsForThreads = 2 * kCellsPerBlock;

struct Simulation::Impl : StepObserver {
  Scene scene;
  RunOptions options;
  std::shared_ptr<PluginRegistry> registry;
  Tissue tissue;
  ProcessPlan plan;
  CellSystem system;
  std::unique_ptr<Integrator> integrator;
  std::shared_ptr<spdlog::logger> log;

  TraceRecorder traces;
  std::vector<BeatBiomarkers> beats;
  std::unique_ptr<BiomarkerTracker> tracker;

  fs::path out;
  CsvWriter biomarkers_csv;
  std::vector<std::string> warnings;  // found at set-up, logged when the run starts
  StabilityEstimate stability;
  std::string status = "set up";
  std::string error;
  double wall_s = 0;
  long long steps = 0;
  long long snapshots_taken = 0;
  std::unique_ptr<MechanicsSolver> mechanics;
  double mechanics_step_ms = 0, mechanics_time_ms = 0, mechanics_seconds = 0;
  // Cells' lengths relative to rest (SL / SL_rest) at the last cell step's
  // start and end, and as handed to a DEM step between them.
  std::vector<double> length_ratio_from, length_ratio_to, length_ratio;
  double length_ratio_from_ms = 0;
  std::array<double, 3> peak_strain{0, 0, 0};
  std::chrono::steady_clock::time_point started, last_progress, last_flush;
  double measurement_seconds = 0, output_seconds = 0, integrator_seconds = 0, set_up_seconds = 0;
  std::string solver_choice;  // why solver.method "auto" chose what it did (empty: a method was named)
  double t_reached_ms = 0;    // the end of the last step taken
  ResourceEstimate resources;
  int interrupted_by = 0;     // the signal that stopped the run, if one did
  // Checkpoints (output.checkpoint): their spacing (on the step grid of a
  // fixed-step method), the state a resumed run starts from, and its time.
  double checkpoint_every_ms = 0;
  std::optional<FoundCheckpoint> resume_point;
  double start_ms = 0;
  json last_checkpoint, resumed_from;
  // Fault injection for the tests of resume (FIBRODEM_TEST_KILL): SIGKILL at
  // this step, or halfway through writing this checkpoint (1 = the first).
  long long kill_at_step = -1, kill_in_checkpoint = -1, checkpoints_written = 0;
  BackgroundWriter writer;  // the tissue picture and the snapshots

  Impl(const Scene& s, std::shared_ptr<PluginRegistry> r, RunOptions o)
      : scene(s), options(o), registry(std::move(r)) {
    ScopeTimer timer(set_up_seconds);
    // Before any computation: a folder that cannot take the outputs stops here.
    if (!scene.output.dir.empty()) prepare_output_dir(scene.output.dir, scene.output.overwrite);
    if (!registry) {
      std::vector<fs::path> search(scene.plugin_path.begin(), scene.plugin_path.end());
      for (auto& dir : PluginRegistry::default_search_path()) search.push_back(std::move(dir));
      registry = std::make_shared<PluginRegistry>(std::move(search));
    } else if (!scene.plugin_path.empty()) {
      warnings.push_back("plugin_path ignored: this run was given its own plugin registry");
    }
    make_logger();
    tissue = scene.tissue->build(scene.seed);
    plan = plan_processes(scene, tissue);
    choose_solver();
    use_threads();
    build_populations();
    derive_contraction_from_traces();
    build_myofilaments();
    warn_of_shadowed_plugins();
    if (!scene.solver.simd) {
      system.for_each_population([](Population& pop) { pop.scalar_reference = true; });
      plan.notes.push_back("solver.simd false: cell models evaluated one cell at a time in double");
    }
    build_coupling();
    build_mechanics();
    system.stimulus = Stimulus(scene.stimuli, tissue);
    traces = TraceRecorder(scene, system, mechanics != nullptr, plan.has("contraction"));
    build_lookup_tables();
    set_state_limits();
    start_from_initial_state();
    integrator = make_integrator(scene.solver);
    check_explicit_stability();
    plan_checkpoints();
    guard_resources();
  }

  // A plugin earlier on the search path (plugin_path, FIBRODEM_PLUGIN_PATH)
  // hides any of the same name after it, such as a bundled one.
  void warn_of_shadowed_plugins() {
    for (const auto& record : registry->loaded())
      for (const auto& hidden : record.shadowed)
        warnings.push_back("plugin " + record.name + " loaded from " + record.file.string() + " hides " +
                           hidden.string() + ", of the same name later on the search path");
  }

  // initial_state: the cells start from another run's checkpoint (the same
  // tissue and models, or a CheckpointError naming what differs).
  void start_from_initial_state() {
    if (scene.initial_state.from.empty()) return;
    const std::string path = "initial_state.from";
    try {
      const FoundCheckpoint found = find_checkpoint(scene.initial_state.from, scene.initial_state.time_ms);
      try {
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

  // output.checkpoint: a fixed-step method's checkpoints fall on its steps
  // (and on its coupling steps), so that a resumed run takes the same steps.
  void plan_checkpoints() {
    checkpoint_every_ms = scene.output.checkpoint.every_ms;
    if (checkpoint_every_ms <= 0) return;
    if (scene.output.dir.empty()) {
      checkpoint_every_ms = 0;
      return;
    }
    if (scene.solver.fixed_step()) {
      const double quantum = scene.solver.dt_ms * std::max(1, system.coupling_every);
      checkpoint_every_ms = std::max(1.0, std::round(checkpoint_every_ms / quantum)) * quantum;
    }
    plan.notes.push_back(fmt::format("checkpoints every {:g} ms, the newest {} kept, in {}", checkpoint_every_ms,
                                     scene.output.checkpoint.keep,
                                     (fs::path(scene.output.dir) / "checkpoints").string()));
    if (const char* kill = std::getenv("FIBRODEM_TEST_KILL")) {
      long long n = 0;
      if (std::sscanf(kill, "step:%lld", &n) == 1) kill_at_step = n;
      else if (std::sscanf(kill, "checkpoint:%lld", &n) == 1) kill_in_checkpoint = n;
    }
  }

  // Before anything large is allocated (integrator buffers, traces, CVODE's
  // matrices): a scene that cannot fit is refused with the estimate.
  void guard_resources() {
    resources = estimate_resources(scene, tissue, system, mechanics != nullptr);
    check_resources(resources, available_memory_bytes(),
                    scene.output.dir.empty() ? std::numeric_limits<double>::infinity()
                                             : available_disk_bytes(scene.output.dir));
    plan.notes.push_back("resources: " + resources.describe());
  }

  // solver.method "auto": the method and its settings for the scene's size
  // and solver.accuracy; everything after sees the method chosen.
  void choose_solver() {
    if (scene.solver.method != "auto") return;
    const MethodChoice choice = choose_method(scene.solver, tissue.cell_count());
    scene.solver = choice.solver;
    solver_choice = choice.why;
    plan.notes.push_back("solver.method auto: " + choice.why);
  }

  // solver.threads: as asked, or ("auto") every core once the tissue has
  // enough blocks of cells to share; a smaller scene runs on one thread, where
  // waking a second costs more than it brings.
  void use_threads() {
    const int cores = std::max(1, omp_get_num_procs());
    int threads = scene.solver.threads;
    std::string why = "solver.threads = " + std::to_string(threads);
    if (threads == 0) {
      threads = cores;
      why = "solver.threads = 0: every core";
    } else if (threads < 0) {
      const bool large = tissue.cell_count() >= kCellsForThreads;
      threads = large ? cores : 1;
      why = fmt::format("solver.threads auto: {} cells {} {} ({} cores)", tissue.cell_count(), large ? ">=" : "<",
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

  // solver.lookup_tables: a table of the voltage_only gates' rates per ionic
  // population whose model marks any (after every parameter change above).
  void build_lookup_tables() {
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

  void make_logger() {
    std::vector<spdlog::sink_ptr> sinks;
    if (options.console_log) sinks.push_back(std::make_shared<spdlog::sinks::stderr_color_sink_mt>());
    if (sinks.empty()) sinks.push_back(std::make_shared<spdlog::sinks::null_sink_mt>());
    log = std::make_shared<spdlog::logger>("fibrodem", sinks.begin(), sinks.end());
    log->set_pattern("[%H:%M:%S.%e] [%l] %v");
    log->flush_on(spdlog::level::warn);  // a warning reaches run.log at once (and once a second: on_step)
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
      system.populations.push_back(make_population(type, spec->second.ionic, ModelKind::ionic, *registry, &warnings));
      settle(system.populations.back(), spec->second);
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

  // cells.TYPE.settle: the type's model alone before t = 0 (run/settle.hpp);
  // every cell of the type then starts from the settled states.
  void settle(Population& pop, const CellTypeSpec& spec) {
    if (spec.settle.ms <= 0) return;
    try {
      SettleResult settled = settle_cell(pop, spec.settle);
      pop.initial_state = std::move(settled.states);
      plan.notes.push_back(settled.note);
    } catch (const std::runtime_error& e) {
      throw ManifestError(join_path(spec.path, "settle"), e.what());
    }
  }

  void build_coupling() {
    if (!plan.has("coupling")) return;
    std::vector<double> capacitance(tissue.cell_count());
    for (std::size_t cell = 0; cell < tissue.cell_count(); ++cell)
      capacitance[cell] = system.populations[system.where[cell].first].capacitance_pF;
    system.coupler = std::make_unique<GapJunctionCoupler>(tissue, scene.coupling.D_m_nS,
                                                          scene.coupling.D_f_nS, capacitance);
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

  // Without a list of effects, a traced variable of a cell type's myofilament
  // model calls for contraction.
  void derive_contraction_from_traces() {
    if (scene.effects_listed || plan.has("contraction")) return;
    for (const auto& block : scene.output.traces.blocks) {
      for (const auto& var : block.variables)
        for (const auto& cell : block.cells) {
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
  }

  // One myofilament population per cell type that names one, over the same cells.
  void build_myofilaments() {
    if (!plan.has("contraction")) return;
    for (std::size_t p = 0; p < system.populations.size(); ++p) {
      Population& host = system.populations[p];
      const CellTypeSpec& spec = scene.cells.at(host.type);
      if (!spec.myofilament) continue;
      Myofilament m;
      m.pop = make_population(host.type, *spec.myofilament, ModelKind::myofilament, *registry, &warnings);
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
    length_ratio_from = length_ratio_to = length_ratio;
  }

  void check_explicit_stability() {
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

  // ---- the run --------------------------------------------------------------

  // A resumed run appends to run.log and continues traces.csv and
  // biomarkers.csv from the checkpoint's lengths (restore()).
  void open_outputs() {
    if (scene.output.dir.empty()) return;
    out = scene.output.dir;
    fs::create_directories(out);
    auto file_sink =
        std::make_shared<spdlog::sinks::basic_file_sink_mt>((out / "run.log").string(), !resume_point);
    file_sink->set_pattern("[%Y-%m-%d %H:%M:%S.%e] [%l] %v");
    log->sinks().push_back(file_sink);
    if (!resume_point) {
      clear_checkpoints(out);  // an earlier run's, in a folder given --overwrite
      traces.open_csv(out / "traces.csv");
      biomarkers_csv = CsvWriter(out / "biomarkers.csv",
                                 {"cell", "type", "beat", "activation_ms", "rmp_mV", "apo_mV", "apd90_ms",
                                  "dvdt_max_mV_per_ms"});
      // (The tissue stays as built: the writer may draw it while the run starts.)
      if (scene.output.tissue_picture) write_file([this] { write_tissue_overview(out, scene.name, tissue); });
    }
    write_summary(out, summary());
  }

  // ---- checkpoints --------------------------------------------------------

  // Everything the run holds at t (the end of a step, between integrator
  // segments), for a checkpoint.
  CheckpointFields checkpoint_fields(double t) {
    CheckpointFields f;
    f.put("run.time_ms", t);
    f.put_text("run.scene", scene.manifest.dump(-1, ' ', false, json::error_handler_t::replace));
    f.put_integer("run.steps", steps);
    f.put_integer("run.snapshots_taken", snapshots_taken);
    static_assert(std::is_trivially_copyable_v<BeatBiomarkers>);
    f.put_integer("run.beat_bytes", static_cast<long long>(sizeof(BeatBiomarkers)));
    f.put_bytes("run.beats", beats.data(), beats.size() * sizeof(BeatBiomarkers));
    if (biomarkers_csv.is_open()) f.put_integer("run.biomarkers_csv_bytes", static_cast<long long>(biomarkers_csv.bytes_written()));
    save_cell_states(system, f);
    tracker->save(f);
    traces.save(f);
    if (mechanics) {
      mechanics->save(f);
      f.put("run.mechanics", std::vector<double>{mechanics_time_ms, mechanics_step_ms, length_ratio_from_ms,
                                                 peak_strain[0], peak_strain[1], peak_strain[2]});
      f.put("run.length_ratio_from", length_ratio_from);
      f.put("run.length_ratio_to", length_ratio_to);
    }
    return f;
  }

  // The run as a checkpoint left it (the scene must be the one it was written for).
  void restore(const CheckpointFields& f) {
    if (f.text("run.scene") != scene.manifest.dump(-1, ' ', false, json::error_handler_t::replace))
      throw CheckpointError("it was written for another scene (its manifest differs from summary.json's)");
    start_ms = t_reached_ms = f.number("run.time_ms");
    if (!(start_ms >= 0 && start_ms <= scene.duration_ms))
      throw CheckpointError(fmt::format("its time, {} ms, is outside this scene's [0, {}] ms", start_ms,
                                        scene.duration_ms));
    steps = f.integer("run.steps");
    snapshots_taken = f.integer("run.snapshots_taken");
    if (f.integer("run.beat_bytes") != static_cast<long long>(sizeof(BeatBiomarkers)))
      throw CheckpointError("its biomarkers were written by another build of fibrodem");
    restore_beats(f);
    load_cell_states(system, f, true);
    tracker->load(f);
    traces.load(f, out.empty() ? fs::path() : out / "traces.csv");
    if (!out.empty())
      biomarkers_csv = CsvWriter::resume(out / "biomarkers.csv", static_cast<std::uintmax_t>(f.integer("run.biomarkers_csv_bytes")));
    if (mechanics) {
      mechanics->load(f);
      const auto m = f.numbers("run.mechanics", 6);
      mechanics_time_ms = m[0], mechanics_step_ms = m[1], length_ratio_from_ms = m[2];
      // The mechanics is at most one of its steps behind the cells.
      if (!(mechanics_time_ms <= start_ms + kTimeEpsilon_ms && mechanics_time_ms >= start_ms - 1.0 &&
            length_ratio_from_ms == start_ms))
        throw CheckpointError("its mechanics' time does not match its cells'");
      peak_strain = {m[3], m[4], m[5]};
      f.read_into("run.length_ratio_from", length_ratio_from);
      f.read_into("run.length_ratio_to", length_ratio_to);
    }
  }

  // The beats measured so far, each checked (a cell of the tissue, its type)
  // before it is taken: a byte of a type must not become an invalid enum.
  void restore_beats(const CheckpointFields& f) {
    const std::string raw = f.text("run.beats");
    if (raw.size() % sizeof(BeatBiomarkers) != 0) throw CheckpointError("its biomarkers are cut short");
    beats.resize(raw.size() / sizeof(BeatBiomarkers));
    for (std::size_t i = 0; i < beats.size(); ++i) {
      const char* beat = raw.data() + i * sizeof(BeatBiomarkers);
      int cell = 0;
      std::underlying_type_t<CellType> type{};
      std::memcpy(&cell, beat + offsetof(BeatBiomarkers, cell), sizeof cell);
      std::memcpy(&type, beat + offsetof(BeatBiomarkers, type), sizeof type);
      if (cell < 0 || static_cast<std::size_t>(cell) >= tissue.cell_count() ||
          type != static_cast<std::underlying_type_t<CellType>>(tissue.type[static_cast<std::size_t>(cell)]))
        throw CheckpointError("its biomarkers name a cell this tissue does not have");
      std::memcpy(static_cast<void*>(&beats[i]), beat, sizeof(BeatBiomarkers));
    }
  }

  // Every output up to t on disk first (pictures included), then the state.
  void write_checkpoint(double t) {
    ScopeTimer timer(output_seconds);
    writer.finish();
    const fs::path file = checkpoint_path(out, t);
    fs::create_directories(file.parent_path());
    ++checkpoints_written;
    const bool kill = checkpoints_written == kill_in_checkpoint;
    write_checkpoint_file(file, checkpoint_fields(t), [kill] {
      if (kill) std::raise(SIGKILL);
    });
    prune_checkpoints(out, scene.output.checkpoint.keep);
    last_checkpoint = {{"file", fs::relative(file, out).string()}, {"time_ms", t}};
    log->info("checkpoint at t = {:g} ms: {}", t, file.string());
    write_summary(out, summary());
  }

  // The run's stretch [start_ms, duration] cut at the checkpoint times; the
  // integrator starts afresh at each (as at a stimulus edge), in a resumed
  // run as in one never stopped.
  void advance_in_segments() {
    if (checkpoint_every_ms <= 0) return integrator->advance(system, start_ms, scene.duration_ms, *this);
    double t = start_ms;
    for (long long k = std::llround(start_ms / checkpoint_every_ms) + 1; t < scene.duration_ms - kTimeEpsilon_ms; ++k) {
      const double next = std::min(static_cast<double>(k) * checkpoint_every_ms, scene.duration_ms);
      integrator->advance(system, t, next, *this);
      t = next;
      write_checkpoint(t);
    }
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
      // What the model says of itself (an imported model: how its V and stimulus were found).
      if (!pop.info().description.empty())
        log->info("{}: model {}: {}", cell_type_name(pop.type), pop.info().name, pop.info().description);
    });
    if (mechanics)
      log->info("mechanics: DEM, contact law {}, step {:.4g} ms (stable {:.4g} ms), subcycled against the "
                "cells' steps", scene.mechanics.contact_law, mechanics_step_ms, mechanics->stable_step_ms());
    if (system.sac.on)
      log->info("stretch-activated current: G = {} nS, E = {} mV, lambda_max = {}", system.sac.G_nS, system.sac.E_mV,
                system.sac.lambda_max);
    if (system.coupler)
      log->info("coupling: gap junctions, D_m = {} nS, D_f = {} nS, {}", scene.coupling.D_m_nS, scene.coupling.D_f_nS,
                !scene.solver.fixed_step()     ? std::string("in the integrator's implicit solve")
                : system.implicit_coupling     ? fmt::format("backward Euler (split), every {} cell step(s)",
                                                             system.coupling_every)
                                               : fmt::format("explicit, updated every {} cell step(s)",
                                                             system.coupling_every));
    log->info("integrator: {}; {} threads", integrator->describe(), system.thread_governor().chosen());
    for (const auto& w : warnings) log->warn("{}", w);
  }

  double next_sample_ms() const override { return traces.next_sample_ms(); }

  void on_sample(double t) override {
    ScopeTimer timer(output_seconds);
    traces.sample(t, system, mechanics.get());
  }

  // The biomarkers of most steps are measured on the step's threads. (The
  // first thread's time here counts as measurement, not as ionic models.)
  void on_step_voltages(double t_old, double t_new, const double* V_new, std::size_t begin,
                        std::size_t end) override {
    if (!tracker->steps_by_range(t_new)) return;  // on_step measures the step whole
    if (begin != 0) return tracker->step_cells(t_old, t_new, V_new, begin, end);
    const auto start = Clock::now();
    tracker->step_cells(t_old, t_new, V_new, begin, end);
    const double took_s = std::chrono::duration<double>(Clock::now() - start).count();
    measurement_seconds += took_s;
    system.seconds[CellSystem::kIonic] -= took_s;
  }

  void on_step(double t_old, double t_new, const double* dVdt) override {
    ++steps;
    if (steps == kill_at_step) std::raise(SIGKILL);
    t_reached_ms = t_new;
    // Few clock readings per step: a single cell steps in about a microsecond.
    const auto start = Clock::now();
    check_states(t_new);
    if (!system.voltage_fresh) system.gather_voltage();
    if (!(system.voltages_observed && tracker->steps_by_range(t_new)))  // else done in on_step_voltages
      tracker->step(t_old, t_new, system.V_mV.data(), dVdt);
    auto measured = Clock::now();
    measurement_seconds += std::chrono::duration<double>(measured - start).count();
    if (mechanics) {
      advance_mechanics(t_new);  // times itself
      measured = Clock::now();
    }
    snapshot_if_due(t_new);
    reclaim_writer_core();
    if (measured - last_flush > std::chrono::seconds(1)) {
      traces.flush_csv();
      log->flush();
      last_flush = measured;
    }
    report_progress(measured, t_new);
    output_seconds += seconds_since(measured);
    // SIGINT / SIGTERM: stop here, at the end of a step (run() writes everything).
    if (const int signal = interrupt_signal())
      throw InterruptedError(signal, fmt::format("interrupted by {} at t = {} ms", signal_name(signal), t_new));
  }

  void snapshot_if_due(double t) {
    const SnapshotSpec& snap = scene.output.snapshots;
    if (out.empty() || snap.every_ms <= 0) return;
    const double next = snap.from_ms + static_cast<double>(snapshots_taken) * snap.every_ms;
    if (t >= next - kTimeEpsilon_ms) {
      // Drawn on the writer's thread while the run goes on.
      // (The tissue itself is shared with the frame, not copied: the writer
      // finishes before the simulation, and so the tissue, goes.)
      const std::shared_ptr<const Tissue> built(std::shared_ptr<void>(), &tissue);
      auto frame = std::make_shared<SnapshotFrame>(take_snapshot(t, snap, built, mechanics.get(), system.V_mV));
      write_file([this, frame] { write_snapshot(out, scene.output.snapshots, scene.name, *frame); });
      ++snapshots_taken;
    }
  }

  // A picture or snapshot file, on the writer's thread while the run goes
  // on. When the cells' threads hold every core, one of them is lent to the
  // writer until it is done (the cells step on one thread fewer meanwhile):
  // the cells' threads wait for each other every step, so a writer sharing a
  // core with one of them stalls both (in the Fig. 3 run on 2 cores its
  // pictures cost about twice their own time that way).
  void write_file(std::function<void()> job) {
    writer.post(std::move(job));
    ThreadGovernor& governor = system.thread_governor();
    if (governor.lent() == 0 && governor.threads() > 1 && governor.threads() >= omp_get_num_procs())
      governor.lend(1);
  }

  // The core lent to the writer back to the cells once its pictures are done.
  void reclaim_writer_core() {
    ThreadGovernor& governor = system.thread_governor();
    if (governor.lent() > 0 && writer.idle()) governor.lend(0);
  }

  // The progress line (RunOptions::progress) and callback (on_progress), every
  // output.progress_every_s of wall time.
  void report_progress(std::chrono::steady_clock::time_point now, double t_new) {
    if ((options.progress || options.on_progress) && scene.output.progress_every_s > 0 &&
        std::chrono::duration<double>(now - last_progress).count() >= scene.output.progress_every_s) {
      last_progress = now;
      if (options.on_progress) options.on_progress(t_new);
      if (!options.progress) return;
      const double elapsed = std::chrono::duration<double>(now - started).count();
      const double left = elapsed / t_new * (scene.duration_ms - t_new);
      std::fprintf(stderr, "\r  t = %.1f / %.1f ms   %.3g ms simulated per s   about %.0f s left   ",
                   t_new, scene.duration_ms, t_new / elapsed, left);
      std::fflush(stderr);
    }
  }

  // Mechanics at its own step up to t (the end of a cell step). Each DEM step
  // takes the cells' lengths interpolated linearly in time across the cell
  // step: a cell step of the adaptive method may span many DEM steps.
  void advance_mechanics(double t) {
    if (!mechanics) return;
    const auto start = std::chrono::steady_clock::now();
    length_ratio_to = system.stretch_by_cell();
    const double span = t - length_ratio_from_ms;
    for (double h = mechanics->step_ms(); mechanics_time_ms + h <= t + kTimeEpsilon_ms; h = mechanics->step_ms()) {
      const double w = span > 0 ? std::clamp((mechanics_time_ms + h - length_ratio_from_ms) / span, 0.0, 1.0) : 1.0;
      for (std::size_t cell = 0; cell < tissue.cell_count(); ++cell)
        length_ratio[cell] = length_ratio_from[cell] + w * (length_ratio_to[cell] - length_ratio_from[cell]);
      mechanics->set_cell_length_ratios(length_ratio);
      mechanics->step(h);
      mechanics_time_ms += h;
      mechanics_step_ms = std::min(mechanics_step_ms, h);
      const auto strain = mechanics->strain();
      for (int k = 0; k < 3; ++k)
        if (std::abs(strain[k]) > std::abs(peak_strain[k])) peak_strain[k] = strain[k];
    }
    std::swap(length_ratio_from, length_ratio_to);
    length_ratio_from_ms = t;
    mechanics_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  // A state outside its physical range (or NaN/Inf) stops the run. The range
  // is widened by round-off (1e-6 relative) and, for CVODE, by its error
  // tolerance: a gate at 1 + 1e-6 after a BDF step at rtol 1e-6 is not a blow-up.
  // (The fixed-step integrators check them as they update them; the scan
  // below then runs only to name the state that left its range.)
  void set_state_limits() {
    const bool cvode = scene.solver.method == "cvode";
    // Ten times CVODE's local error bound rtol |y| + atol at the bound.
    auto slack = [&](double bound) {
      const double scale = std::max(1.0, std::abs(bound));
      return std::max(1e-6 * scale, cvode ? 10 * (scene.solver.rtol * scale + scene.solver.atol) : 0.0);
    };
    system.for_each_population([&](Population& pop) {
      pop.lower_limit.clear();
      pop.upper_limit.clear();
      for (const StateInfo& state : pop.info().states) {
        pop.lower_limit.push_back(state.lower - slack(state.lower));
        pop.upper_limit.push_back(state.upper + slack(state.upper));
      }
    });
  }

  void check_states(double t) {
    if (system.states_checked && system.states_in_limits) return;
    system.for_each_population([&](const Population& pop) {
      const std::size_t n = pop.size();
      for (std::size_t k = 0; k < pop.n_states(); ++k) {
        const double* y = pop.y.data() + k * n;
        for (std::size_t c = 0; c < n; ++c)
          if (!(y[c] >= pop.lower_limit[k] && y[c] <= pop.upper_limit[k])) blow_up(t, pop, k, c, y[c]);
      }
    });
  }

  // A blow-up at a step this many times below the stability estimate is
  // blamed on the model: the case was 300x; 10x leaves no doubt that
  // an explicit scheme is stable there.
  static constexpr double kModelBlameFactor = 10;

  std::string plugin_file(const Population& pop) const {
    for (const auto& r : registry->loaded())
      if (r.name == pop.info().name) return r.file.string();
    return "plugin";
  }

  // "V = -80.1 mV, n = nan, ...": every state of local cell c.
  static std::string cell_states(const Population& pop, std::size_t c) {
    std::string s;
    for (std::size_t k = 0; k < pop.n_states(); ++k)
      s += (k ? ", " : "") + pop.info().states[k].name + " = " + format_number(pop.state(static_cast<int>(k), c)) +
           (pop.info().states[k].unit.empty() || pop.info().states[k].unit == "1" ? "" : " " + pop.info().states[k].unit);
    return s;
  }

  [[noreturn]] void blow_up(double t, const Population& pop, std::size_t k, std::size_t c, double value) const {
    std::ostringstream s;
    s << "blow-up at t = " << format_number(t) << " ms: cell " << pop.cells[c] << " ("
      << cell_type_name(pop.type) << ", model " << pop.info().name << "), state '" << pop.info().states[k].name
      << "' = " << format_number(value) << " " << pop.info().states[k].unit << ", expected within ["
      << format_number(pop.info().states[k].lower) << ", " << format_number(pop.info().states[k].upper)
      << "]";
    // A step far below the estimated stability limit (or with none: gates by
    // Rush-Larsen, no explicit coupling) is not what went wrong: the model is.
    const double dt = scene.solver.dt_ms;
    if (scene.solver.fixed_step() && dt * kModelBlameFactor <= stability.limit_ms()) {
      s << "; the step (solver.dt_ms = " << format_number(dt) << " ms) is "
        << (std::isfinite(stability.limit_ms())
                ? fmt::format("{:.3g}x below the estimated explicit stability limit ({:.3g} ms)",
                              stability.limit_ms() / dt, stability.limit_ms())
                : std::string("not limited by any explicit stability estimate (gates by Rush-Larsen, no explicit "
                              "coupling)"))
        << ", so the model is the likely cause, not the step: model " << pop.info().name << " (" << plugin_file(pop)
        << ") took '" << pop.info().states[k].name << "' there. The cell's states after that step (each finite one "
        << "is its last finite value; a non-finite one had a non-finite rate in that step): " << cell_states(pop, c)
        << ". Check the model with: fibrodem check-plugin " << pop.info().name;
    } else if (scene.solver.fixed_step()) {
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
      {
        ScopeTimer timer(output_seconds);
        open_outputs();
        log_setup();
      }
      tracker = std::make_unique<BiomarkerTracker>(
          tissue.type, system.stimulus.onsets(scene.duration_ms), scene.output.biomarkers_from_ms,
          [this](const BeatBiomarkers& b) { record_beat(b); });
      if (scene.output.rmp_method == "pre_upstroke")
        tracker->use_pre_upstroke_rmp(scene.output.rmp_window_ms, scene.output.rmp_gap_ms);
      system.record_rest_lengths();
      if (resume_point) {
        resume();
      } else {
        system.gather_voltage();
        tracker->start(0.0, system.V_mV.data());
      }
      try {
        advance_and_time_integrator();
      } catch (const InterruptedError& e) {
        status = "interrupted";
        error = e.what();
        interrupted_by = e.signal();
        log->warn("{}: stopping with every output written", error);
      }
      tracker->finish();
      ScopeTimer timer(output_seconds);
      if (!out.empty() && scene.output.maps) write_maps(out, scene.name, tissue, beats);
      writer.finish();
      if (status == "running") status = "completed";
    } catch (const std::exception& e) {
      status = "failed";
      error = e.what();
      finish_writing();
    }
    if (options.progress) std::fprintf(stderr, "\n");
    wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    try {
      traces.flush_csv();  // the last rows: a full disk shows here at the latest
    } catch (const std::exception& e) {
      if (status != "failed") status = "failed", error = e.what();
    }
    log_run_end();
    if (!out.empty()) {
      std::error_code ignored;
      write_summary(out, summary());
      if (scene.output.report) write_report();
      else fs::remove(out / "report.html", ignored);  // an earlier run's, overwritten, would mislead
      log->info("outputs in {}", fs::absolute(out).string());
    }
    log->flush();
    if (status == "failed") throw std::runtime_error(error);
    if (status == "interrupted") throw InterruptedError(interrupted_by, error);
  }

  // report.html from the folder as written (a failed or interrupted run's
  // too); its own time goes into summary.json as report_time_s, so its cost
  // beside the run's wall time can be read off every run. A report that
  // cannot be written is a warning: the run's results stand.
  void write_report() {
    log->flush();  // the report shows run.log
    const auto start = Clock::now();
    try {
      write_run_report(out);
    } catch (const std::exception& e) {
      log->warn("report.html not written: {}", e.what());
    }
    const double report_s = seconds_since(start);
    log->info("report.html written in {:.3f} s ({:.2f} % of the run's wall time)", report_s,
              wall_s > 0 ? 100 * report_s / wall_s : 0.0);
    json s = summary();
    s["report_time_s"] = report_s;
    write_summary(out, s);
  }

  void resume() {
    try {
      restore(resume_point->fields);
    } catch (const CheckpointError& e) {
      throw CheckpointError("checkpoint " + resume_point->file.string() + " does not fit this run: " + e.what());
    }
    for (const auto& skipped : resume_point->skipped) log->warn("resume: passed over {}", skipped);
    resumed_from = {{"file", fs::relative(resume_point->file, out).string()}, {"time_ms", start_ms}};
    log->info("resumed from checkpoint {} at t = {:g} ms", resume_point->file.string(), start_ms);
  }

  // A failed run keeps what was written: the pictures already taken are
  // finished (an error in them is logged; the run's own error stands).
  void finish_writing() {
    try {
      writer.finish();
    } catch (const std::exception& e) {
      warnings.push_back(std::string("picture not written: ") + e.what());
    }
  }

  // The integrator's own time: its wall time less what the models, coupling,
  // the observer (measurement, output, mechanics) took within it.
  void advance_and_time_integrator() {
    auto others = [&] {
      return system.seconds[0] + system.seconds[1] + system.seconds[2] + measurement_seconds + output_seconds +
             mechanics_seconds;
    };
    const double before = others();
    const auto start = Clock::now();
    auto charge = [&] { integrator_seconds += std::max(0.0, seconds_since(start) - (others() - before)); };
    try {
      advance_in_segments();
    } catch (...) {
      charge();  // a failed run reports its time too
      throw;
    }
    charge();
  }

  // Clamped lookup tables, mechanics' report, and how the run ended.
  void log_run_end() {
    for (const auto& pop : system.populations)
      if (pop.table && pop.table->clamp_count() > 0)
        log->warn("lookup tables: {} model {}: V left the table [{:g}, {:g}] mV in {} cell evaluations "
                  "(rates clamped to the table's ends)",
                  cell_type_name(pop.type), pop.info().name, pop.table->v_min(), pop.table->v_max(),
                  pop.table->clamp_count());
    if (mechanics) log->info("mechanics: {}", mechanics->report());
    if (const auto& governor = system.thread_governor(); governor.adapting())
      log->info("threads auto: the cell models' loop ran {} steps on {} threads and {} on one ({} switches)",
                governor.calls_on_more(), governor.max_threads(), governor.calls_on_one(), governor.switches());
    if (const auto report = integrator->report(); !report.empty()) log->info("integrator: {}", report);
    if (status == "failed") log->error("run failed: {}", error);
    else if (status == "interrupted")
      log->warn("run interrupted: {} of {} ms simulated in {:.3f} s wall, {} steps", t_reached_ms, scene.duration_ms,
                wall_s, steps);
    else log->info("run completed: {} ms simulated in {:.3f} s wall, {} steps", scene.duration_ms, wall_s, steps);
  }

  // ---- summary ----------------------------------------------------------------

  json summary() const {
    return run_summary({.scene = scene,
                        .registry = *registry,
                        .plan = plan,
                        .warnings = warnings,
                        .integrator = integrator->describe(),
                        .solver_choice = solver_choice,
                        .simulated_ms = t_reached_ms,
                        .status = status,
                        .error = error,
                        .wall_s = wall_s,
                        .steps = steps,
                        .tissue = tissue,
                        .system = system,
                        .beats = beats,
                        .mechanics = mechanics != nullptr,
                        .peak_strain = peak_strain,
                        .mechanics_step_ms = mechanics_step_ms,
                        .mechanics_seconds = mechanics_seconds,
                        .measurement_seconds = measurement_seconds,
                        .output_seconds = output_seconds,
                        .integrator_seconds = integrator_seconds,
                        .set_up_seconds = set_up_seconds,
                        .last_checkpoint = last_checkpoint,
                        .resumed_from = resumed_from});
  }
};

Simulation::Simulation(const Scene& scene, std::shared_ptr<PluginRegistry> registry, RunOptions options)
    : impl_(std::make_unique<Impl>(scene, std::move(registry), options)) {}
Simulation::~Simulation() = default;

void Simulation::run() { impl_->run(); }
void Simulation::resume_from(FoundCheckpoint checkpoint) { impl_->resume_point = std::move(checkpoint); }
const Tissue& Simulation::tissue() const { return impl_->tissue; }
const ProcessPlan& Simulation::processes() const { return impl_->plan; }
const std::vector<BeatBiomarkers>& Simulation::biomarkers() const { return impl_->beats; }
const std::vector<double>& Simulation::trace_times() const { return impl_->traces.times(); }
json Simulation::summary() const { return impl_->summary(); }
std::string Simulation::integrator_description() const { return impl_->integrator->describe(); }

std::string Simulation::resource_estimate() const { return impl_->resources.describe(); }

std::vector<std::string> Simulation::trace_column_names() const { return impl_->traces.column_names(); }
const std::vector<std::vector<double>>& Simulation::trace_samples() const { return impl_->traces.samples(); }

const std::vector<double>& Simulation::trace(const std::string& variable, int cell) const {
  return impl_->traces.trace(variable, cell);
}

}  // namespace fibrodem
