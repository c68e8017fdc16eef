// `fibrodem compare`: runs two variants and writes their A/B comparison
// (the engine: study/compare_variants.hpp).
//   fibrodem compare A.json B.json [--out DIR] [--set P=V]...
//   fibrodem compare M.json --a P=V... --b P=V... [--out DIR] [--seeds K]
#include <iostream>

#include "apps/commands.hpp"
#include "scene/scene.hpp"
#include "study/compare_variants.hpp"

namespace fibrodem::cli {

int compare_command(const CompareArgs& args) {
  return guarded([&] {
    if (args.manifests.size() == 1 && args.a_overrides.empty() && args.b_overrides.empty())
      throw ManifestError("", "compare needs two manifests, or one manifest with --a and --b overrides");
    json a = read_manifest_file(args.manifests.front());
    json b = read_manifest_file(args.manifests.back());
    for (const auto& s : args.overrides) {
      apply_override(a, s);
      apply_override(b, s);
    }
    for (const auto& s : args.a_overrides) apply_override(a, s);
    for (const auto& s : args.b_overrides) apply_override(b, s);
    CompareOptions options;
    options.out = args.out.empty() ? default_compare_dir(a) : std::filesystem::path(args.out);
    options.seeds = args.seeds;
    options.overwrite = args.overwrite;
    options.report = !args.no_report;
    options.console_log = !args.quiet;
    std::cout << "A: " << args.manifests.front();
    for (const auto& s : args.a_overrides) std::cout << " " << s;
    std::cout << "\nB: " << args.manifests.back();
    for (const auto& s : args.b_overrides) std::cout << " " << s;
    const CompareResult result = run_compare(a, b, options);
    std::cout << "\n\n" << result.markdown << "\noutputs: " << options.out.string()
              << (args.seeds > 0 ? "/{report.html,paired.md,paired.csv,comparison.md,comparison.csv,traces.csv,"
                                   "traces.png,seed_*/A,seed_*/B}\n"
                                 : "/{report.html,comparison.md,comparison.csv,traces.csv,traces.png,A/,B/}\n");
    return 0;
  });
}

}  // namespace fibrodem::cli
