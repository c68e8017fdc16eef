// An A/B comparison (docs/guide/compare.md): two variants of a scene run one
// after the other into DIR/A and DIR/B, or with seeds on each of K tissues
// (DIR/seed_<s>/A, B), then compared (compare/: the biomarker table and
// common-time-base traces of the (first) pair, and over the seeds the paired
// statistics) and reported. The engine of `fibrodem compare` and of the
// Python module's fibrodem.compare.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "compare/ab_comparison.hpp"
#include "compare/paired_comparison.hpp"
#include "measure/sample_statistics.hpp"
#include "util/json_reader.hpp"

namespace fibrodem {

struct CompareOptions {
  std::filesystem::path out;  // the comparison's folder (required)
  int seeds = 0;              // > 0: A and B on this many tissue seeds, paired statistics
  bool overwrite = false;     // replace earlier runs' files in out/A, out/B, ...
  bool report = true;         // report.html (the comparison's and each run's)
  bool console_log = false;   // the runs' logs also on stderr
  // Where plugins are searched after a manifest's plugin_path; empty: as
  // `fibrodem run` searches (study/plugin_search.hpp).
  std::vector<std::filesystem::path> plugin_search_path;
};

// Where a comparison goes without --out: out/compare_<A's name>.
std::filesystem::path default_compare_dir(const json& a);

struct CompareResult {
  std::filesystem::path dir;
  std::string a_dir, b_dir;                // the (first) pair's folders, relative to dir
  std::vector<ComparisonRow> rows;         // comparison.csv: the (first) pair's mean biomarkers
  std::vector<long long> seeds;            // with seeds: the tissues' seeds
  std::vector<json> summaries_a, summaries_b;  // each run's summary.json, per seed
  std::vector<PairedRow> paired;           // with seeds: paired.csv's rows
  std::string markdown;                    // what the command line prints: paired.md or the comparison table
};

// Checks both variants (their scenes built, their folders free) before either
// runs, so a bad B stops it with nothing of A run (errors name the variant);
// then runs and writes everything. A run that fails or is interrupted throws
// as Simulation::run does.
CompareResult run_compare(const json& a, const json& b, const CompareOptions& options);

}  // namespace fibrodem
