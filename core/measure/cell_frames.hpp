// One value of every cell at each of a run's sample times, as float
// (frame-major): output.reentry's membrane potential (measure/reentry.hpp)
// and, in a run with mechanics, the cells' fibre stretch at the same times
// (measure/cell_strain.hpp).
#pragma once

#include <cstddef>
#include <vector>

namespace fibrodem {

struct CellFrames {
  explicit CellFrames(std::size_t cell_count = 0) : cells(cell_count) {}
  std::size_t cells;
  std::vector<double> t_ms;
  std::vector<float> values;

  std::size_t count() const { return t_ms.size(); }
  const float* frame(std::size_t k) const { return &values[k * cells]; }
  // Throws std::invalid_argument if `per_cell` does not hold one value a cell.
  void add(double t, const std::vector<double>& per_cell);
  // Room for `frames` more frames at once: grown frame by frame, the array
  // doubles its capacity, and while it moves the old and the new copies
  // both hold every frame so far (up to twice the frames' bytes resident).
  void reserve_more(std::size_t frames);
};

// V of every cell at each re-entry sample [mV].
using VoltageFrames = CellFrames;
// The fibre stretch lambda_f of every cell at each re-entry sample.
using StretchFrames = CellFrames;

}  // namespace fibrodem
