#include "measure/accuracy.hpp"

#include <cmath>
#include <map>
#include <utility>

namespace fibrodem {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kTimeMatch_ms = 1e-6;

bool is_column_of(const std::string& column, const std::string& variable) {
  if (column.size() <= variable.size() + 1 || column.compare(0, variable.size(), variable) != 0 ||
      column[variable.size()] != '_')
    return false;
  for (std::size_t i = variable.size() + 1; i < column.size(); ++i)
    if (column[i] < '0' || column[i] > '9') return false;
  return true;
}

// Pairs of indices (reference, candidate) of the sample times both runs have.
std::vector<std::pair<std::size_t, std::size_t>> common_times(const std::vector<double>& a,
                                                              const std::vector<double>& b) {
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (std::abs(a[i] - b[j]) <= kTimeMatch_ms) pairs.emplace_back(i++, j++);
    else if (a[i] < b[j]) ++i;
    else ++j;
  }
  return pairs;
}

void raise(double& max, double value) {
  if (std::isnan(max) || value > max) max = value;
}

}  // namespace

AccuracyErrors compare_runs(const RunRecord& reference, const RunRecord& candidate, const std::string& variable) {
  AccuracyErrors e;

  // Traces: columns of the variable present in both, on the common times.
  const auto times = common_times(reference.times_ms, candidate.times_ms);
  double sum_sq = 0;
  for (std::size_t c = 0; c < reference.columns.size(); ++c) {
    if (!is_column_of(reference.columns[c], variable)) continue;
    std::size_t k = 0;
    while (k < candidate.columns.size() && candidate.columns[k] != reference.columns[c]) ++k;
    if (k == candidate.columns.size()) continue;
    const auto& ref = reference.samples[c];
    const auto& cand = candidate.samples[k];
    for (const auto& [i, j] : times) {
      if (i >= ref.size() || j >= cand.size()) continue;
      const double d = std::abs(cand[j] - ref[i]);
      const double dd = std::isfinite(d) ? d : kInf;
      sum_sq += dd * dd;
      raise(e.v_max_mV, dd);
      ++e.v_samples;
    }
  }
  if (e.v_samples > 0) e.v_rms_mV = std::sqrt(sum_sq / static_cast<double>(e.v_samples));

  // Biomarkers, beat by beat.
  std::map<std::pair<int, int>, const BeatBiomarkers*> by_key;
  for (const auto& b : candidate.beats) by_key[{b.cell, b.beat}] = &b;
  for (const auto& ref : reference.beats) {
    ++e.beats_compared;
    const auto it = by_key.find({ref.cell, ref.beat});
    if (it == by_key.end()) {
      ++e.beats_mismatched;
      e.apd90_max_ms = e.activation_max_ms = kInf;
      continue;
    }
    const BeatBiomarkers& cand = *it->second;
    if (fired(ref) != fired(cand)) {  // one fired, the other did not: no time to compare
      ++e.beats_mismatched;
      e.apd90_max_ms = e.activation_max_ms = kInf;
      continue;
    }
    if (!fired(ref)) continue;  // neither fired: they agree, with nothing to measure
    raise(e.activation_max_ms, std::abs(cand.activation_ms - ref.activation_ms));
    const bool ref_apd = std::isfinite(ref.apd90_ms), cand_apd = std::isfinite(cand.apd90_ms);
    if (ref_apd && cand_apd) raise(e.apd90_max_ms, std::abs(cand.apd90_ms - ref.apd90_ms));
    else if (ref_apd != cand_apd) {
      ++e.beats_mismatched;
      e.apd90_max_ms = kInf;
    }
  }

  // Conduction velocity.
  if (reference.cv_cm_per_s) {
    if (candidate.cv_cm_per_s) {
      e.cv_abs_cm_per_s = std::abs(*candidate.cv_cm_per_s - *reference.cv_cm_per_s);
      e.cv_rel = e.cv_abs_cm_per_s / std::abs(*reference.cv_cm_per_s);
    } else {
      e.cv_abs_cm_per_s = e.cv_rel = kInf;
    }
  }
  return e;
}

std::optional<std::size_t> cheapest_meeting(const std::vector<LadderRun>& runs,
                                            const std::function<double(const AccuracyErrors&)>& metric,
                                            double threshold, const std::string& method) {
  std::optional<std::size_t> best;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const LadderRun& r = runs[i];
    if (!r.completed || (!method.empty() && r.method != method)) continue;
    const auto meets = [&](const LadderRun& run) { return run.completed && metric(run.errors) <= threshold; };
    if (!meets(r)) continue;  // NaN never qualifies
    bool finer_meet = true;
    for (const auto& f : runs)
      if (f.method == r.method && f.setting < r.setting && !meets(f)) finer_meet = false;
    if (!finer_meet) continue;
    if (!best || r.wall_s < runs[*best].wall_s) best = i;
  }
  return best;
}

}  // namespace fibrodem
