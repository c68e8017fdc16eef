#include "report/snapshot_frames.hpp"

#include <algorithm>
#include <cmath>

#include "io/drawing.hpp"

namespace fibrodem {

std::vector<std::size_t> evenly_spread(std::size_t n, std::size_t most) {
  std::vector<std::size_t> picked;
  if (n == 0 || most == 0) return picked;
  if (n <= most || most == 1) {
    for (std::size_t k = 0; k < std::min(n, most); ++k) picked.push_back(k);
    return picked;
  }
  // k (n - 1) / (most - 1), rounded: distinct since the step exceeds 1.
  for (std::size_t k = 0; k < most; ++k)
    picked.push_back(static_cast<std::size_t>(std::llround(static_cast<double>(k) * (n - 1) / (most - 1))));
  return picked;
}

std::string png_at_most_wide(const std::filesystem::path& png, int max_width_px) {
  return drawing().png_at_most_wide(png, max_width_px);
}

std::vector<std::pair<std::string, std::string>> animation_frames(
    const std::vector<std::pair<std::string, std::filesystem::path>>& frames, std::size_t most, int max_width_px) {
  std::vector<std::pair<std::string, std::string>> out;
  for (std::size_t k : evenly_spread(frames.size(), most)) {
    std::string bytes = png_at_most_wide(frames[k].second, max_width_px);
    if (!bytes.empty()) out.emplace_back(frames[k].first, std::move(bytes));
  }
  return out;
}

}  // namespace fibrodem
