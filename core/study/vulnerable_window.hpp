// The vulnerable window of an S1-S2 protocol (docs/topics/arrhythmia.md): the S2
// coupling intervals at which S2 induces re-entry. The manifest's
// stimulus[1] (S2) is moved to each interval of a scan after the last onset
// of stimulus[0] (S1), one run per interval (and tissue seed) by a sweep's
// point runner (study/sweep_point.hpp: isolated, resumable runs); each run is
// classified from its summary.json, then each boundary between "induced"
// and "not induced" is refined by bisection to a given resolution.
//
// The search itself (scan, then bisection) takes any classifier, so that it
// can be checked against a known window; run_vulnerable_window gives it the
// one that runs fibrodem.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "study/s1s2_protocol.hpp"
#include "study/sweep_point.hpp"

namespace fibrodem {

// What S2 did at one interval.
enum class S2Outcome {
  reentry,     // summary.json reentry.detected
  no_reentry,  // S2 propagated (or capture could not be told), no re-entry
  no_capture,  // S2's beat reached fewer myocytes than the capture fraction
  failed,      // the run did not complete (counted as not induced)
};
const char* outcome_name(S2Outcome outcome);
inline bool induced(S2Outcome outcome) { return outcome == S2Outcome::reentry; }

// One interval of one tissue seed.
struct S2Probe {
  double interval_ms = 0;
  long long seed = 0;
};

struct S2Result {
  S2Probe probe;
  S2Outcome outcome = S2Outcome::failed;
  std::optional<double> duration_ms;  // summary reentry.duration_ms
  std::optional<int> ps_max;          // summary reentry.phase_singularities_max
  bool refinement = false;            // run by the bisection, not the scan
  std::string run;                    // its folder, relative to the search's
  std::string error;                  // why it failed
  bool reused = false;                // completed by an earlier search with the same manifest
};

// Runs a batch of probes (independent: any order, in parallel) and returns
// their results in the probes' order.
using S2Classifier = std::function<std::vector<S2Result>(const std::vector<S2Probe>&)>;

struct WindowScan {
  double from_ms = 0, to_ms = 0, step_ms = 0;  // the scan: from, from + step, ... <= to
  double resolution_ms = 1;                    // bisection stops when a boundary is bracketed this closely
};

// A window: the least and the greatest interval of a run of induced
// intervals (both induced), each within resolution_ms of the interval where
// induction stops (the scan can miss windows narrower than its step).
struct InducedWindow {
  double lower_ms = 0, upper_ms = 0;
  // The scan reached the window's end at `from_ms` or `to_ms` without a
  // non-induced interval beyond it: the window may extend further.
  bool open_below = false, open_above = false;
};

struct SeedWindows {
  long long seed = 0;
  std::vector<InducedWindow> windows;  // in increasing order
};

struct WindowSearch {
  std::vector<S2Result> results;  // every run, scan first, then the bisection's rounds
  std::vector<SeedWindows> per_seed;
  // The union over the seeds (intervals induced on at least one tissue).
  std::vector<InducedWindow> overall;
};

// The scan's intervals (ManifestError-free: throws std::invalid_argument for
// step <= 0, to < from or more than 10^4 intervals).
std::vector<double> scan_intervals(const WindowScan& scan);

// The scan on every seed, then bisection rounds: each round probes the
// midpoint of every bracket still wider than the resolution, all seeds and
// boundaries in one batch (so the classifier can run them in parallel).
WindowSearch search_vulnerable_window(const WindowScan& scan, const std::vector<long long>& seeds,
                                      const S2Classifier& classify);

// Windows from classified intervals of one seed (any order).
std::vector<InducedWindow> induced_windows(std::vector<S2Result> results, const WindowScan& scan);

// ---- Running fibrodem ----

struct VulnerableWindowOptions {
  std::filesystem::path out;  // the search's folder (required)
  PointRunner runner;
  unsigned jobs = 0;           // runs at once; 0: one per core
  WindowScan scan;             // from/to/step 0: around the manifest's own interval (default_scan)
  int seeds = 0;               // > 0: this many tissue seeds (the manifest's and the next ones)
  double capture_fraction = 0.5;  // S2 captured if its beat reached at least this fraction of the myocytes
  bool overwrite = false;      // run again what was run before
  bool report = false;         // each run's report.html
  std::function<void(const S2Result&)> on_run_done;  // from a worker, one call at a time
};

// Without a scan given: the manifest's S2 coupling interval
// (study/s1s2_protocol.hpp) +- 100 ms by 10 ms (from at least 10 ms).
WindowScan default_scan(const json& manifest);

// Where a search goes without --out: out/vulnerable_window_<the manifest's name>.
std::filesystem::path default_vulnerable_window_dir(const json& manifest);

// Adds output.reentry (defaults) if the manifest has none; returns whether
// it did.
bool ensure_reentry_output(json& manifest);

// The outcome of a run from its summary.json (null: failed). S2's beat is
// the one that starts at `s2_onset_ms`.
S2Outcome classify_summary(const json& summary, double s2_onset_ms, double capture_fraction);

struct VulnerableWindowResult {
  WindowSearch search;
  bool reentry_output_added = false;
  std::size_t reused = 0;  // runs kept from an earlier search with the same manifest
};

// Runs the search on `manifest` into options.out: runs/ci_<ms>_seed_<s>/,
// vulnerable_window.csv, vulnerable_window.json and vulnerable_window.png.
VulnerableWindowResult run_vulnerable_window(json manifest, VulnerableWindowOptions options);

}  // namespace fibrodem
