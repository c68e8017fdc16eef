// `fibrodem restitution MANIFEST [--out DIR] [--intervals MS,...] [--cells
// I,...] [--jobs N]`: S1-S2 action-potential restitution and the effective
// refractory period (the engine: study/restitution.hpp). Each run is a
// `fibrodem run` process of its own (this executable), as a sweep's points.
#include <boost/dll/runtime_symbol_info.hpp>

#include <algorithm>
#include <cmath>
#include <iostream>

#include "apps/commands.hpp"
#include "scene/scene.hpp"
#include "study/restitution.hpp"

namespace fibrodem::cli {

int restitution_command(const RestitutionArgs& args) {
  return guarded([&] {
    json manifest = read_manifest_file(args.manifest);
    for (const auto& o : args.overrides) apply_override(manifest, o);
    RestitutionOptions options;
    options.out = args.out.empty() ? default_restitution_dir(manifest) : std::filesystem::path(args.out);
    options.runner = ChildProcessRunner{boost::dll::program_location().string()};
    options.jobs = args.jobs;
    options.intervals_ms = args.intervals_ms;
    options.cells = args.cells;
    options.erp_resolution_ms = args.resolution_ms;
    options.capture_fraction = args.capture_fraction;
    options.overwrite = args.overwrite;
    options.on_run_done = [](const RestitutionPoint& p) {
      std::cerr << "interval " << p.interval_ms << " ms: "
                << (!p.error.empty() ? "failed - " + p.error
                    : p.captured     ? "captured, APD90 " + std::to_string(p.s2_apd90_ms) + " ms at DI " +
                                       std::to_string(p.di_ms) + " ms"
                                     : "not captured")
                << (p.reused ? " (run before, kept)" : "") << "\n";
    };
    const RestitutionResult result = run_restitution(manifest, options);
    if (result.erp_ms)
      std::cout << "ERP: " << *result.erp_ms << " ms (the longest S1-S2 interval not captured)\n";
    else
      std::cout << "ERP: not bracketed (S2 was captured at every interval, or at none)\n";
    std::cout << result.points.size() << " runs\noutputs: " << options.out.string()
              << "/{restitution.csv,restitution.json,restitution.png,runs/}\n";
    const bool failed = std::any_of(result.points.begin(), result.points.end(),
                                    [](const RestitutionPoint& p) { return !p.error.empty(); });
    return failed ? 4 : 0;
  });
}

}  // namespace fibrodem::cli
