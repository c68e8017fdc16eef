#include "compare/paired_comparison.hpp"

#include <cmath>
#include <fstream>
#include <sstream>

#include "io/csv_writer.hpp"
#include "measure/sample_statistics.hpp"
#include "measure/summary_metrics.hpp"
#include "util/number_text.hpp"

namespace fibrodem {

namespace {

std::string fixed(double v, int digits) { return fixed_decimals(v, digits); }

std::string p_text(double p) {
  if (!std::isfinite(p)) return "";
  if (p < 1e-4) return "< 1e-4";
  return significant_digits(p, 2);
}

}  // namespace

std::vector<PairedRow> paired_rows(const std::vector<json>& a, const std::vector<json>& b) {
  std::vector<PairedRow> rows;
  for (const auto& metric : summary_metrics()) {
    std::vector<double> va, vb;
    for (std::size_t k = 0; k < a.size() && k < b.size(); ++k) {
      va.push_back(metric.of(a[k]));
      vb.push_back(metric.of(b[k]));
    }
    const PairedTest test = paired_t_test(va, vb);
    if (test.difference.n == 0) continue;  // the scene does not measure it
    rows.push_back({metric.name, summarize(va).mean, summarize(vb).mean, test.difference, test.t, test.p});
  }
  return rows;
}

std::string write_paired_comparison(const std::vector<json>& a, const std::vector<json>& b,
                                    const std::vector<long long>& seeds, const std::filesystem::path& dir) {
  CsvWriter csv(dir / "paired.csv", {"metric", "pairs", "a_mean", "b_mean", "b_minus_a_mean", "b_minus_a_sd",
                                     "ci95_low", "ci95_high", "t", "p"});
  std::ostringstream md;
  md << "A and B on the same " << seeds.size() << " tissues (seeds";
  for (long long s : seeds) md << " " << s;
  md << "): paired differences B - A, mean [95 % CI], paired t-test (two-sided).\n\n"
     << "| metric | pairs | A | B | B - A [95 % CI] | t | p |\n|---|---:|---:|---:|---:|---:|---:|\n";
  for (const PairedRow& row : paired_rows(a, b)) {
    const SampleSummary& d = row.difference;
    csv.cell(row.metric).cell(static_cast<long long>(d.n));
    for (double v : {row.a_mean, row.b_mean, d.mean, d.sd, d.ci95_low, d.ci95_high, row.t, row.p})
      csv.cell(std::isfinite(v) ? format_number(v) : std::string());
    csv.end_row();
    const int digits = row.metric.rfind("peak_eps", 0) == 0 ? 6 : 3;
    md << "| " << row.metric << " | " << d.n << " | " << fixed(row.a_mean, digits) << " | " << fixed(row.b_mean, digits)
       << " | " << fixed(d.mean, digits)
       << (std::isfinite(d.ci95_low) ? " [" + fixed(d.ci95_low, digits) + ", " + fixed(d.ci95_high, digits) + "]" : "")
       << " | " << fixed(row.t, 2) << " | " << p_text(row.p) << " |\n";
  }
  std::ofstream(dir / "paired.md") << md.str();
  return md.str();
}

}  // namespace fibrodem
