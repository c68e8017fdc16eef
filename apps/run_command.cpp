// `fibrodem run` and `fibrodem validate`.
#include <unistd.h>

#include <cstdlib>
#include <iostream>

#include "apps/commands.hpp"
#include "run/interrupt.hpp"
#include "run/simulation.hpp"

namespace fibrodem::cli {

namespace {

Scene load_scene(const RunArgs& args) {
  json manifest = read_manifest_file(args.manifest);
  for (const auto& assignment : args.overrides) apply_override(manifest, assignment);
  return parse_scene(manifest);
}

}  // namespace

int run_command(const RunArgs& args) {
  return guarded([&] {
    Scene scene = load_scene(args);
    if (!args.out.empty()) scene.output.dir = args.out;
    if (scene.output.dir.empty()) scene.output.dir = "out/" + scene.name;
    scene.output.overwrite = args.overwrite;
    RunOptions options;
    options.console_log = !args.quiet;
    // A progress line only for a person at a terminal, never in logs or CI.
    options.progress = !args.quiet && isatty(STDERR_FILENO) && std::getenv("CI") == nullptr;
    Simulation simulation(scene, nullptr, options);
    install_interrupt_handlers();  // SIGINT / SIGTERM end the run at the end of a step, outputs kept
    simulation.run();
    std::cout << "outputs: " << scene.output.dir << "/{summary.json,biomarkers.csv,traces.csv,run.log}\n";
    return 0;
  });
}

int validate_command(const RunArgs& args) {
  return guarded([&] {
    Scene scene = load_scene(args);
    scene.output.dir.clear();      // validating writes nothing
    Simulation simulation(scene);  // builds tissue, loads plugins, checks names; does not run
    const Tissue& tissue = simulation.tissue();
    std::cout << args.manifest << ": valid. " << tissue.cell_count() << " cells ("
              << tissue.count(CellType::myocyte) << " myocytes, " << tissue.count(CellType::fibroblast)
              << " fibroblasts); processes:";
    for (const auto& p : simulation.processes().built) std::cout << " " << p.name;
    std::cout << "; " << simulation.integrator_description() << "; " << simulation.resource_estimate() << "\n";
    return 0;
  });
}

}  // namespace fibrodem::cli
