// `fibrodem compare`: runs two variants and writes their A/B comparison.
//   fibrodem compare A.json B.json [--out DIR] [--set P=V]...
//   fibrodem compare M.json --a P=V... --b P=V... [--out DIR]
#include <iostream>

#include "apps/commands.hpp"
#include "compare/ab_comparison.hpp"
#include "run/simulation.hpp"

namespace fibrodem::cli {

namespace {

RunRecord run_variant(const std::string& label, json manifest, const std::filesystem::path& dir, bool quiet,
                      bool overwrite) {
  Scene scene = parse_scene(manifest);
  scene.output.dir = (dir / label).string();
  scene.output.overwrite = overwrite;
  RunOptions options;
  options.console_log = !quiet;
  Simulation simulation(scene, nullptr, options);
  simulation.run();
  return record_of(simulation, label);
}

}  // namespace

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
    const std::string name = a.value("name", std::string("scene"));
    const std::filesystem::path dir = args.out.empty() ? "out/compare_" + name : args.out;
    const RunRecord ra = run_variant("A", a, dir, args.quiet, args.overwrite);
    const RunRecord rb = run_variant("B", b, dir, args.quiet, args.overwrite);
    write_comparison(ra, rb, dir);
    std::cout << "A: " << args.manifests.front();
    for (const auto& s : args.a_overrides) std::cout << " " << s;
    std::cout << "\nB: " << args.manifests.back();
    for (const auto& s : args.b_overrides) std::cout << " " << s;
    std::cout << "\n\n" << comparison_markdown(ra, rb) << "\noutputs: " << dir.string()
              << "/{comparison.md,comparison.csv,traces.csv,A/,B/}\n";
    return 0;
  });
}

}  // namespace fibrodem::cli
