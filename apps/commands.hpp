// The subcommands of `fibrodem`, one function each. Exit codes: 0 success,
// 2 bad manifest, 3 plugin problem, 4 the run failed (outputs so far kept).
#pragma once

#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "cellml/import.hpp"
#include "model/plugin_registry.hpp"
#include "run/interrupt.hpp"
#include "study/study_options.hpp"
#include "util/manifest_error.hpp"

namespace CLI {
class App;
class Validator;
}

namespace fibrodem::cli {

struct RunArgs {
  std::string manifest;
  std::string out;
  std::vector<std::string> overrides;
  bool quiet = false;
  bool overwrite = false;  // replace another run's files in the output folder
  bool no_report = false;  // no report.html (as output.report: false)
};

struct ResumeArgs {
  std::string dir;  // a run's output folder
  bool quiet = false;
  bool no_report = false;
};

// `fibrodem report DIR`: report.html of a run's folder, from what is on disk.
struct ReportArgs {
  std::string dir;
};

struct CompareArgs {
  std::vector<std::string> manifests;  // one or two
  std::string out;
  std::vector<std::string> overrides, a_overrides, b_overrides;
  bool quiet = false;
  bool overwrite = false;
  bool no_report = false;
  int seeds = 0;  // > 0: A and B on this many tissue seeds, paired statistics
};

struct SweepArgs {
  std::string sweep;
  std::string out;
  std::vector<std::string> overrides;  // --set, after the sweep file's own `set`
  bool overwrite = false;
  bool no_report = false;  // neither the sweep's report.html nor its runs'
  unsigned jobs = 0;  // 0: one per core
};

// `fibrodem vulnerable-window` and `fibrodem restitution`: the manifest
// file, then what the Python module gives as well (study/study_options.hpp:
// the one options path of both, with each option's default and limits).
struct VulnerableWindowArgs {
  std::string manifest;
  StudyInput input;
  VulnerableWindowOptions options;
};

struct RestitutionArgs {
  std::string manifest;
  StudyInput input;
  RestitutionOptions options;
};

// `fibrodem tune-cv`: conductances for target conduction velocities (study/cv_tuning.hpp).
struct TuneCvArgs {
  std::string manifest;
  std::optional<double> along_m_per_s, across_m_per_s;
  std::string preset;  // study/cv_tuning.hpp cv_presets(); the --cv-* options override it
  double tolerance = 0.01;
  int max_iterations = 10;
  double length_mm = 5;
  std::string write;  // the manifest with the conductances found; empty: none
  std::vector<std::string> overrides;
};

// `fibrodem bench accuracy`: ladders of steps and tolerances against a reference.
struct BenchAccuracyArgs {
  std::string manifest;
  std::string out;
  std::vector<std::string> overrides;
  std::vector<std::string> methods;  // empty: all (euler, rush_larsen, rush_larsen2, cvode, adaptive, auto)
  std::vector<double> dt_ms;         // empty: the default ladder
  std::vector<double> rtol;          // empty: the default ladder
  std::vector<double> tol;           // adaptive's rtol = atol; empty: the default ladder
  std::vector<double> accuracy_ms;   // auto's solver.accuracy; empty: the default ladder
  double atol_ratio = 1e-2;          // atol = ratio * rtol
  double reference_rtol = 0;         // 0: the tightest rtol / 100
  double every_ms = 0;               // 0: the manifest's trace interval
  int repeat = 1;                    // wall time: the least of this many runs
};

// `fibrodem bench headline`: the headline speed figures beside another build's.
struct BenchHeadlineArgs {
  std::string baseline;  // another fibrodem executable; empty: this build alone
  int repeat = 3;
  std::string examples = "examples";
  bool skip_em = false;
  bool large = false;
};

int run_command(const RunArgs& args);
int resume_command(const ResumeArgs& args);
int report_command(const ReportArgs& args);
int sweep_command(const SweepArgs& args);
int compare_command(const CompareArgs& args);
int vulnerable_window_command(VulnerableWindowArgs& args);
int restitution_command(RestitutionArgs& args);
int tune_cv_command(const TuneCvArgs& args);
CLI::App* add_tune_cv_subcommand(CLI::App& app, TuneCvArgs& args);
int validate_command(const RunArgs& args);
int plugins_command(bool as_json);
// `fibrodem plot SPEC.json --out FILE.png` (apps/plot_command.cpp).
int plot_command(const std::string& spec_file, const std::string& out);
int check_plugin_command(const std::string& file_or_name);

// `fibrodem new-model`: a plugin skeleton that builds out of tree.
struct NewModelArgs {
  std::string name;
  std::string kind = "ionic";  // ionic | myofilament | contact-law
  std::string dir;             // default ./NAME
};
int new_model_command(const NewModelArgs& args);
int bench_command(const char* program, const std::vector<std::string>& args);
int bench_accuracy_command(const BenchAccuracyArgs& args);
// Adds `accuracy` (its options into `args`) under the `bench` subcommand.
CLI::App* add_bench_accuracy_subcommand(CLI::App& bench, BenchAccuracyArgs& args);
int bench_headline_command(const BenchHeadlineArgs& args);
int import_cellml_command(const cellml::ImportOptions& options);
// `fibrodem schema [--markdown|--json] [manifest|sweep|command-line]`: the
// manifest's or sweep file's JSON Schema, or the reference in Markdown of
// either or of the command line `app` declares (docs/reference/).
struct SchemaArgs {
  std::string format = "markdown";  // markdown | json
  std::string kind = "manifest";    // manifest | sweep | command-line
};
int schema_command(const SchemaArgs& args, const CLI::App& app);
CLI::App* add_import_cellml_subcommand(CLI::App& app, cellml::ImportOptions& options);
CLI::App* add_bench_headline_subcommand(CLI::App& bench, BenchHeadlineArgs& args);
CLI::App* add_vulnerable_window_subcommand(CLI::App& app, VulnerableWindowArgs& args);
CLI::App* add_restitution_subcommand(CLI::App& app, RestitutionArgs& args);
// CLI11's check of a study option's limits (study/study_options.hpp), the
// validator the flag had when it was written out: its description is --help's.
CLI::Validator within_limits(const StudyNumberOption& option);

// A failure's message on standard error, in one write: under mpirun every
// rank may print the same one, and pieces written apart would interleave.
// A rank of a job of several says which it is.
void print_failure(const std::string& kind, const std::string& what);

// Runs `body`, turning each kind of failure into a message and an exit code.
template <class Body>
int guarded(Body body) {
  try {
    return body();
  } catch (const InterruptedError& e) {
    print_failure("stopped", std::string(e.what()) + " (outputs written)");
    return 128 + e.signal();  // as a shell reports a process killed by the signal
  } catch (const ManifestError& e) {
    print_failure("error", e.what());
    return 2;
  } catch (const PluginError& e) {
    print_failure("error", e.what());
    return 3;
  } catch (const std::exception& e) {
    print_failure("error", e.what());
    return 4;
  }
}

}  // namespace fibrodem::cli
