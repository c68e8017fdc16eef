// The `fibrodem` command line (docs/reference/command_line.md).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <iostream>
#include <string>
#include <vector>

#include "apps/commands.hpp"
#include "apps/openmp_spinning.hpp"

namespace {

// Edits (insertions, deletions, substitutions) from a to b: Levenshtein's distance.
std::size_t edits_between(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// A first word that is no subcommand (and no option) is named as such, with
// the nearest subcommand if one is two edits away, before CLI11 parses: it
// would answer "A subcommand is required", and to `WORD --help` print the
// general help and exit 0. Exit 109, CLI11's code for arguments not expected.
int refuse_unknown_subcommand(const CLI::App& app, const std::string& word) {
  std::string names, nearest;
  std::size_t nearest_edits = 3;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
    const std::string& name = sub->get_name();
    names += std::string(names.empty() ? "" : ", ") + name;
    if (const std::size_t e = edits_between(word, name); e < nearest_edits) nearest_edits = e, nearest = name;
  }
  std::cerr << "fibrodem: '" << word << "' is not a subcommand"
            << (nearest.empty() ? "" : " (did you mean '" + nearest + "'?)") << "; the subcommands are " << names
            << " (fibrodem --help)\n";
  return static_cast<int>(CLI::ExitCodes::ExtrasError);
}

}  // namespace

int main(int argc, char** argv) {
  fibrodem::cli::keep_arguments(argv);
  CLI::App app{"fibrodem: cardiac tissue cell by cell (electrophysiology, coupling, mechanics)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("fibrodem ") + FIBRODEM_VERSION);

  fibrodem::cli::RunArgs run_args;
  CLI::App* run = app.add_subcommand("run", "Run the scene of a manifest and write its output directory");
  run->add_option("manifest", run_args.manifest, "experiment manifest (JSON)")->required();
  run->add_option("--out", run_args.out, "output directory (default: the manifest's output.dir, else out/NAME)");
  run->add_option("--set", run_args.overrides, "override a manifest value: PATH=VALUE (repeatable)");
  run->add_flag("--quiet", run_args.quiet, "log to run.log only");
  run->add_flag("--overwrite", run_args.overwrite, "replace another run's files in the output directory");
  run->add_flag("--no-report", run_args.no_report, "write no report.html (as output.report: false)");

  fibrodem::cli::ResumeArgs resume_args;
  CLI::App* resume = app.add_subcommand("resume", "Continue a stopped, interrupted or killed run from its last good checkpoint");
  resume->add_option("dir", resume_args.dir, "the run's output directory")->required();
  resume->add_flag("--quiet", resume_args.quiet, "log to run.log only");
  resume->add_flag("--no-report", resume_args.no_report, "write no report.html");

  fibrodem::cli::ReportArgs report_args;
  CLI::App* report = app.add_subcommand("report", "Write report.html of a run's folder (also a failed, interrupted or killed run's) from what is on disk");
  report->add_option("dir", report_args.dir, "the run's output directory")->required();

  fibrodem::cli::RunArgs validate_args;
  CLI::App* validate = app.add_subcommand("validate", "Check a manifest (and build its scene) without running it");
  validate->add_option("manifest", validate_args.manifest, "experiment manifest (JSON)")->required();
  validate->add_option("--set", validate_args.overrides, "override a manifest value: PATH=VALUE (repeatable)");

  fibrodem::cli::CompareArgs compare_args;
  CLI::App* compare = app.add_subcommand("compare", "Run two variants (two manifests, or one with --a/--b overrides) and compare them");
  compare->add_option("manifests", compare_args.manifests, "A.json B.json, or one manifest")->required()->expected(1, 2);
  compare->add_option("--out", compare_args.out, "output directory (default out/compare_NAME)");
  compare->add_option("--set", compare_args.overrides, "override for both: PATH=VALUE (repeatable)");
  compare->add_option("--a", compare_args.a_overrides, "override for A only: PATH=VALUE (repeatable)");
  compare->add_option("--b", compare_args.b_overrides, "override for B only: PATH=VALUE (repeatable)");
  compare->add_flag("--quiet", compare_args.quiet, "log to each run's run.log only");
  compare->add_flag("--overwrite", compare_args.overwrite, "replace earlier runs' files in the output directory");
  compare->add_flag("--no-report", compare_args.no_report, "write no report.html (neither the comparison's nor A's and B's)");
  compare->add_option("--seeds", compare_args.seeds, "run A and B on K tissue seeds (the manifest's and the next K - 1) and report paired differences with their 95 % CI and a paired t-test")
      ->check(CLI::Range(1, 10000));

  fibrodem::cli::SweepArgs sweep_args;
  CLI::App* sweep = app.add_subcommand("sweep", "Run a manifest over a grid of parameter values and tabulate the results");
  sweep->add_option("sweep", sweep_args.sweep, "sweep file (JSON: manifest, set, grid)")->required();
  sweep->add_option("--out", sweep_args.out, "output directory (default out/sweep_NAME)");
  sweep->add_option("--jobs", sweep_args.jobs, "runs at once (default: one per core; under mpirun, per rank: the cores shared by the ranks on a host)");
  sweep->add_option("--set", sweep_args.overrides, "override a value of the sweep's manifest: PATH=VALUE (repeatable)");
  sweep->add_flag("--overwrite", sweep_args.overwrite, "run every point again, even those completed before with the same manifest");
  sweep->add_flag("--no-report", sweep_args.no_report, "write no report.html (neither the sweep's nor its runs')");

  fibrodem::cli::VulnerableWindowArgs window_args;
  CLI::App* window = fibrodem::cli::add_vulnerable_window_subcommand(app, window_args);

  fibrodem::cli::TuneCvArgs tune_cv_args;
  CLI::App* tune_cv = fibrodem::cli::add_tune_cv_subcommand(app, tune_cv_args);

  fibrodem::cli::RestitutionArgs restitution_args;
  CLI::App* restitution = fibrodem::cli::add_restitution_subcommand(app, restitution_args);

  bool plugins_json = false;
  CLI::App* plugins = app.add_subcommand("plugins", "List the cell-model plugins found, with states and parameters");
  plugins->add_flag("--json", plugins_json, "print JSON instead of text");

  std::string plot_spec, plot_out;
  CLI::App* plot = app.add_subcommand("plot", "Draw line plots (PNG) from a JSON description of panels and series");
  plot->add_option("spec", plot_spec, "JSON: {title, columns, panels: [{title, x_label, y_label, series: [{label, x, y}]}]}")->required();
  plot->add_option("--out", plot_out, "the PNG file to write")->required();
  std::string check_plugin_target;
  CLI::App* check_plugin = app.add_subcommand("check-plugin", "Check a cell-model plugin against the plugin contract (metadata, derivatives written, finite, voltage_only, linear forms, bounds over a beat, block = single cell)");
  check_plugin->add_option("plugin", check_plugin_target, "a plugin file (libfibrodem_NAME.so) or a model name on the search path")->required();
  fibrodem::cli::NewModelArgs new_model_args;
  CLI::App* new_model = app.add_subcommand("new-model", "Write a plugin skeleton (source, CMakeLists.txt, test manifest) that builds out of tree against an installed fibrodem");
  new_model->add_option("name", new_model_args.name, "the plugin's name (lower-case letters, digits, '_')")->required();
  new_model->add_option("--kind", new_model_args.kind, "ionic (default), myofilament or contact-law")
      ->check(CLI::IsMember({"ionic", "myofilament", "contact-law"}));
  new_model->add_option("--dir", new_model_args.dir, "directory to write (default ./NAME); existing files are never overwritten");

  fibrodem::cli::BenchAccuracyArgs accuracy_args;
  fibrodem::cli::BenchHeadlineArgs headline_args;
  CLI::App* bench = app.add_subcommand("bench", "Run the performance benchmarks (Google Benchmark; its --benchmark_* flags pass through), `bench headline` or `bench accuracy`");
  bench->allow_extras();
  CLI::App* accuracy = fibrodem::cli::add_bench_accuracy_subcommand(*bench, accuracy_args);
  CLI::App* headline = fibrodem::cli::add_bench_headline_subcommand(*bench, headline_args);

  fibrodem::cellml::ImportOptions import_args;
  CLI::App* import_cellml = fibrodem::cli::add_import_cellml_subcommand(app, import_args);

  fibrodem::cli::SchemaArgs schema_args;
  CLI::App* schema = app.add_subcommand("schema", "Print the JSON Schema of the manifest or the sweep file, or the reference in Markdown of either or of the command line");
  schema->add_flag_callback("--markdown", [&] { schema_args.format = "markdown"; }, "the reference in Markdown (the default)");
  schema->add_flag_callback("--json", [&] { schema_args.format = "json"; }, "the JSON Schema itself");
  schema->add_option("kind", schema_args.kind, "manifest (the default), sweep or command-line (Markdown only)")->check(CLI::IsMember({"manifest", "sweep", "command-line"}));

  const std::string first = argc > 1 ? argv[1] : "";
  if (!first.empty() && first[0] != '-' && app.get_subcommands([&](const CLI::App* sub) { return sub->get_name() == first; }).empty())
    return refuse_unknown_subcommand(app, first);
  CLI11_PARSE(app, argc, argv);

  // Commands that run scenes or benchmarks on several threads bound OpenMP's
  // spinning now; run, resume and validate once they know their scene.
  const auto chosen = [](const CLI::App* sub) { return sub->parsed(); };
  if (chosen(compare) || chosen(sweep) || chosen(window) || chosen(restitution) || chosen(bench))
    fibrodem::cli::bound_openmp_spinning();

  if (chosen(run)) return fibrodem::cli::run_command(run_args);
  if (chosen(resume)) return fibrodem::cli::resume_command(resume_args);
  if (chosen(report)) return fibrodem::cli::report_command(report_args);
  if (chosen(validate)) return fibrodem::cli::validate_command(validate_args);
  if (chosen(compare)) return fibrodem::cli::compare_command(compare_args);
  if (chosen(sweep)) return fibrodem::cli::sweep_command(sweep_args);
  if (chosen(window)) return fibrodem::cli::vulnerable_window_command(window_args);
  if (chosen(restitution)) return fibrodem::cli::restitution_command(restitution_args);
  if (chosen(tune_cv)) return fibrodem::cli::tune_cv_command(tune_cv_args);
  if (chosen(plugins)) return fibrodem::cli::plugins_command(plugins_json);
  if (chosen(plot)) return fibrodem::cli::plot_command(plot_spec, plot_out);
  if (chosen(schema)) return fibrodem::cli::schema_command(schema_args, app);
  if (chosen(import_cellml)) return fibrodem::cli::import_cellml_command(import_args);
  if (chosen(check_plugin)) return fibrodem::cli::check_plugin_command(check_plugin_target);
  if (chosen(new_model)) return fibrodem::cli::new_model_command(new_model_args);
  if (chosen(accuracy)) return fibrodem::cli::bench_accuracy_command(accuracy_args);
  if (chosen(headline)) return fibrodem::cli::bench_headline_command(headline_args);
  if (chosen(bench)) return fibrodem::cli::bench_command(argv[0], bench->remaining());
  return 0;
}
