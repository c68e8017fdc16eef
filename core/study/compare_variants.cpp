#include "study/compare_variants.hpp"

#include "compare/paired_comparison.hpp"
#include "measure/summary_metrics.hpp"
#include "report/compare_report.hpp"
#include "run/output_dir.hpp"
#include "run/run_record.hpp"
#include "run/simulation.hpp"
#include "study/plugin_search.hpp"

namespace fibrodem {

namespace fs = std::filesystem;

namespace {

struct Variant {
  RunRecord record;
  json summary;
};

Variant run_variant(const std::string& label, const json& manifest, const CompareOptions& options) {
  Scene scene = parse_scene(manifest);
  scene.output.dir = (options.out / label).string();
  scene.output.overwrite = options.overwrite;
  if (!options.report) scene.output.report = false;
  RunOptions run_options;
  run_options.console_log = options.console_log;
  Simulation simulation(scene, registry_searching(scene, options.plugin_search_path), run_options);
  simulation.run();
  return {record_of(simulation, label.substr(label.rfind('/') + 1)), simulation.summary()};
}

long long first_seed(const json& a) {
  return a.contains("seed") && a["seed"].is_number_integer() ? a["seed"].get<long long>() : 0;
}

// Both variants' scenes built (tissue, plugins, names, traces) and their output
// folders checked before either runs; errors say which variant.
void validate_variants(const std::vector<std::pair<std::string, const json*>>& variants,
                       const CompareOptions& options) {
  for (const auto& [label, manifest] : variants) {
    try {
      Scene scene = parse_scene(*manifest);
      prepare_output_dir(options.out / label, options.overwrite);
      scene.output.dir.clear();  // validating writes nothing
      Simulation check(scene, registry_searching(scene, options.plugin_search_path));
    } catch (const ManifestError& e) {
      throw ManifestError(label + ": " + e.path(), e.detail());
    } catch (const PluginError& e) {
      throw PluginError(label + ": " + e.what());
    }
  }
}

// A and B on each of K tissues (A's seed and the K - 1 after it), then the
// paired statistics; the first pair's comparison and traces as without seeds.
void compare_over_seeds(const json& a, const json& b, const CompareOptions& options, CompareResult& result) {
  const long long first = first_seed(a);
  std::vector<RunRecord> first_pair;
  for (int k = 0; k < options.seeds; ++k) {
    const long long seed = first + k;
    json a_k = a, b_k = b;
    a_k["seed"] = b_k["seed"] = seed;
    const std::string tissue = "seed_" + std::to_string(seed);
    Variant va = run_variant(tissue + "/A", a_k, options);
    Variant vb = run_variant(tissue + "/B", b_k, options);
    if (k == 0) {
      write_comparison(va.record, vb.record, options.out);
      result.rows = compare_biomarkers(va.record, vb.record);
      first_pair.emplace_back(std::move(va.record));
      first_pair.emplace_back(std::move(vb.record));
      result.a_dir = tissue + "/A", result.b_dir = tissue + "/B";
    }
    result.summaries_a.push_back(va.summary);
    result.summaries_b.push_back(vb.summary);
    result.seeds.push_back(seed);
  }
  result.markdown = write_paired_comparison(result.summaries_a, result.summaries_b, result.seeds, options.out);
  result.paired = paired_rows(result.summaries_a, result.summaries_b);
  if (options.report)
    write_compare_report(options.out, {first_pair[0], first_pair[1], result.a_dir, result.b_dir, result.markdown});
}

}  // namespace

fs::path default_compare_dir(const json& a) { return "out/compare_" + a.value("name", std::string("scene")); }

CompareResult run_compare(const json& a, const json& b, const CompareOptions& options) {
  if (options.out.empty()) throw std::invalid_argument("run_compare: no output folder");
  CompareResult result;
  result.dir = options.out;
  // With seeds, each seed's tissue is built when its pair runs (the first is checked here).
  if (options.seeds > 0) {
    json a0 = a, b0 = b;
    a0["seed"] = b0["seed"] = first_seed(a);
    const std::string tissue = "seed_" + std::to_string(first_seed(a));
    validate_variants({{tissue + "/A", &a0}, {tissue + "/B", &b0}}, options);
    compare_over_seeds(a, b, options, result);
    return result;
  }
  validate_variants({{"A", &a}, {"B", &b}}, options);
  const Variant va = run_variant("A", a, options);
  const Variant vb = run_variant("B", b, options);
  write_comparison(va.record, vb.record, options.out);
  if (options.report) write_compare_report(options.out, {va.record, vb.record, "A", "B", ""});
  result.a_dir = "A", result.b_dir = "B";
  result.rows = compare_biomarkers(va.record, vb.record);
  result.summaries_a = {va.summary};
  result.summaries_b = {vb.summary};
  result.markdown = comparison_markdown(va.record, vb.record);
  return result;
}

}  // namespace fibrodem
