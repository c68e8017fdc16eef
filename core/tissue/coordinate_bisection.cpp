#include "tissue/coordinate_bisection.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

namespace fibrodem {

namespace {

// A level's histogram passes keep about this many buckets over all of its
// boxes (24 bytes each).
constexpr std::size_t kBucketBudget = std::size_t{1} << 18;

struct Box {
  double x_low = std::numeric_limits<double>::infinity(), x_high = -x_low;
  double y_low = x_low, y_high = -x_low;
  void add(double x, double y) {
    x_low = std::min(x_low, x), x_high = std::max(x_high, x);
    y_low = std::min(y_low, y), y_high = std::max(y_high, y);
  }
};

struct Bucket {
  std::size_t count = 0;
  double low = std::numeric_limits<double>::infinity(), high = -low;
};

}  // namespace

// The search for one box's median along its axis: the cell of rank `rank`
// among the box's cells in (coordinate, number) order. Its candidates are
// the cells whose coordinate lies in [low_um, high_um]; `below` of the
// box's cells lie under low_um. Each histogram pass narrows the interval
// to one bucket's cells (strictly fewer: the interval's two ends fall in
// its first and last buckets); once few enough, or all at one
// coordinate, the candidates are collected and the median picked.
class CoordinateCuts::Search {
 public:
  Search(int node, std::size_t rank, bool along_x, double low_um, double high_um, std::size_t cells)
      : node_(node), rank_(rank), along_x_(along_x), low_(low_um), high_(high_um), candidates_(cells) {}

  int node() const { return node_; }
  std::size_t rank() const { return rank_; }
  bool along_x() const { return along_x_; }
  bool collecting(std::size_t collect_limit) const { return candidates_ <= collect_limit || low_ == high_; }

  void start_pass(bool collect, std::size_t buckets) {
    collect_ = collect;
    if (collect)
      collected_.reserve(candidates_);
    else
      buckets_.assign(buckets, Bucket{});
  }
  void add(int cell, double along_um) {
    if (along_um < low_ || along_um > high_) return;
    if (collect_) {
      collected_.emplace_back(along_um, cell);
      return;
    }
    const auto last = buckets_.size() - 1;
    const double at = std::floor((along_um - low_) / (high_ - low_) * static_cast<double>(buckets_.size()));
    Bucket& b = buckets_[std::min(last, static_cast<std::size_t>(at))];
    ++b.count, b.low = std::min(b.low, along_um), b.high = std::max(b.high, along_um);
  }
  // After a histogram pass: the interval becomes the bucket holding the
  // sought cell.
  void narrow() {
    const std::size_t sought = rank_ - below_;
    std::size_t before = 0;
    for (const Bucket& b : buckets_) {
      if (before + b.count > sought) {
        below_ += before, low_ = b.low, high_ = b.high, candidates_ = b.count;
        break;
      }
      before += b.count;
    }
    buckets_ = {};
  }
  // After a collecting pass: the sought cell's (coordinate, number). A
  // strict order, so the same cell whatever nth_element's algorithm.
  std::pair<double, int> median() {
    if (collected_.size() != candidates_)
      throw std::logic_error("CoordinateCuts: the cells changed between passes (" + std::to_string(collected_.size()) +
                             " collected of " + std::to_string(candidates_) + ")");
    const auto middle = collected_.begin() + static_cast<std::ptrdiff_t>(rank_ - below_);
    std::nth_element(collected_.begin(), middle, collected_.end());
    return *middle;
  }

 private:
  int node_;
  std::size_t rank_;
  bool along_x_;
  double low_, high_;
  std::size_t below_ = 0, candidates_;
  bool collect_ = false;
  std::vector<Bucket> buckets_;
  std::vector<std::pair<double, int>> collected_;
};

std::size_t CoordinateCuts::cells_in(int part) const {
  return cells_per_part_ + (static_cast<std::size_t>(part) < parts_with_one_more_ ? 1 : 0);
}

int CoordinateCuts::node_of(int cell, double x_um, double y_um) const {
  int n = 0;
  while (nodes_[static_cast<std::size_t>(n)].lower >= 0) {
    const Node& node = nodes_[static_cast<std::size_t>(n)];
    const double along = node.along_x ? x_um : y_um;
    const bool below = along < node.at_um || (along == node.at_um && cell < node.at_cell);
    n = below ? node.lower : node.upper;
  }
  return n;
}

int CoordinateCuts::part_of(int cell, double x_um, double y_um) const {
  return nodes_[static_cast<std::size_t>(node_of(cell, x_um, y_um))].first_part;
}

// Node n cut at (at_um, at_cell): its lower `lower_cells` cells take its
// lower half of parts (rounded down). Children holding more than one part
// join the next level.
void CoordinateCuts::cut(std::size_t n, bool along_x, double at_um, int at_cell, std::size_t lower_cells,
                         std::vector<int>& next_level) {
  const Node parent = nodes_[n];
  const int lower_parts = parent.parts / 2;
  const Node lower{parent.first_part, lower_parts, lower_cells};
  const Node upper{parent.first_part + lower_parts, parent.parts - lower_parts, parent.cells - lower_cells};
  for (const Node& child : {lower, upper}) {
    if (child.parts > 1) next_level.push_back(static_cast<int>(nodes_.size()));
    nodes_.push_back(child);
  }
  Node& node = nodes_[n];
  node.along_x = along_x, node.at_um = at_um, node.at_cell = at_cell;
  node.lower = static_cast<int>(nodes_.size()) - 2, node.upper = static_cast<int>(nodes_.size()) - 1;
}

CoordinateCuts::CoordinateCuts(std::size_t cells, int parts, CellPitch pitch, const EachCellCentre& each_cell,
                               std::size_t collect_budget)
    : parts_(parts) {
  if (parts < 1 || static_cast<std::size_t>(parts) > cells)
    throw std::invalid_argument("cannot cut " + std::to_string(cells) + " cells into " + std::to_string(parts) +
                                " parts: expected 1 to " + std::to_string(cells));
  cells_per_part_ = cells / static_cast<std::size_t>(parts);
  parts_with_one_more_ = cells % static_cast<std::size_t>(parts);
  nodes_.push_back({0, parts, cells});
  std::vector<int> level;
  if (parts > 1) level.push_back(0);
  // Each level's boxes are cut at once: a pass for their bounding boxes,
  // then passes narrowing every box's median until each is found.
  while (!level.empty()) {
    std::vector<int> search_of(nodes_.size(), -1);  // node -> its search
    for (std::size_t i = 0; i < level.size(); ++i) search_of[static_cast<std::size_t>(level[i])] = static_cast<int>(i);
    std::vector<Search> searches = start_searches(level, search_of, pitch, each_cell);
    level = cut_at_medians(searches, search_of, each_cell, collect_budget);
  }
}

// A level's searches: each box's axis, across its longer side in cells,
// and the rank of its median (the cells its lower parts hold).
std::vector<CoordinateCuts::Search> CoordinateCuts::start_searches(const std::vector<int>& level,
                                                                   const std::vector<int>& search_of, CellPitch pitch,
                                                                   const EachCellCentre& each_cell) const {
  std::vector<Box> boxes(level.size());
  each_cell([&](int cell, double x, double y) {
    const int s = search_of[static_cast<std::size_t>(node_of(cell, x, y))];
    if (s >= 0) boxes[static_cast<std::size_t>(s)].add(x, y);
  });
  std::vector<Search> searches;
  for (std::size_t i = 0; i < level.size(); ++i) {
    const Node& node = nodes_[static_cast<std::size_t>(level[i])];
    const Box& b = boxes[i];
    const bool along_x = (b.x_high - b.x_low) / pitch.x_um >= (b.y_high - b.y_low) / pitch.y_um;
    std::size_t lower_cells = 0;
    for (int p = node.first_part; p < node.first_part + node.parts / 2; ++p) lower_cells += cells_in(p);
    searches.emplace_back(level[i], lower_cells, along_x, along_x ? b.x_low : b.y_low, along_x ? b.x_high : b.y_high,
                          node.cells);
  }
  return searches;
}

// Passes over the cells until every search has found its median and its
// box is cut; returns the next level (the new boxes of several parts).
std::vector<int> CoordinateCuts::cut_at_medians(std::vector<Search>& searches, std::vector<int>& search_of,
                                                const EachCellCentre& each_cell, std::size_t collect_budget) {
  std::vector<int> next_level;
  std::vector<char> found(searches.size(), 0), collects(searches.size(), 0);
  for (std::size_t open = searches.size(); open > 0;) {
    const std::size_t buckets = std::clamp<std::size_t>(kBucketBudget / open, 64, 4096);
    const std::size_t collect_limit = std::max<std::size_t>(16, collect_budget / open);
    for (std::size_t i = 0; i < searches.size(); ++i) {
      if (found[i]) continue;
      collects[i] = searches[i].collecting(collect_limit);
      searches[i].start_pass(collects[i], buckets);
    }
    each_cell([&](int cell, double x, double y) {
      const int s = search_of[static_cast<std::size_t>(node_of(cell, x, y))];
      if (s < 0) return;
      Search& search = searches[static_cast<std::size_t>(s)];
      search.add(cell, search.along_x() ? x : y);
    });
    for (std::size_t i = 0; i < searches.size(); ++i) {
      if (found[i]) continue;
      if (!collects[i]) {
        searches[i].narrow();
        continue;
      }
      const auto [at_um, at_cell] = searches[i].median();
      cut(static_cast<std::size_t>(searches[i].node()), searches[i].along_x(), at_um, at_cell, searches[i].rank(),
          next_level);
      search_of.resize(nodes_.size(), -1);  // (cells below a cut box no longer count for its search)
      found[i] = 1;
      --open;
    }
  }
  return next_level;
}

}  // namespace fibrodem
