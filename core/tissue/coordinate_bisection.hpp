// Recursive coordinate bisection of the cells: the cells split into parts
// by straight cuts through their centres, each cut across the longer side
// of its cells' bounding box, measured in cells (docs/guide/parallel.md,
// Design 2). It reads the centres alone, never the cell graph; the parts
// are compact, as a spatial split of the DEM wants.
//
// The cuts are found from the cells handed over one at a time, as often as
// asked (a pass for the tissue's box, then a few a level of cuts), so that a
// process need not hold every cell's centre to know where they lie:
// CoordinateCuts keeps the cuts alone (a few numbers a part), and tells
// any cell's part from its number and centre.
#pragma once

#include <cstddef>
#include <functional>
#include <limits>
#include <utility>
#include <vector>

namespace fibrodem {

// The cells' spacing along x and y [um]: a cut across x passes between
// columns pitch_x_um apart, so the box's sides are compared in cells.
struct CellPitch {
  double x_um = 1, y_um = 1;
};

// The bounding box of some cells' centres [um] (empty: infinite bounds).
struct CellBox {
  double x_low = std::numeric_limits<double>::infinity(), x_high = -x_low;
  double y_low = x_low, y_high = -x_low;
  void add(double x_um, double y_um);
  void add(const CellBox& other);
};

// Every cell once, in any order: visit(cell number, x_um, y_um).
using EachCellCentre = std::function<void(const std::function<void(int, double, double)>&)>;

// The cuts of `cells` cells into `parts` parts (1 <= parts <= cells): part p
// holds cells / parts cells, one more for the first cells % parts parts.
// Each cut puts the cells below a median along its axis (ties: the lower
// cell number) on the side of the lower parts, so the parts are a function
// of the cells' numbers and centres alone, whatever order they come in.
class CoordinateCuts {
 public:
  // `collect_budget`: about how many cells' coordinates a pass may hold at
  // once (kCandidateBytes each) to pick the medians among; more passes
  // narrow the boxes' medians down to it.
  static constexpr std::size_t kCollectBudget = std::size_t{1} << 16;
  static constexpr std::size_t kCandidateBytes = 24;
  CoordinateCuts(std::size_t cells, int parts, CellPitch pitch, const EachCellCentre& each_cell,
                 std::size_t collect_budget = kCollectBudget);

  int parts() const { return parts_; }
  std::vector<std::size_t> sizes() const;  // cells per part
  // The part of a cell of the tissue cut (its number and centre).
  int part_of(int cell, double x_um, double y_um) const;

 private:
  // A box of cells holding parts [first_part, first_part + parts); split
  // (parts > 1) by a cut: cells whose (coordinate along the axis, number)
  // is below (at_um, at_cell) go to `lower`, the rest to `upper`.
  struct Node {
    int first_part = 0, parts = 1;
    std::size_t cells = 0;
    CellBox box;
    bool along_x = true;
    double at_um = 0;
    int at_cell = 0;
    int lower = -1, upper = -1;
  };
  class Search;

  // The node a cell is in, descending through the cuts made so far.
  int node_of(int cell, double x_um, double y_um) const;
  std::size_t cells_in(int part) const;
  std::vector<Search> start_searches(const std::vector<int>& level, CellPitch pitch) const;
  std::vector<int> cut_at_medians(std::vector<Search>& searches, std::vector<int>& search_of,
                                  const EachCellCentre& each_cell, std::size_t collect_budget);
  void cut(std::size_t n, const Search& search, std::pair<double, int> at, std::vector<int>& next_level);

  int parts_ = 1;
  std::size_t cells_per_part_ = 0, parts_with_one_more_ = 0;
  std::vector<Node> nodes_;
};

}  // namespace fibrodem
