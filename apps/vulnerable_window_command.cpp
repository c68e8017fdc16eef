// `fibrodem vulnerable-window MANIFEST [--out DIR] [--from MS --to MS --step MS]
// [--seeds N] [--jobs N]`: the S1-S2 coupling intervals at which S2 induces
// re-entry (the engine: study/vulnerable_window.hpp). Each run is a
// `fibrodem run` process of its own (this executable), as a sweep's points.
#include <boost/dll/runtime_symbol_info.hpp>

#include <algorithm>
#include <iostream>
#include <sstream>

#include "apps/commands.hpp"
#include "scene/scene.hpp"
#include "study/vulnerable_window.hpp"

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

int vulnerable_window_command(const VulnerableWindowArgs& args) {
  return guarded([&] {
    json manifest = read_manifest_file(args.manifest);
    for (const auto& o : args.overrides) apply_override(manifest, o);
    VulnerableWindowOptions options;
    options.out = args.out.empty() ? default_vulnerable_window_dir(manifest) : std::filesystem::path(args.out);
    options.runner = ChildProcessRunner{boost::dll::program_location().string()};
    options.jobs = args.jobs;
    options.seeds = args.seeds;
    options.overwrite = args.overwrite;
    options.capture_fraction = args.capture_fraction;
    const bool scan_given = args.from_ms > 0 || args.to_ms > 0 || args.step_ms > 0;
    if (scan_given) {
      if (!(args.from_ms > 0 && args.to_ms >= args.from_ms && args.step_ms > 0))
        throw ManifestError("--from/--to/--step", "give all three, with 0 < from <= to and step > 0 (got from " +
                                                      std::to_string(args.from_ms) + ", to " + std::to_string(args.to_ms) +
                                                      ", step " + std::to_string(args.step_ms) + ")");
      options.scan = {args.from_ms, args.to_ms, args.step_ms, args.resolution_ms};
    } else {
      options.scan.resolution_ms = args.resolution_ms;
    }
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
