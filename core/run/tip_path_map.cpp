#include "run/tip_path_map.hpp"

#include <spdlog/fmt/fmt.h>

#include <algorithm>

#include "io/tissue_picture.hpp"

namespace fibrodem {

void write_tip_path_map(const std::filesystem::path& file, const std::string& scene_name, const Tissue& tissue,
                        const std::vector<SingularityTrack>& tracks, const MapField& field) {
  std::vector<const SingularityTrack*> longest;
  for (const auto& track : tracks) longest.push_back(&track);
  // Longest-lived first; equal lives in order of id.
  std::stable_sort(longest.begin(), longest.end(), [](const SingularityTrack* a, const SingularityTrack* b) {
    return a->death_ms - a->birth_ms > b->death_ms - b->birth_ms;
  });
  longest.resize(std::min(longest.size(), kMostTipPaths));
  PictureOptions picture;
  picture.antialias = false;  // a palette PNG, as the other maps
  picture.value_label = field.value_label;
  picture.title = fmt::format("{}: phase singularity paths over {} (white +1, red -1; {})", scene_name, field.what,
                              longest.size() < tracks.size()
                                  ? fmt::format("the {} longest-lived of {}", longest.size(), tracks.size())
                                  : fmt::format("{} tracked", tracks.size()));
  for (const SingularityTrack* track : longest) {
    PicturePath path;
    path.light = track->chirality > 0;
    for (const auto& p : track->trajectory) {
      path.x_um.push_back(p.x_mm * 1000);
      path.y_um.push_back(p.y_mm * 1000);
    }
    picture.paths.push_back(std::move(path));
  }
  write_tissue_png(tissue, file, &field.values, picture);
}

}  // namespace fibrodem
