// `fibrodem restitution MANIFEST [--out DIR] [--intervals MS,...] [--cells
// I,...] [--jobs N]`: S1-S2 action-potential restitution and the effective
// refractory period (the engine: study/restitution.hpp). Each run is a
// `fibrodem run` process of its own (this executable), as a sweep's points.
#include <CLI/CLI.hpp>
#include <boost/dll/runtime_symbol_info.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iostream>

#include "apps/commands.hpp"
#include "scene/scene.hpp"

namespace fibrodem::cli {

CLI::App* add_restitution_subcommand(CLI::App& app, RestitutionArgs& args) {
  namespace option = study_option;
  RestitutionOptions& o = args.options;
  auto* sub = app.add_subcommand("restitution", "S1-S2 action-potential restitution: APD90 and APD50 of S2 (stimulus[1]) against the diastolic interval, and the effective refractory period");
  sub->add_option("manifest", args.manifest, "manifest with S1 (stimulus[0], a train with count) and S2 (stimulus[1])")->required();
  sub->add_option("--out", args.input.out, "output directory (default out/restitution_NAME)");
  sub->add_option(option::intervals.flag, o.intervals_ms, "S1-S2 coupling intervals [ms], comma-separated (default: the S1 period, then 800 ... 100)")->delimiter(',')->check(within_limits(option::intervals));
  sub->add_option(option::cells.flag, o.cells, "cells to measure, comma-separated indices (default: every myocyte; medians over them)")->delimiter(',')->check(within_limits(option::cells));
  sub->add_option(option::erp_resolution.flag, o.erp_resolution_ms, "the ERP's bisection stops at this bracket [ms] (default " + fmt::format("{}", o.erp_resolution_ms) + "; 0: no bisection)")->check(within_limits(option::erp_resolution));
  sub->add_option(option::capture_fraction.flag, o.capture_fraction, "S2 counts as captured when at least this fraction of the measured cells fire (default " + fmt::format("{}", o.capture_fraction) + ")")->check(within_limits(option::capture_fraction));
  sub->add_option("--jobs", o.jobs, "runs at once (default: one per core)");
  sub->add_option("--set", args.input.overrides, "override a value of the manifest: PATH=VALUE (repeatable)");
  sub->add_flag("--overwrite", o.overwrite, "run every interval again, even those run before with the same manifest");
  return sub;
}

int restitution_command(RestitutionArgs& args) {
  return guarded([&] {
    args.input.manifest = read_manifest_file(args.manifest);
    RestitutionOptions options = prepare_restitution(args.input, args.options);
    options.runner = ChildProcessRunner{boost::dll::program_location().string()};
    options.on_run_done = [](const RestitutionPoint& p) {
      std::cerr << "interval " << p.interval_ms << " ms: "
                << (!p.error.empty() ? "failed - " + p.error
                    : p.captured     ? "captured, APD90 " + std::to_string(p.s2_apd90_ms) + " ms at DI " +
                                       std::to_string(p.di_ms) + " ms"
                                     : "not captured")
                << (p.reused ? " (run before, kept)" : "") << "\n";
    };
    const RestitutionResult result = run_restitution(args.input.manifest, options);
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
