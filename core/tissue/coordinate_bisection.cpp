#include "tissue/coordinate_bisection.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

namespace fibrodem {

namespace {

// A level's histogram passes keep about this many buckets over all of its
// boxes (40 bytes each).
constexpr std::size_t kBucketBudget = std::size_t{1} << 18;

struct Bucket {
  std::size_t count = 0;
  CellBox box;  // of its cells
};

// A collected candidate: its coordinate along the search's axis, its
// number, and its coordinate across.
struct Candidate {
  double along_um;
  int cell;
  double across_um;
};
static_assert(sizeof(Candidate) == CoordinateCuts::kCandidateBytes);

}  // namespace

void CellBox::add(double x, double y) {
  x_low = std::min(x_low, x), x_high = std::max(x_high, x);
  y_low = std::min(y_low, y), y_high = std::max(y_high, y);
}

void CellBox::add(const CellBox& other) {
  x_low = std::min(x_low, other.x_low), x_high = std::max(x_high, other.x_high);
  y_low = std::min(y_low, other.y_low), y_high = std::max(y_high, other.y_high);
}

// The search for one box's median along its axis: the cell of rank `rank`
// among the box's cells in (coordinate, number) order. Its candidates are
// the cells whose coordinate lies in [low, high]; `below` of the box's
// cells lie under low. Each histogram pass narrows the interval to one
// bucket's cells (strictly fewer: the interval's two ends fall in its
// first and last buckets); once few enough, or all at one coordinate, the
// candidates are collected and the median picked. The cells left out on
// either side, and the candidates once split, give the two halves' boxes,
// so that the next level needs no pass for them.
class CoordinateCuts::Search {
 public:
  Search(int node, std::size_t rank, bool along_x, const CellBox& box, std::size_t cells)
      : node_(node),
        rank_(rank),
        along_x_(along_x),
        low_(along_x ? box.x_low : box.y_low),
        high_(along_x ? box.x_high : box.y_high),
        candidates_(cells) {}

  int node() const { return node_; }
  std::size_t rank() const { return rank_; }
  bool along_x() const { return along_x_; }
  const CellBox& lower_box() const { return lower_box_; }
  const CellBox& upper_box() const { return upper_box_; }
  bool collecting(std::size_t collect_limit) const { return candidates_ <= collect_limit || low_ == high_; }

  void start_pass(bool collect, std::size_t buckets) {
    collect_ = collect;
    if (collect) {
      collected_.reserve(candidates_);
      return;
    }
    buckets_.assign(buckets, Bucket{});
    // (Monotone in the coordinate: the interval's ends fall in the first and
    // last buckets.)
    bucket_scale_ = static_cast<double>(buckets) / (high_ - low_);
  }
  void add(int cell, double x_um, double y_um) {
    const double along = along_x_ ? x_um : y_um;
    if (along < low_ || along > high_) return;
    if (collect_) {
      collected_.push_back({along, cell, along_x_ ? y_um : x_um});
      return;
    }
    const auto at = static_cast<std::size_t>((along - low_) * bucket_scale_);  // (>= 0: truncation is floor)
    Bucket& b = buckets_[std::min(buckets_.size() - 1, at)];
    ++b.count;
    b.box.add(x_um, y_um);
  }
  // After a histogram pass: the interval becomes the bucket holding the
  // sought cell; the buckets on either side go to the halves' boxes.
  void narrow() {
    const std::size_t sought = rank_ - below_;
    std::size_t before = 0, chosen = buckets_.size();
    for (std::size_t k = 0; k < buckets_.size(); ++k) {
      const Bucket& b = buckets_[k];
      if (b.count == 0) continue;
      if (chosen < k) {
        upper_box_.add(b.box);
      } else if (before + b.count > sought) {
        chosen = k;
        below_ += before, candidates_ = b.count;
        low_ = along_x_ ? b.box.x_low : b.box.y_low, high_ = along_x_ ? b.box.x_high : b.box.y_high;
      } else {
        before += b.count;
        lower_box_.add(b.box);
      }
    }
    buckets_ = {};
  }
  // After a collecting pass: the sought cell's (coordinate, number), in a
  // strict order (the same cell whatever nth_element's algorithm); the
  // candidates below it go to the lower half's box, the rest the upper's.
  std::pair<double, int> median() {
    if (collected_.size() != candidates_)
      throw std::logic_error("CoordinateCuts: the cells changed between passes (" + std::to_string(collected_.size()) +
                             " collected of " + std::to_string(candidates_) + ")");
    const auto middle = collected_.begin() + static_cast<std::ptrdiff_t>(rank_ - below_);
    std::nth_element(collected_.begin(), middle, collected_.end(), [](const Candidate& a, const Candidate& b) {
      return a.along_um < b.along_um || (a.along_um == b.along_um && a.cell < b.cell);
    });
    for (auto c = collected_.begin(); c != collected_.end(); ++c)
      (c < middle ? lower_box_ : upper_box_)
          .add(along_x_ ? c->along_um : c->across_um, along_x_ ? c->across_um : c->along_um);
    const std::pair<double, int> at{middle->along_um, middle->cell};
    collected_ = {};
    return at;
  }

 private:
  int node_;
  std::size_t rank_;
  bool along_x_;
  double low_, high_, bucket_scale_ = 0;
  std::size_t below_ = 0, candidates_;
  bool collect_ = false;
  std::vector<Bucket> buckets_;
  std::vector<Candidate> collected_;
  CellBox lower_box_, upper_box_;
};

std::size_t CoordinateCuts::cells_in(int part) const {
  return cells_per_part_ + (static_cast<std::size_t>(part) < parts_with_one_more_ ? 1 : 0);
}

std::vector<std::size_t> CoordinateCuts::sizes() const {
  std::vector<std::size_t> sizes(static_cast<std::size_t>(parts_));
  for (int part = 0; part < parts_; ++part) sizes[static_cast<std::size_t>(part)] = cells_in(part);
  return sizes;
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

// Node n cut where its search found the median: its cells below it (as
// many as the search's rank) take its lower half of parts (rounded down).
// Children holding more than one part join the next level.
void CoordinateCuts::cut(std::size_t n, const Search& search, std::pair<double, int> at, std::vector<int>& next_level) {
  const Node parent = nodes_[n];
  const int lower_parts = parent.parts / 2;
  const Node lower{parent.first_part, lower_parts, search.rank(), search.lower_box()};
  const Node upper{parent.first_part + lower_parts, parent.parts - lower_parts, parent.cells - search.rank(),
                   search.upper_box()};
  for (const Node& child : {lower, upper}) {
    if (child.parts > 1) next_level.push_back(static_cast<int>(nodes_.size()));
    nodes_.push_back(child);
  }
  Node& node = nodes_[n];
  node.along_x = search.along_x(), node.at_um = at.first, node.at_cell = at.second;
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
  nodes_.push_back({0, parts, cells, CellBox{}});
  if (parts == 1) return;
  each_cell([this](int, double x, double y) { nodes_[0].box.add(x, y); });
  // Each level's boxes are cut at once, by passes narrowing every box's
  // median until each is found.
  for (std::vector<int> level{0}; !level.empty();) {
    std::vector<int> search_of(nodes_.size(), -1);  // node -> its search
    for (std::size_t i = 0; i < level.size(); ++i) search_of[static_cast<std::size_t>(level[i])] = static_cast<int>(i);
    std::vector<Search> searches = start_searches(level, pitch);
    level = cut_at_medians(searches, search_of, each_cell, collect_budget);
  }
}

// A level's searches: each box's axis, across its longer side in cells,
// and the rank of its median (the cells its lower parts hold).
std::vector<CoordinateCuts::Search> CoordinateCuts::start_searches(const std::vector<int>& level,
                                                                   CellPitch pitch) const {
  std::vector<Search> searches;
  for (const int n : level) {
    const Node& node = nodes_[static_cast<std::size_t>(n)];
    const CellBox& b = node.box;
    const bool along_x = (b.x_high - b.x_low) / pitch.x_um >= (b.y_high - b.y_low) / pitch.y_um;
    std::size_t lower_cells = 0;
    for (int p = node.first_part; p < node.first_part + node.parts / 2; ++p) lower_cells += cells_in(p);
    searches.emplace_back(n, lower_cells, along_x, b, node.cells);
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
      searches[static_cast<std::size_t>(s)].add(cell, x, y);
    });
    for (std::size_t i = 0; i < searches.size(); ++i) {
      if (found[i]) continue;
      if (!collects[i]) {
        searches[i].narrow();
        continue;
      }
      const std::pair<double, int> at = searches[i].median();
      cut(static_cast<std::size_t>(searches[i].node()), searches[i], at, next_level);
      search_of.resize(nodes_.size(), -1);  // (cells below a cut box no longer count for its search)
      found[i] = 1;
      --open;
    }
  }
  return next_level;
}

}  // namespace fibrodem
