// The tissue's cells split into parts, one per MPI rank of a run over
// several ranks (docs/guide/parallel.md): parts of nearly equal cell counts
// with few edges of the cell graph between them (each cut edge is a
// potential sent between two ranks at every coupling evaluation).
//
// Every rank builds the same tissue from the same scene and seed, and the
// partition is a function of the tissue alone, so every rank computes the
// same partition without communicating: by recursive coordinate bisection
// of the cells' centres (tissue/coordinate_bisection.hpp), which never needs
// the whole cell graph, or by Scotch on the whole graph (a fixed strategy, a
// fixed random seed and its deterministic mode, on one thread), which cuts
// fewer edges of an irregular graph at the cost of holding it.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <vector>

#include "tissue/cell_stream.hpp"
#include "tissue/coordinate_bisection.hpp"
#include "tissue/tissue.hpp"

namespace fibrodem {

// How the cells are split: "rcb" or "scotch" in a manifest (solver.partition).
enum class PartitionMethod { rcb, scotch };

// Load imbalance Scotch is asked to keep within: no part holds more than
// (1 + kPartImbalance) times the mean cell count (rounded up to whole cells).
inline constexpr double kPartImbalance = 0.01;

struct CellPartition {
  int parts = 1;
  std::vector<int> part_of;  // per cell: its part, in [0, parts)

  std::vector<std::size_t> sizes() const;  // cells per part
  // Edges of the tissue's cell graph whose two cells lie in different parts.
  std::size_t cut_edges(const Tissue& tissue) const;
};

// Splits the tissue's cells into `parts` parts (1 <= parts <= cell count;
// std::invalid_argument naming both otherwise). One part: every cell in part
// 0. Cells without edges (isolated fibroblasts) are placed like any other,
// counted for the balance. rcb needs the cells' centres, scotch their graph.
// `pitch`, if given, is the one rcb cuts with (cell_pitch's of the whole
// graph, for a tissue that holds part of it).
CellPartition partition_cells(const Tissue& tissue, int parts, PartitionMethod method = PartitionMethod::rcb,
                              const CellPitch* pitch = nullptr);

// partition_cells' part of each cell, asked cell by cell (a rank asks for
// its own cells' alone): rcb's held as its cuts, Scotch's for every cell.
using PartOfCell = std::function<int(int)>;
PartOfCell part_of_cells(const Tissue& tissue, int parts, PartitionMethod method,
                                      const CellPitch* pitch = nullptr);

// rcb's cuts of the tissue's cells (their centres, which it must hold) into
// `parts` parts, kept as cuts: a cell's part is then read from its centre
// (part_by_cuts), and no process need hold every cell's part. partition_cells
// with rcb gives each cell the part its centre gives here.
CoordinateCuts cut_by_centres(const Tissue& tissue, int parts, CellPitch pitch);
int part_by_cuts(const CoordinateCuts& cuts, const Tissue& tissue, int cell);

// The cells' mean spacing along x and along y: the mean of |dx| and of |dy|
// over the cell graph's edges (1 um along an axis no edge spans), which
// rcb compares its boxes' sides by.
CellPitch cell_pitch(const Tissue& tissue);

// An edge of a tissue's cell graph as a stream gives it, each end with its centre.
using VisitCellEdge = std::function<void(const CellCentre&, const CellCentre&)>;

// Rank `rank`'s cut of a tissue whose cells come one at a time from
// `cells` (a builder's stream: tissue/cell_stream.hpp), `tissue` holding
// their types alone (CellStream::cell_types): rcb's cuts (those of
// partition_cells on the whole tissue, the pitch summed in the same order)
// found in passes over the cells, then the centres the rank holds (its own
// cells' and its ghosts') and the edges it keeps (those with one of its
// cells at an end: all its ghosts and coupling need), set in the tissue
// (Tissue::hold_cells_of, Tissue::keep_part_of_graph), which reads any
// other cell's type and centre from `cells`. `every_edge`, if given, sees every edge
// on the last pass. Throws std::logic_error if the edges do not come in
// increasing order. No cell's part is held: each is read from the cuts.
struct PartialGraphCut {
  CoordinateCuts cuts;
  CellPitch pitch;
  std::size_t cut_edges = 0;  // of the whole graph
};
PartialGraphCut cut_without_graph(Tissue& tissue, int parts, int rank, std::shared_ptr<const CellStream> cells,
                                  const VisitCellEdge& every_edge = nullptr);

}  // namespace fibrodem
