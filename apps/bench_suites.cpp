// `fibrodem bench`: Google Benchmark suites
// of the hot loops. Speed is measured here, never in timed tests. Reported
// counter: cell_steps_per_s (cells x steps / wall time, Hustad & Cai 2022).
#include <benchmark/benchmark.h>
#include <omp.h>

#include <iostream>
#include <memory>
#include <tuple>

#include "apps/commands.hpp"
#include "integrate/fixed_step.hpp"
#include "mechanics/dem_solver.hpp"
#include "model/plugin_registry.hpp"
#include "model/population.hpp"
#include "run/simulation.hpp"
#include "tissue/tissue_builder.hpp"

namespace fibrodem::cli {

namespace {

constexpr std::size_t kBlockCells = 10000;

Population block_of(std::shared_ptr<const CellModel> model, std::size_t cells = kBlockCells) {
  Population pop;
  pop.model = std::move(model);
  for (const auto& p : pop.info().parameters) pop.params.push_back(p.default_value);
  for (const auto& s : pop.info().states) pop.initial_state.push_back(s.initial);
  pop.voltage_state = pop.info().voltage_state;
  pop.cells.resize(cells);
  pop.reset();
  return pop;
}

// One evaluation of the model's derivatives over a block of 10^4 cells, on one
// thread (the kernel's own throughput; threads split blocks of cells); with
// lookup_tables the voltage_only gates' rates come from the table.
void evaluate_block(benchmark::State& state, std::shared_ptr<const CellModel> model, bool lookup_tables) {
  omp_set_num_threads(1);
  Population pop = block_of(std::move(model));
  if (lookup_tables && !pop.use_lookup_table()) {
    state.SkipWithError("the model marks no voltage_only gate");
    return;
  }
  for (auto _ : state) {
    pop.evaluate(0.0);
    benchmark::DoNotOptimize(pop.a.data());
    benchmark::ClobberMemory();
  }
  state.counters["cell_steps_per_s"] =
      benchmark::Counter(static_cast<double>(state.iterations() * kBlockCells), benchmark::Counter::kIsRate);
}

// A whole Rush-Larsen step over `cells` cells (10^4, or 5 x 10^4 to see that
// the cost per cell stays flat once the states outgrow the caches), one
// thread, as a run takes it: each block of cells updated right after its
// evaluation; with lookup_tables the tabulated gates advanced from the table's
// y_inf and exp(b dt) columns.
void rush_larsen_block(benchmark::State& state, std::shared_ptr<const CellModel> model, bool lookup_tables,
                       std::size_t cells) {
  omp_set_num_threads(1);
  constexpr double dt_ms = 0.01;
  Population pop = block_of(std::move(model), cells);
  if (lookup_tables) {
    if (!pop.use_lookup_table()) {
      state.SkipWithError("the model marks no voltage_only gate");
      return;
    }
    // As a run's integrator does: the table's Rush-Larsen columns where it has them.
    if (auto with_step = pop.table->with_rush_larsen_step(dt_ms)) {
      pop.table = with_step;
      pop.table_advances_gates = true;
    }
  }
  FixedStepIntegrator rl(FixedStepIntegrator::Rule::rush_larsen, dt_ms);
  for (auto _ : state) {
    pop.evaluate(0.0, [&](const BlockView& block) { rl.update_view(pop, block, dt_ms); }, false);
    benchmark::ClobberMemory();
  }
  state.counters["cell_steps_per_s"] =
      benchmark::Counter(static_cast<double>(state.iterations() * cells), benchmark::Counter::kIsRate);
}

// `beats` simulated seconds (beats at 1 Hz) of one cell, whole run: the wall
// time per iteration over `beats` is the wall time per simulated second.
// `variant` empty: the model's default parameter set.
void single_cell_beats_of(benchmark::State& state, const std::string& model, const std::string& variant,
                          bool myocyte, const json& solver, int beats) {
  const std::string type = myocyte ? "myocyte" : "fibroblast";
  json cell = {{"model", model}};
  if (!variant.empty()) cell["variant"] = variant;
  json m = {{"fibrodem", 1}, {"name", "bench"}, {"duration_ms", 1000 * beats},
            {"tissue", {{"builder", "single_cell"}, {"type", type}}},
            {"cells", {{type, cell}}},
            {"stimulus", json::array({{{"target", type}, {"start_ms", 50}, {"duration_ms", 2},
                                       {"amplitude_pA", myocyte ? 2000 : 20}}})},
            {"solver", solver},
            {"output", {{"traces", {{"cells", json::array()}}}}}};
  if (beats > 1) {
    m["stimulus"][0]["period_ms"] = 1000;
    m["stimulus"][0]["count"] = beats;
  }
  const Scene scene = parse_scene(m);
  auto registry = std::make_shared<PluginRegistry>();
  for (auto _ : state) {
    try {
      Simulation sim(scene, registry);
      sim.run();
      benchmark::DoNotOptimize(sim.biomarkers().data());
    } catch (const std::exception& e) {
      state.SkipWithError(e.what());
      break;
    }
  }
}

void single_cell_second(benchmark::State& state, std::string model, bool myocyte, json solver) {
  single_cell_beats_of(state, model, "", myocyte, solver, 1);
}

// One DEM step of the paper's full-size tissue (Table 1, contact detection on)
// while every myocyte shortens as in a twitch (lambda = 1 - 0.05 (1 - cos(2 pi
// t / 200 ms)), 10 % at its peak as in the Fig. 3 EM scene), at the solver's
// own step, on `threads` threads. The twitch starts at rest (lambda = 1), so
// the contact list is rebuilt about as often as in that scene (every ~110
// steps; a start mid-twitch would jump lambda on the first step and shake the
// tissue into a rebuild every few steps).
// Counter: particle_steps_per_s, per wall second (the main thread's CPU time
// would not count the other threads' work).
void dem_step(benchmark::State& state, std::string builder, int threads) {
  omp_set_num_threads(threads);
  json spec = {{"builder", builder}};
  JsonReader reader(spec, "tissue");
  const Tissue tissue = make_tissue_builder(reader)->build(1);
  DemSolver dem(tissue, DemSpec{});
  std::vector<double> ratio(tissue.cell_count(), 1.0);
  for (auto _ : state) {
    const double lambda = 1 - 0.05 * (1 - std::cos(2 * M_PI * dem.time_ms() / 200));
    for (std::size_t c = 0; c < tissue.cell_count(); ++c)
      if (tissue.type[c] == CellType::myocyte) ratio[c] = lambda;
    dem.set_cell_length_ratios(ratio);
    dem.step(dem.step_ms());
  }
  state.counters["particle_steps_per_s"] = benchmark::Counter(
      static_cast<double>(state.iterations() * tissue.particles.size()), benchmark::Counter::kIsRate);
  state.counters["particles"] = static_cast<double>(tissue.particles.size());
}

// The machine's memory bandwidth as STREAM's triad measures it (McCalpin
// 1995, IEEE TCCA Newsletter): a[i] = b[i] + s c[i] over three arrays of
// 256 MB each, far past any last-level cache, on `threads` threads (each
// array first touched by the threads that stream it). Bytes counted as
// STREAM counts them, 24 an element (two read, one written; the write's
// read for ownership left out). docs/topics/performance.md sets the large
// sheet's stepping against it.
void memory_triad(benchmark::State& state, int threads) {
  constexpr long kElements = 1L << 25;
  omp_set_num_threads(threads);
  std::unique_ptr<double[]> a(new double[kElements]), b(new double[kElements]), c(new double[kElements]);
#pragma omp parallel for schedule(static)
  for (long i = 0; i < kElements; ++i) a[i] = 0.0, b[i] = 1.0, c[i] = 2.0;
  const double s = 3.0;
  for (auto _ : state) {
#pragma omp parallel for schedule(static)
    for (long i = 0; i < kElements; ++i) a[i] = b[i] + s * c[i];
    benchmark::DoNotOptimize(a.get());
    benchmark::ClobberMemory();
  }
  state.SetBytesProcessed(state.iterations() * 24 * kElements);
}

}  // namespace

int bench_command(const char* program, const std::vector<std::string>& args) {
  PluginRegistry registry;
  std::vector<std::shared_ptr<const CellModel>> models;
  for (const auto& name : registry.available()) {
    auto model = registry.load(name);
    if (model->info().kind != ModelKind::ionic) continue;
    models.push_back(model);
    benchmark::RegisterBenchmark(("evaluate_block_1e4/" + name).c_str(), evaluate_block, model, false)
        ->Unit(benchmark::kMicrosecond);
    bool any_voltage_only = false;
    for (const auto& s : model->info().states) any_voltage_only = any_voltage_only || s.voltage_only;
    if (any_voltage_only)
      benchmark::RegisterBenchmark(("evaluate_block_1e4_lut/" + name).c_str(), evaluate_block, model, true)
          ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark(("rush_larsen_step_1e4/" + name).c_str(), rush_larsen_block, model, false,
                                 kBlockCells)
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark(("rush_larsen_step_5e4/" + name).c_str(), rush_larsen_block, model, false,
                                 5 * kBlockCells)
        ->Unit(benchmark::kMicrosecond);
    if (any_voltage_only)
      benchmark::RegisterBenchmark(("rush_larsen_step_1e4_lut/" + name).c_str(), rush_larsen_block, model, true,
                                   kBlockCells)
          ->Unit(benchmark::kMicrosecond);
    // The machine's own gain from threads: 10^4 cells on each thread, the
    // threads independent (no shared work, no waits between steps), cell-steps
    // summed over the threads per wall second. Two threads' figure over one's
    // is the most a perfectly split tissue step could gain on this machine now
    // (a host with other tenants, or cores sharing caches, gives less than 2x).
    benchmark::RegisterBenchmark(("rush_larsen_step_1e4_each_thread/" + name).c_str(), rush_larsen_block, model,
                                 false, kBlockCells)
        ->Unit(benchmark::kMicrosecond)
        ->UseRealTime()
        ->Threads(1)
        ->Threads(2);
    const bool myocyte = find_output(model->info(), "Ca_i") >= 0;
    benchmark::RegisterBenchmark(("one_cell_1s/" + name + "/cvode_rtol1e-6").c_str(), single_cell_second, name,
                                 myocyte, json{{"method", "cvode"}, {"rtol", 1e-6}, {"atol", 1e-8}})
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("one_cell_1s/" + name + "/rush_larsen_dt0.01").c_str(), single_cell_second, name,
                                 myocyte, json{{"method", "rush_larsen"}, {"dt_ms", 0.01}})
        ->Unit(benchmark::kMillisecond);
  }
  // CVODE on one myocyte at the two tolerance pairs compared with Myokit's
  // CVODES simulation (docs/topics/performance.md#cvode-against-myokit): CRN 1998 and
  // Ni 2017, one beat (set-up included) and ten (per simulated second, the
  // set-up shared by ten beats).
  const std::pair<const char*, const char*> cvode_cells[] = {{"courtemanche", ""}, {"colman", "ni2017"}};
  for (const auto& [model, variant] : cvode_cells) {
    const std::string label = std::string(model) + (*variant ? std::string("_") + variant : "");
    for (const auto& [rtol, atol, suffix] : {std::tuple{1e-6, 1e-8, "1e-6"}, std::tuple{1e-4, 1e-6, "1e-4"}}) {
      for (int beats : {1, 10}) {
        const std::string name =
            (beats == 1 ? "one_cell_1s/" : "one_cell_10s/") + label + "/cvode_rtol" + suffix;
        if (beats == 1 && label == model && std::string(suffix) == "1e-6") continue;  // registered above
        // (Copies: clang 14 cannot capture structured bindings.)
        const json solver{{"method", "cvode"}, {"rtol", rtol}, {"atol", atol}};
        const char *m = model, *v = variant;
        benchmark::RegisterBenchmark(name.c_str(), [=](benchmark::State& st) {
          single_cell_beats_of(st, m, v, true, solver, beats);
        })->Unit(benchmark::kMillisecond);
      }
    }
  }
  for (const char* builder : {"in_series", "interstitial"})
    for (int threads : {1, 2})
      benchmark::RegisterBenchmark(
          (std::string("dem_step/") + builder + (threads > 1 ? "/threads:" + std::to_string(threads) : "")).c_str(),
          dem_step, std::string(builder), threads)
          ->Unit(benchmark::kMicrosecond)
          ->UseRealTime();
  for (int threads : {1, 2})
    benchmark::RegisterBenchmark(("memory_triad/threads:" + std::to_string(threads)).c_str(), memory_triad, threads)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
  std::vector<std::string> storage = {program};
  storage.insert(storage.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& s : storage) argv.push_back(s.data());
  int argc = static_cast<int>(argv.size());
  benchmark::Initialize(&argc, argv.data());
  if (benchmark::ReportUnrecognizedArguments(argc, argv.data())) return 2;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

}  // namespace fibrodem::cli
