// `fibrodem sweep SWEEP.json [--out DIR] [--jobs N] [--set P=V]...`: runs a
// manifest over the Cartesian product of parameter values (and tissue seeds)
// and tabulates the results (the engine: study/sweep.hpp).
//
// Each point runs as a `fibrodem run` process of its own (this executable),
// so a point that crashes cannot take the others down.
// Past one machine: under `mpirun -n N`, run k goes to rank k mod N (each
// rank a local pool of workers), and rank 0 writes the tables: the same
// numbers as a local sweep.
#include <boost/dll/runtime_symbol_info.hpp>

#include <iostream>
#include <thread>

#include "apps/commands.hpp"
#include "apps/mpi_ranks.hpp"
#include "study/sweep.hpp"

namespace fibrodem::cli {

namespace {

// A run's outcome as text for gathering to rank 0, and back.
json outcome_json(std::size_t k, const SweepRun& r) {
  return {{"run", k}, {"summary", r.summary}, {"status", r.status}, {"error", r.error}, {"reused", r.reused}};
}

void take_outcome(const json& j, std::vector<SweepRun>& runs) {
  SweepRun& r = runs.at(j.at("run").get<std::size_t>());
  r.summary = j.at("summary");
  r.status = j.at("status").get<std::string>();
  r.error = j.at("error").get<std::string>();
  r.reused = j.at("reused").get<bool>();
}

}  // namespace

int sweep_command(const SweepArgs& args) {
  return guarded([&] {
    const MpiRanks ranks;
    const SweepFile sweep = load_sweep_file(args.sweep, args.overrides);
    std::vector<SweepRun> runs = sweep_points(sweep);
    SweepOptions options;
    options.out = args.out.empty() ? default_sweep_dir(sweep) : std::filesystem::path(args.out);
    options.runner = ChildProcessRunner{boost::dll::program_location().string()};
    options.overwrite = args.overwrite;
    options.report = !args.no_report;
    // This rank's runs (all of them without MPI), over a pool of workers
    // sharing this machine's cores with the other ranks here.
    std::vector<std::size_t> mine;
    for (std::size_t k = static_cast<std::size_t>(ranks.rank()); k < runs.size(); k += static_cast<std::size_t>(ranks.size()))
      mine.push_back(k);
    const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
    options.jobs = args.jobs > 0 ? args.jobs : std::max(1u, cores / static_cast<unsigned>(ranks.on_this_host()));
    options.on_point_done = [&](std::size_t k, const SweepRun& run) {
      std::cerr << "run " << k + 1 << "/" << runs.size()
                << (run.reused ? " done before (same manifest): kept"
                    : run.status == "completed" ? " done"
                                                : " " + run.status + ": " + run.error)
                << "\n";
    };
    run_sweep_points(sweep, runs, mine, options);

    // Under MPI, rank 0 gathers the other ranks' outcomes and tabulates.
    if (ranks.launched()) {
      json outcomes = json::array();
      for (std::size_t k : mine) outcomes.push_back(outcome_json(k, runs[k]));
      const auto gathered = ranks.gather(outcomes.dump(-1, ' ', false, json::error_handler_t::replace));
      if (ranks.rank() != 0) return 0;
      for (const auto& text : gathered)
        for (const auto& j : json::parse(text)) take_outcome(j, runs);
    }
    const SweepResult result = tabulate_sweep(sweep, std::move(runs), options);
    std::cout << result.markdown << "\n";
    if (result.reused > 0)
      std::cout << result.reused << " of " << result.runs.size()
                << " runs completed before with the same manifest: kept, not run again\n";
    if (ranks.launched()) std::cout << "over " << ranks.size() << " MPI ranks\n";
    std::cout << "outputs: " << options.out.string() << "/{sweep.csv,sweep.md,"
              << (sweep.seeds.empty() ? "" : "sweep_stats.csv,") << "sweep.png,"
              << (args.no_report ? "" : "report.html,") << "run_*/}\n";
    return result.all_completed() ? 0 : 4;
  });
}

}  // namespace fibrodem::cli
