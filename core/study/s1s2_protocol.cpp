#include "study/s1s2_protocol.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include "util/manifest_error.hpp"
#include "util/number_text.hpp"

namespace fibrodem {

double number_at(const json& object, const char* key, double otherwise, const std::string& path) {
  if (!object.contains(key)) return otherwise;
  if (!object[key].is_number()) throw ManifestError(join_path(path, key), "expected a number");
  return object[key].get<double>();
}

std::vector<double> train_onsets(const json& stimulus, std::size_t i) {
  const std::string path = "stimulus[" + std::to_string(i) + "]";
  const json& s = stimulus.at(i);
  if (!s.is_object()) throw ManifestError(path, "expected an object");
  const double start = number_at(s, "start_ms", 0, path), period = number_at(s, "period_ms", 0, path);
  if (period > 0 && !s.contains("count"))
    throw ManifestError(path + ".count", "an S1-S2 protocol needs a finite train: give count");
  const double count = period > 0 ? number_at(s, "count", 1, path) : 1;
  std::vector<double> onsets;
  for (int k = 0; k < static_cast<int>(count); ++k) onsets.push_back(start + k * period);
  return onsets;
}

double last_s1_onset_ms(const json& manifest, const std::string& study) {
  if (!manifest.contains("stimulus") || !manifest["stimulus"].is_array() || manifest["stimulus"].size() < 2)
    throw ManifestError("stimulus", study + " needs S1 (stimulus[0]) and S2 (stimulus[1])");
  return train_onsets(manifest["stimulus"], 0).back();
}

double coupling_interval_ms(const json& manifest, const std::string& study) {
  const double s1 = last_s1_onset_ms(manifest, study);
  return number_at(manifest["stimulus"][1], "start_ms", 0, "stimulus[1]") - s1;
}

std::optional<std::size_t> beat_of_onset(const json& manifest, double onset_ms) {
  std::set<double> onsets;
  for (std::size_t i = 0; i < manifest["stimulus"].size(); ++i)
    for (double t : train_onsets(manifest["stimulus"], i)) onsets.insert(t);
  std::size_t beat = 0;
  for (double t : onsets) {
    if (std::abs(t - onset_ms) < 1e-9) return beat;
    ++beat;
  }
  return std::nullopt;
}

double bisection_interval_ms(double low_ms, double high_ms, double resolution_ms) {
  const double half_steps = std::floor((high_ms - low_ms) / resolution_ms / 2 + 1e-9);
  return low_ms + std::max(1.0, half_steps) * resolution_ms;
}

std::string interval_text(double ms) {
  return significant_digits(ms, 10);
}

}  // namespace fibrodem
