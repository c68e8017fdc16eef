// The myocytes' new shapes at the cells' length ratios (dem_bodies.hpp): a
// clump contracts along its axis; its centroid and axis stay.
#include <stdexcept>
#include <string>
#include <vector>

#include "mechanics/dem_bodies.hpp"
#include "mechanics/dem_units.hpp"
#include "util/number_text.hpp"

namespace fibrodem {

void DemBodies::set_cell_length_ratios(const std::vector<double>& ratio) {
  if (ratio.size() != cells)
    throw std::invalid_argument("set_cell_length_ratios: " + std::to_string(ratio.size()) +
                                " ratios for " + std::to_string(cells) + " cells");
  // Each myocyte's new shape (cells are independent: in parallel), kept only
  // if every ratio is in range and every shape exists; else the error of the
  // first cell that fails, and nothing changed. The bodies are taken in
  // fixed parts of equal clump counts (only clumps change shape; the
  // interstitial tissue lists them first), a thread the same parts every
  // step, so that a body's data stay in one core's cache (parts handed out
  // as the threads come free would move between the cores).
  const std::size_t none = cells;
  std::size_t failed = none;
  std::string error;
#pragma omp parallel
  {
#pragma omp for schedule(static)
    for (std::size_t k = 0; k < kStepParts; ++k)
      for (std::size_t b = shape_part_first_body[k]; b < shape_part_first_body[k + 1]; ++b) {
        if (!bclump[b] || !steps(b)) continue;  // a fibroblast keeps its disk; another rank's body
        const auto c = static_cast<std::size_t>(bcell[b]);
        const double l = ratio[c];
        if (!(l >= 0.5 && l <= 1.5)) {
#pragma omp critical(dem_shape_error)
          if (c < failed) {
            failed = c;
            error = "cell " + std::to_string(c) + ": length ratio " + significant_digits(l, 6) + " outside [0.5, 1.5]";
          }
          continue;
        }
        if (brest[b].n < 2) continue;
        next_r[b] = btarget_r[b];
        next_s[b] = btarget_s[b];
        if (l == blambda[b]) continue;
        try {
          const ClumpShape shape = contracted_shape(area_rule, length_mode, brest[b], l,
                                                    btarget_r[b]);
          next_r[b] = shape.r;
          next_s[b] = shape.s;
        } catch (const std::invalid_argument& e) {
#pragma omp critical(dem_shape_error)
          if (c < failed) {
            failed = c;
            error = e.what();
          }
        }
      }
    // (After the loop's barrier every thread reads the same `failed`.)
    if (failed == none) {
#pragma omp for schedule(static) nowait
      for (std::size_t k = 0; k < kStepParts; ++k)
        for (std::size_t b = shape_part_first_body[k]; b < shape_part_first_body[k + 1]; ++b) {
          if (!bclump[b] || brest[b].n < 2 || !steps(b)) continue;
          blambda[b] = ratio[static_cast<std::size_t>(bcell[b])];
          btarget_r[b] = next_r[b];
          btarget_s[b] = next_s[b];
        }
    }
  }
  if (failed != none) throw std::invalid_argument(error);
}

}  // namespace fibrodem
