// `fibrodem tune-cv MANIFEST --cv-along-m-per-s V [--cv-across-m-per-s V]
// [--preset NAME] [--write OUT.json]`: the gap-junction conductances that
// give target conduction velocities on the manifest's cells and layout
// (the engine: study/cv_tuning.hpp).
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <fstream>
#include <iostream>

#include "apps/commands.hpp"
#include "apps/openmp_spinning.hpp"
#include "scene/scene.hpp"
#include "study/cv_tuning.hpp"

namespace fibrodem::cli {

namespace {

std::string presets_listed() {
  std::string names;
  for (const auto& p : cv_presets()) names += std::string(names.empty() ? "" : ", ") + p.name;
  return names;
}

// "0.7012 m/s (target 0.7, +0.17 %)", or "-" when not measured.
std::string reached(const std::optional<double>& cv, const std::optional<double>& target) {
  if (!target) return "-";
  if (!cv) return fmt::format("no conduction across the strand (target {:.4g})", *target);
  return fmt::format("{:.4g} m/s (target {:.4g}, {:+.2f} %)", *cv, *target, 100 * (*cv / *target - 1));
}

}  // namespace

CLI::App* add_tune_cv_subcommand(CLI::App& app, TuneCvArgs& a) {
  auto* sub = app.add_subcommand("tune-cv", "Find the gap-junction conductances (coupling.D_m_nS, D_m_side_nS) that give target conduction velocities along and across the fibres, as openCARP's tuneCV");
  sub->add_option("manifest", a.manifest, "manifest whose cells, solver, layout (strand or fibrotic_sheet) and stimulus[0] pulse are used")->required();
  sub->add_option("--cv-along-m-per-s", a.along_m_per_s, "target CV along the fibres [m/s]")->check(CLI::PositiveNumber);
  sub->add_option("--cv-across-m-per-s", a.across_m_per_s, "target CV across the fibres [m/s] (fibrotic_sheet only)")->check(CLI::PositiveNumber);
  sub->add_option("--preset", a.preset, "cited human atrial targets: " + presets_listed() + " (the --cv-* options override its values)");
  sub->add_option("--tolerance", a.tolerance, "stop when every CV is within this fraction of its target (default 0.01)")->check(CLI::Range(1e-4, 0.5));
  sub->add_option("--max-iterations", a.max_iterations, "at most this many iterations (default 10)")->check(CLI::Range(1, 100));
  sub->add_option("--length-mm", a.length_mm, "length of the measuring strand or sheet in the wave's direction [mm] (default 5)")->check(CLI::Range(1.0, 100.0));
  sub->add_option("--write", a.write, "write the manifest with the conductances found to this file");
  sub->add_option("--set", a.overrides, "override a value of the manifest: PATH=VALUE (repeatable)");
  return sub;
}

int tune_cv_command(const TuneCvArgs& args) {
  bound_openmp_spinning();
  return guarded([&] {
    json manifest = read_manifest_file(args.manifest);
    for (const auto& o : args.overrides) apply_override(manifest, o);
    CvTuningOptions options;
    if (!args.preset.empty()) {
      const CvPreset* preset = find_cv_preset(args.preset);
      if (!preset) {
        std::cerr << "error: --preset '" << args.preset << "': expected one of " << presets_listed() << "\n";
        return 2;
      }
      options.along_m_per_s = preset->along_m_per_s;
      options.across_m_per_s = preset->across_m_per_s;
      std::cout << "preset " << preset->name << ": along " << preset->along_m_per_s << " m/s, across "
                << preset->across_m_per_s << " m/s (" << preset->source << ")\n";
    }
    if (args.along_m_per_s) options.along_m_per_s = args.along_m_per_s;
    if (args.across_m_per_s) options.across_m_per_s = args.across_m_per_s;
    if (!options.along_m_per_s && !options.across_m_per_s) {
      std::cerr << "error: no target: give --cv-along-m-per-s, --cv-across-m-per-s or --preset (" << presets_listed()
                << ")\n";
      return 2;
    }
    options.tolerance = args.tolerance;
    options.max_iterations = args.max_iterations;
    options.length_mm = args.length_mm;
    options.on_step = [&](const CvTuningStep& s) {
      std::cout << fmt::format("iteration {}: D_m_nS {:.6g}, D_m_side_nS {:.6g}: along {}, across {}\n", s.iteration,
                               s.D_m_nS, s.D_m_side_nS, reached(s.along_m_per_s, options.along_m_per_s),
                               reached(s.across_m_per_s, options.across_m_per_s))
                << std::flush;
    };
    CvTuningResult result;
    try {
      result = tune_conduction_velocity(manifest, options);
    } catch (const CvTargetUnreachable& e) {
      print_failure("error", std::string("target out of reach: ") + e.what());
      return 2;
    }
    std::cout << fmt::format("{}: D_m_nS {:.6g}, D_m_side_nS {:.6g} after {} iterations: along {}, across {}\n",
                             result.converged ? "reached" : "not reached", result.D_m_nS, result.D_m_side_nS,
                             result.steps.size(), reached(result.along_m_per_s, options.along_m_per_s),
                             reached(result.across_m_per_s, options.across_m_per_s));
    if (!result.converged) {
      print_failure("error", fmt::format("no CV within {:g} % of its target after {} iterations (--max-iterations)",
                                         100 * options.tolerance, result.steps.size()));
      return 4;
    }
    if (!args.write.empty()) {
      std::ofstream out(args.write);
      out << with_conductances(manifest, result.D_m_nS, result.D_m_side_nS).dump(2) << "\n";
      if (!out) throw std::runtime_error("cannot write " + args.write);
      std::cout << "wrote " << args.write << "\n";
    }
    return 0;
  });
}

}  // namespace fibrodem::cli
