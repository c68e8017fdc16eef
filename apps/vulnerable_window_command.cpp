// `fibrodem vulnerable-window MANIFEST [--out DIR] [--from MS --to MS --step MS]
// [--seeds N] [--jobs N]`: the S1-S2 coupling intervals at which S2 induces
// re-entry (the engine: study/vulnerable_window.hpp). Each run is a
// `fibrodem run` process of its own (this executable), as a sweep's points.
#include <CLI/CLI.hpp>
#include <boost/dll/runtime_symbol_info.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <iostream>
#include <sstream>

#include "apps/commands.hpp"
#include "scene/scene.hpp"

namespace fibrodem::cli {

namespace {

std::string window_text(const InducedWindow& w) {
  std::ostringstream s;
  s << "[" << w.lower_ms << ", " << w.upper_ms << "] ms";
  if (w.open_below) s << " (re-entry at the scan's first interval: the window may start earlier)";
  if (w.open_above) s << " (re-entry at the scan's last interval: the window may end later)";
  return s.str();
}

void print_windows(const std::string& what, const std::vector<InducedWindow>& windows) {
  std::cout << what << ": ";
  if (windows.empty()) std::cout << "no re-entry at any interval scanned";
  for (std::size_t k = 0; k < windows.size(); ++k) std::cout << (k ? ", " : "") << window_text(windows[k]);
  std::cout << "\n";
}

}  // namespace

CLI::App* add_vulnerable_window_subcommand(CLI::App& app, VulnerableWindowArgs& args) {
  namespace option = study_option;
  VulnerableWindowOptions& o = args.options;
  auto* sub = app.add_subcommand("vulnerable-window", "Scan the S1-S2 coupling interval (stimulus[1] after stimulus[0]) and find the window that induces re-entry, boundaries refined by bisection");
  sub->add_option("manifest", args.manifest, "manifest with S1 (stimulus[0]) and S2 (stimulus[1])")->required();
  sub->add_option("--out", args.input.out, "output directory (default out/vulnerable_window_NAME)");
  sub->add_option(option::scan_from.flag, o.scan.from_ms, "first coupling interval of the scan [ms] (with --to and --step; default: the manifest's interval - 100)")->check(within_limits(option::scan_from));
  sub->add_option(option::scan_to.flag, o.scan.to_ms, "last coupling interval of the scan [ms]")->check(within_limits(option::scan_to));
  sub->add_option(option::scan_step.flag, o.scan.step_ms, "the scan's step [ms] (default 10)")->check(within_limits(option::scan_step));
  sub->add_option(option::bisection_resolution.flag, o.scan.resolution_ms, "bisection stops when a boundary is bracketed this closely [ms] (default " + fmt::format("{}", o.scan.resolution_ms) + ")")->check(within_limits(option::bisection_resolution));
  sub->add_option(option::capture_fraction.flag, o.capture_fraction, "S2 counts as captured when its beat reaches at least this fraction of the myocytes (default " + fmt::format("{}", o.capture_fraction) + ")")->check(within_limits(option::capture_fraction));
  sub->add_option(option::seeds.flag, o.seeds, "search on K tissue seeds (the manifest's and the next K - 1)")->check(within_limits(option::seeds));
  sub->add_option("--jobs", o.jobs, "runs at once (default: one per core)");
  sub->add_option("--set", args.input.overrides, "override a value of the manifest: PATH=VALUE (repeatable)");
  sub->add_flag("--overwrite", o.overwrite, "run every interval again, even those run before with the same manifest");
  return sub;
}

int vulnerable_window_command(VulnerableWindowArgs& args) {
  return guarded([&] {
    args.input.manifest = read_manifest_file(args.manifest);
    VulnerableWindowOptions options = prepare_vulnerable_window(args.input, args.options);
    json& manifest = args.input.manifest;
    options.runner = ChildProcessRunner{boost::dll::program_location().string()};
    const bool scan_given = options.scan.step_ms > 0;
    if (ensure_reentry_output(manifest))
      std::cerr << "note: the manifest has no output.reentry; added {\"every_ms\": 2, \"tau_ms\": 10} to every run\n";
    if (!scan_given) {
      const WindowScan scan = default_scan(manifest);
      std::cerr << "scan: " << scan.from_ms << " to " << scan.to_ms << " ms by " << scan.step_ms
                << " ms (the manifest's interval +- 100 ms)\n";
    }
    options.on_run_done = [](const S2Result& r) {
      std::cerr << "interval " << r.probe.interval_ms << " ms, seed " << r.probe.seed << ": " << outcome_name(r.outcome)
                << (r.reused ? " (run before, kept)" : "") << (r.error.empty() ? "" : " - " + r.error) << "\n";
    };
    const VulnerableWindowResult result = run_vulnerable_window(manifest, options);
    for (const auto& s : result.search.per_seed) print_windows("seed " + std::to_string(s.seed), s.windows);
    if (result.search.per_seed.size() > 1) print_windows("any seed", result.search.overall);
    std::cout << result.search.results.size() << " runs (" << result.reused << " kept from before)\n"
              << "outputs: " << options.out.string()
              << "/{report.html,vulnerable_window.csv,vulnerable_window.json,vulnerable_window.png,runs/}\n";
    const bool failed = std::any_of(result.search.results.begin(), result.search.results.end(),
                                    [](const S2Result& r) { return r.outcome == S2Outcome::failed; });
    return failed ? 4 : 0;
  });
}

}  // namespace fibrodem::cli
