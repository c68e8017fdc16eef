#include "report/biomarker_spread.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

namespace fibrodem {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

BiomarkerDigest::BiomarkerDigest(const std::vector<std::string>& header, std::set<int> typed_cells)
    : type_column_(csv_column(header, "type")), cell_column_(csv_column(header, "cell")),
      activation_column_(csv_column(header, "activation_ms")), typed_cells_(std::move(typed_cells)) {
  for (const auto& metric : kBiomarkerColumns)
    if (const auto column = csv_column(header, metric)) columns_.emplace_back(metric, *column);
}

std::size_t BiomarkerDigest::type_index(const std::string& type) {
  const auto seen = std::find(types_seen_.begin(), types_seen_.end(), type);
  if (seen != types_seen_.end()) return static_cast<std::size_t>(seen - types_seen_.begin());
  types_seen_.push_back(type);
  not_fired_.push_back(0);
  tallies_.resize(types_seen_.size() * columns_.size());
  return types_seen_.size() - 1;
}

void BiomarkerDigest::first_pass(const std::vector<std::string>& row) {
  ++rows_;
  if (!type_column_) return;
  const std::string& type = row[*type_column_];
  const std::size_t t = type_index(type);
  const bool measured = fired(row);
  if (!measured) ++not_fired_[t];
  for (std::size_t m = 0; measured && m < columns_.size(); ++m) {
    const double v = csv_number(row[columns_[m].second]);
    if (!std::isfinite(v)) continue;
    Tally& s = tally(t, m);
    s.lo = s.n == 0 ? v : std::min(s.lo, v);
    s.hi = s.n == 0 ? v : std::max(s.hi, v);
    s.sum += v;
    ++s.n;
  }
  if (cell_column_ && !typed_cells_.empty()) {
    const std::string& text = row[*cell_column_];
    char* end = nullptr;
    const long index = std::strtol(text.c_str(), &end, 10);
    if (end != text.c_str() && typed_cells_.count(static_cast<int>(index)))
      types_.emplace(static_cast<int>(index), type);
  }
}

void BiomarkerDigest::second_pass(const std::vector<std::string>& row) {
  if (!binned_) {  // the bins on the ranges of the first pass
    binned_ = true;
    for (Tally& s : tallies_) {
      if (s.n == 0) continue;
      double lo = s.lo, hi = s.hi;
      if (hi - lo < 1e-9 * std::max(1.0, std::abs(lo))) lo -= 0.5, hi += 0.5;  // one value: one bin around it
      const std::size_t bins = static_cast<std::size_t>(std::ceil(std::log2(static_cast<double>(s.n)))) + 1;
      s.count.assign(bins, 0.0);
      s.bin_lo = lo;
      s.bin_hi = hi;
      s.bin_width = (hi - lo) / static_cast<double>(bins);
    }
  }
  if (!type_column_) return;
  const auto seen = std::find(types_seen_.begin(), types_seen_.end(), row[*type_column_]);
  if (seen == types_seen_.end()) return;  // not a row of the first pass
  const auto t = static_cast<std::size_t>(seen - types_seen_.begin());
  if (!fired(row)) return;  // counted in the first pass
  for (std::size_t m = 0; m < columns_.size(); ++m) {
    const double v = csv_number(row[columns_[m].second]);
    Tally& s = tally(t, m);
    if (!std::isfinite(v) || s.count.empty()) continue;
    const double mean = s.sum / static_cast<double>(s.n);
    s.squares += (v - mean) * (v - mean);
    const std::size_t bins = s.count.size();
    ++s.count[std::min(bins - 1, static_cast<std::size_t>(std::max(0.0, (v - s.bin_lo) / s.bin_width)))];
  }
}

bool BiomarkerDigest::fired(const std::vector<std::string>& row) const {
  return !activation_column_ || !row[*activation_column_].empty();
}

std::vector<std::pair<std::string, std::size_t>> BiomarkerDigest::not_fired() const {
  std::vector<std::pair<std::string, std::size_t>> out;
  for (std::size_t t = 0; t < types_seen_.size(); ++t) out.emplace_back(types_seen_[t], not_fired_[t]);
  return out;
}

std::vector<BiomarkerSpread> BiomarkerDigest::spread() const {
  std::vector<BiomarkerSpread> out;
  for (std::size_t t = 0; t < types_seen_.size(); ++t)
    for (std::size_t m = 0; m < columns_.size(); ++m) {
      const Tally& s = tally(t, m);
      const double n = static_cast<double>(s.n);
      out.push_back({types_seen_[t], columns_[m].first, s.n, s.n > 0 ? s.sum / n : kNaN,
                     s.n > 1 ? std::sqrt(s.squares / (n - 1)) : kNaN, s.n > 0 ? s.lo : kNaN, s.n > 0 ? s.hi : kNaN});
    }
  return out;
}

std::vector<PlotPanel> BiomarkerDigest::histograms() const {
  std::vector<PlotPanel> panels;
  for (std::size_t t = 0; t < types_seen_.size(); ++t)
    for (std::size_t m = 0; m < columns_.size(); ++m) {
      const Tally& s = tally(t, m);
      if (s.count.empty()) continue;
      const std::string& metric = columns_[m].first;
      // A step line: up and across each bar.
      PlotSeries series{"n = " + std::to_string(s.n), {s.bin_lo}, {0.0}};
      series.markers = false;
      for (std::size_t b = 0; b < s.count.size(); ++b) {
        const double left = s.bin_lo + static_cast<double>(b) * s.bin_width;
        series.x.insert(series.x.end(), {left, left + s.bin_width});
        series.y.insert(series.y.end(), {s.count[b], s.count[b]});
      }
      series.x.push_back(s.bin_hi);
      series.y.push_back(0.0);
      panels.push_back({types_seen_[t] + ": " + metric, metric, "cell-beats", false, false, {std::move(series)}, {}});
    }
  return panels;
}

std::optional<BiomarkerDigest> digest_biomarkers_csv(const std::filesystem::path& file,
                                                     const std::set<int>& typed_cells) {
  CsvRowReader first(file);
  if (!first.ok()) return std::nullopt;
  BiomarkerDigest digest(first.header(), typed_cells);
  std::vector<std::string> row;
  std::size_t rows = 0;
  while (first.next(row)) digest.first_pass(row), ++rows;
  CsvRowReader second(file);
  // The file is read again from its start: a run still appending to it adds
  // rows past those of the first pass, which the second leaves out.
  for (std::size_t r = 0; r < rows && second.next(row); ++r) digest.second_pass(row);
  return digest;
}

}  // namespace fibrodem
