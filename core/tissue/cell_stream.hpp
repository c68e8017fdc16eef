// A tissue's cells and cell graph handed over one at a time, as often as
// asked, by a builder that need not hold them: for a rank of a split run,
// which keeps its own cells' and ghosts' centres and the edges at its own
// cells alone (docs/guide/parallel.md, Design 1). A builder that makes its
// cells from a compact description (fibrotic_sheet: a byte a slot) streams
// them from it; any other, from the whole tissue it builds (stream_of).
#pragma once

#include <functional>
#include <memory>

#include "tissue/tissue.hpp"

namespace fibrodem {

class CellStream {
 public:
  virtual ~CellStream() = default;
  // The tissue's cells' types alone, as the builder makes them, its
  // particles and bonds counted and their bounds kept
  // (Tissue::release_unbuilt_particles): no centres, no graph.
  virtual Tissue cell_types() const = 0;
  // Every cell once, by increasing number: visit(cell, type, x_um, y_um).
  virtual void for_each_cell(const std::function<void(int, CellType, double, double)>& visit) const = 0;
  // Every edge of the cell graph once, in Tissue::cell_edges' order
  // (increasing), each end with its centre.
  virtual void for_each_edge(const std::function<void(const CellCentre&, const CellCentre&)>& visit) const = 0;
};

// The stream of a tissue's cells (built with its centres and graph),
// which it holds.
std::unique_ptr<CellStream> stream_of(Tissue tissue);

}  // namespace fibrodem
