#include "measure/cell_frames.hpp"

#include <stdexcept>
#include <string>

namespace fibrodem {

void CellFrames::add(double t, const std::vector<double>& per_cell) {
  if (per_cell.size() != cells)
    throw std::invalid_argument("a frame of " + std::to_string(per_cell.size()) + " values for " +
                                std::to_string(cells) + " cells");
  t_ms.push_back(t);
  values.insert(values.end(), per_cell.begin(), per_cell.end());
}

void CellFrames::reserve_more(std::size_t frames) {
  t_ms.reserve(t_ms.size() + frames);
  values.reserve(values.size() + frames * cells);
}

}  // namespace fibrodem
