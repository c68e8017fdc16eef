// The frames of report.html's snapshot animation: at most a given number,
// spread evenly over the run (first and last kept), each scaled down to a
// bounded width, so that the page stays a few megabytes at any tissue size
// and any number of snapshots (the PNG files beside it keep full size).
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace fibrodem {

inline constexpr std::size_t kMostAnimationFrames = 60;
inline constexpr int kAnimationWidthPx = 720;

// Indices of `most` of n items spread evenly, first and last included (all
// of them when n <= most), increasing.
std::vector<std::size_t> evenly_spread(std::size_t n, std::size_t most);

// The PNG file's bytes, scaled down (nearest pixel) to at most
// `max_width_px` wide if it is wider; empty if it cannot be read.
std::string png_at_most_wide(const std::filesystem::path& png, int max_width_px);

// (label, file) frames in time order -> (label, PNG bytes) for the page.
std::vector<std::pair<std::string, std::string>> animation_frames(
    const std::vector<std::pair<std::string, std::filesystem::path>>& frames,
    std::size_t most = kMostAnimationFrames, int max_width_px = kAnimationWidthPx);

}  // namespace fibrodem
