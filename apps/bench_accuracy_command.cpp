// `fibrodem bench accuracy MANIFEST [--out DIR] [--set P=V]... [--methods ...]
//  [--dt LIST] [--rtol LIST] [--tol LIST] [--accuracy LIST] [--atol-ratio R]
//  [--reference-rtol X] [--every MS] [--repeat N]`: what accuracy costs in
// time. The scene's accuracy ladder (study/accuracy_ladder.hpp says what is
// run and measured against what) into DIR/accuracy.csv, DIR/accuracy.md and
// DIR/work_precision.png (study/accuracy_report.hpp); a line per run on
// stderr as it goes, accuracy.md on stdout at the end.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "apps/commands.hpp"
#include "study/accuracy_ladder.hpp"
#include "study/accuracy_report.hpp"

namespace fibrodem::cli {

namespace {

AccuracyLadderSpec ladder_spec(const BenchAccuracyArgs& args) {
  AccuracyLadderSpec spec;
  spec.manifest = read_manifest_file(args.manifest);
  for (const auto& assignment : args.overrides) apply_override(spec.manifest, assignment);
  spec.methods = args.methods;
  spec.dt_ms = args.dt_ms;
  spec.rtol = args.rtol;
  spec.tol = args.tol;
  spec.accuracy_ms = args.accuracy_ms;
  spec.atol_ratio = args.atol_ratio;
  spec.reference_rtol = args.reference_rtol;
  spec.every_ms = args.every_ms;
  spec.repeat = args.repeat;
  return spec;
}

// The command as given (the options set, defaults left out), for accuracy.md.
std::string command_line(const BenchAccuracyArgs& args, int repeat) {
  std::string c = "fibrodem bench accuracy " + args.manifest;
  for (const auto& o : args.overrides) c += " --set " + o;
  auto option = [&](const char* name, const std::vector<double>& values) {
    if (values.empty()) return;
    c += std::string(" ") + name + " ";
    for (std::size_t i = 0; i < values.size(); ++i) c += (i ? "," : "") + fmt::format("{:g}", values[i]);
  };
  if (!args.methods.empty()) {
    c += " --methods ";
    for (std::size_t i = 0; i < args.methods.size(); ++i) c += (i ? "," : "") + args.methods[i];
  }
  option("--dt", args.dt_ms);
  option("--rtol", args.rtol);
  option("--tol", args.tol);
  option("--accuracy", args.accuracy_ms);
  if (args.reference_rtol > 0) c += fmt::format(" --reference-rtol {:g}", args.reference_rtol);
  if (args.every_ms > 0) c += fmt::format(" --every {:g}", args.every_ms);
  if (repeat > 1) c += " --repeat " + std::to_string(repeat);
  return c;
}

}  // namespace

CLI::App* add_bench_accuracy_subcommand(CLI::App& bench, BenchAccuracyArgs& a) {
  auto* acc = bench.add_subcommand(
      "accuracy", "Error against a tight CVODE reference, and wall time, per integrator over ladders of dt and rtol");
  acc->add_option("manifest", a.manifest, "experiment manifest (JSON)")->required();
  acc->add_option("--out", a.out, "output directory (default out/accuracy_NAME)");
  acc->add_option("--set", a.overrides, "override a manifest value: PATH=VALUE (repeatable)");
  acc->add_option("--methods", a.methods, "integrators (default euler,rush_larsen,rush_larsen2,cvode,adaptive,auto)")
      ->delimiter(',');
  acc->add_option("--dt", a.dt_ms, "fixed-step ladder [ms] (default 0.001,0.002,0.005,0.01,0.02,0.05,0.1,0.25)")
      ->delimiter(',');
  acc->add_option("--rtol", a.rtol, "CVODE ladder (default 1e-3,1e-4,1e-5,1e-6,1e-7)")->delimiter(',');
  acc->add_option("--tol", a.tol, "adaptive ladder, rtol = atol (default 0.1,0.03,0.01,0.003,0.001,1e-4)")
      ->delimiter(',');
  acc->add_option("--accuracy", a.accuracy_ms, "auto ladder, solver.accuracy (default 1,0.5,0.1,0.01)")
      ->delimiter(',');
  acc->add_option("--atol-ratio", a.atol_ratio, "CVODE atol = ratio x rtol (default 1e-2)");
  acc->add_option("--reference-rtol", a.reference_rtol, "reference CVODE rtol (default: the tightest rtol / 100)");
  acc->add_option("--every", a.every_ms, "V sample interval [ms] (default: the manifest's output.traces.every_ms)");
  acc->add_option("--repeat", a.repeat, "runs per point; the wall time is the least (default 1)");
  return acc;
}

int bench_accuracy_command(const BenchAccuracyArgs& args) {
  return guarded([&]() -> int {
    AccuracyLadder ladder = plan_accuracy_ladder(ladder_spec(args));
    const std::filesystem::path dir = args.out.empty() ? "out/accuracy_" + ladder.scene.name : args.out;
    std::filesystem::create_directories(dir);
    run_accuracy_ladder(ladder, [](const std::string& line) { std::cerr << line << "\n"; });
    const std::string md = write_accuracy_report(ladder, dir, command_line(args, ladder.repeat));
    std::cout << md << "\noutputs: " << dir.string() << "/{accuracy.csv,accuracy.md,work_precision.png}\n";
    return 0;
  });
}

}  // namespace fibrodem::cli
