// `fibrodem compare`: runs two variants and writes their A/B comparison.
//   fibrodem compare A.json B.json [--out DIR] [--set P=V]...
//   fibrodem compare M.json --a P=V... --b P=V... [--out DIR] [--seeds K]
#include <iostream>

#include "apps/commands.hpp"
#include "compare/ab_comparison.hpp"
#include "compare/paired_comparison.hpp"
#include "report/compare_report.hpp"
#include "run/output_dir.hpp"
#include "run/run_record.hpp"
#include "run/simulation.hpp"

namespace fibrodem::cli {

namespace {

struct Variant {
  RunRecord record;
  json summary;
};

Variant run_variant(const std::string& label, json manifest, const std::filesystem::path& dir, const CompareArgs& args) {
  Scene scene = parse_scene(manifest);
  scene.output.dir = (dir / label).string();
  scene.output.overwrite = args.overwrite;
  if (args.no_report) scene.output.report = false;
  RunOptions options;
  options.console_log = !args.quiet;
  Simulation simulation(scene, nullptr, options);
  simulation.run();
  return {record_of(simulation, label.substr(label.rfind('/') + 1)), simulation.summary()};
}

long long first_seed(const json& a) {
  return a.contains("seed") && a["seed"].is_number_integer() ? a["seed"].get<long long>() : 0;
}

// Both variants' scenes built (tissue, plugins, names, traces) and their output
// folders checked before either runs, so that a bad B is found before A has
// run; errors say which variant.
void validate_variants(const std::vector<std::pair<std::string, const json*>>& variants, const std::filesystem::path& dir,
                       bool overwrite) {
  for (const auto& [label, manifest] : variants) {
    try {
      Scene scene = parse_scene(*manifest);
      prepare_output_dir(dir / label, overwrite);
      scene.output.dir.clear();  // validating writes nothing
      Simulation check(scene);
    } catch (const ManifestError& e) {
      throw ManifestError(label + ": " + e.path(), std::string(e.what()).substr(std::string("manifest: ").size()));
    } catch (const PluginError& e) {
      throw PluginError(label + ": " + e.what());
    }
  }
}

// --seeds K: A and B on each of K tissues (the manifest's seed and the K - 1
// after it), then the paired statistics; the first pair's comparison and
// traces as without seeds.
std::string compare_over_seeds(const json& a, const json& b, const std::filesystem::path& dir, const CompareArgs& args) {
  const long long first = first_seed(a);
  std::vector<json> summaries_a, summaries_b;
  std::vector<long long> seeds;
  std::vector<RunRecord> first_pair;
  std::vector<std::string> first_dirs;
  for (int k = 0; k < args.seeds; ++k) {
    const long long seed = first + k;
    json a_k = a, b_k = b;
    a_k["seed"] = b_k["seed"] = seed;
    const std::string tissue = "seed_" + std::to_string(seed);
    Variant va = run_variant(tissue + "/A", a_k, dir, args);
    Variant vb = run_variant(tissue + "/B", b_k, dir, args);
    if (k == 0) {
      write_comparison(va.record, vb.record, dir);
      first_pair.emplace_back(std::move(va.record));
      first_pair.emplace_back(std::move(vb.record));
      first_dirs = {tissue + "/A", tissue + "/B"};
    }
    summaries_a.push_back(va.summary);
    summaries_b.push_back(vb.summary);
    seeds.push_back(seed);
  }
  const std::string paired = write_paired_comparison(summaries_a, summaries_b, seeds, dir);
  if (!args.no_report)
    write_compare_report(dir, {first_pair[0], first_pair[1], first_dirs[0], first_dirs[1], paired});
  return paired;
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
    std::cout << "A: " << args.manifests.front();
    for (const auto& s : args.a_overrides) std::cout << " " << s;
    std::cout << "\nB: " << args.manifests.back();
    for (const auto& s : args.b_overrides) std::cout << " " << s;
    // --seeds: each seed's tissue is built when its pair runs (the first is checked here).
    if (args.seeds > 0) {
      json a0 = a, b0 = b;
      a0["seed"] = b0["seed"] = first_seed(a);
      const std::string tissue = "seed_" + std::to_string(first_seed(a));
      validate_variants({{tissue + "/A", &a0}, {tissue + "/B", &b0}}, dir, args.overwrite);
    } else {
      validate_variants({{"A", &a}, {"B", &b}}, dir, args.overwrite);
    }
    if (args.seeds > 0) {
      std::cout << "\n\n" << compare_over_seeds(a, b, dir, args) << "\noutputs: " << dir.string()
                << "/{report.html,paired.md,paired.csv,comparison.md,comparison.csv,traces.csv,traces.png,seed_*/A,seed_*/B}\n";
      return 0;
    }
    const Variant va = run_variant("A", a, dir, args);
    const Variant vb = run_variant("B", b, dir, args);
    write_comparison(va.record, vb.record, dir);
    if (!args.no_report) write_compare_report(dir, {va.record, vb.record, "A", "B", ""});
    std::cout << "\n\n" << comparison_markdown(va.record, vb.record) << "\noutputs: " << dir.string()
              << "/{report.html,comparison.md,comparison.csv,traces.csv,traces.png,A/,B/}\n";
    return 0;
  });
}

}  // namespace fibrodem::cli
