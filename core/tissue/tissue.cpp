#include "tissue/tissue.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

#include "tissue/cell_stream.hpp"

namespace fibrodem {

std::size_t Tissue::count(CellType t) const {
  if (cells_partial_) return t == CellType::myocyte ? partial_myocytes_ : partial_cell_count_ - partial_myocytes_;
  return static_cast<std::size_t>(std::count(type.begin(), type.end(), t));
}

std::array<double, 4> empty_bounds_um() {
  constexpr double inf = std::numeric_limits<double>::infinity();
  return {inf, -inf, inf, -inf};
}

void extend_bounds_um(std::array<double, 4>& b, const Particle& p) {
  b[0] = std::min(b[0], p.x_um - p.r_um);
  b[1] = std::max(b[1], p.x_um + p.r_um);
  b[2] = std::min(b[2], p.y_um - p.r_um);
  b[3] = std::max(b[3], p.y_um + p.r_um);
}

std::array<double, 4> Tissue::bounds_um() const {
  if (particles_released_) return released_bounds_um_;
  std::array<double, 4> b = empty_bounds_um();
  if (particles.empty())
    for (std::size_t c = 0; c < type.size(); ++c) extend_bounds_um(b, {x_um[c], y_um[c], 0.0});
  for (const auto& p : particles) extend_bounds_um(b, p);
  return b;
}

void Tissue::release_centres() {
  std::vector<double>().swap(x_um);
  std::vector<double>().swap(y_um);
  // (Held in part, the cells' list goes too, 25 bytes a held cell: a
  // rank's populations and trackers hold what they need of their types.)
  std::vector<CellCentre>().swap(held_cells_);
  std::vector<CellType>().swap(held_types_);
  every_cell_.reset();
}

void Tissue::hold_cells_of(std::vector<CellCentre> held, std::shared_ptr<const CellStream> every_cell) {
  if (!every_cell) throw std::logic_error("Tissue::hold_cells_of: no stream of every cell");
  if (cells_partial_) throw std::logic_error("Tissue::hold_cells_of: the tissue holds part of its cells already");
  held_types_.reserve(held.size());
  for (std::size_t k = 0; k < held.size(); ++k) {
    if (k > 0 && held[k].cell <= held[k - 1].cell)
      throw std::logic_error("Tissue::hold_cells_of: the held cells are not by increasing cell number");
    held_types_.push_back(type.at(static_cast<std::size_t>(held[k].cell)));
  }
  partial_cell_count_ = type.size();
  partial_myocytes_ = count(CellType::myocyte);
  cells_partial_ = true;
  for (auto* v : {&x_um, &y_um}) std::vector<double>().swap(*v);
  std::vector<CellType>().swap(type);
  held_cells_ = std::move(held);
  held_cells_.shrink_to_fit();
  every_cell_ = std::move(every_cell);
}

std::size_t Tissue::find_held(int cell) const {
  const auto held = std::lower_bound(held_cells_.begin(), held_cells_.end(), cell,
                                     [](const CellCentre& c, int wanted) { return c.cell < wanted; });
  return held != held_cells_.end() && held->cell == cell ? static_cast<std::size_t>(held - held_cells_.begin())
                                                         : held_cells_.size();
}

std::size_t Tissue::held_index(int cell) const {
  const std::size_t k = find_held(cell);
  if (k == held_cells_.size())
    throw std::logic_error("Tissue: cell " + std::to_string(cell) + " is not held on this rank");
  return k;
}

CellType Tissue::type_of(int cell) const {
  return cells_partial_ ? held_types_[held_index(cell)] : type.at(static_cast<std::size_t>(cell));
}

CellCentre Tissue::centre_of(int cell) const {
  if (!cells_partial_) {
    const auto c = static_cast<std::size_t>(cell);
    return {cell, x_um.at(c), y_um.at(c)};
  }
  if (!every_cell_) throw std::logic_error("Tissue::centre_of: the cells' centres were freed");
  return held_cells_[held_index(cell)];
}

std::vector<CellType> Tissue::types_of(const std::vector<int>& cells) const {
  std::vector<CellType> types(cells.size());
  if (!cells_partial_) {
    for (std::size_t k = 0; k < cells.size(); ++k) types[k] = type.at(static_cast<std::size_t>(cells[k]));
    return types;
  }
  // Those not held, by cell number, then one pass over every cell for them.
  std::vector<std::pair<int, std::size_t>> wanted;
  for (std::size_t k = 0; k < cells.size(); ++k) {
    const std::size_t held = find_held(cells[k]);
    if (held < held_cells_.size())
      types[k] = held_types_[held];
    else
      wanted.emplace_back(cells[k], k);
  }
  if (wanted.empty()) return types;
  std::sort(wanted.begin(), wanted.end());
  std::size_t next = 0, found = 0;
  for_each_type([&](int cell, CellType t) {
    for (; next < wanted.size() && wanted[next].first == cell; ++next, ++found) types[wanted[next].second] = t;
  });
  if (found != wanted.size())
    throw std::logic_error("Tissue::types_of: cell " + std::to_string(wanted[found].first) + " is not in the tissue");
  return types;
}

void Tissue::for_each_cell(const std::function<void(int, CellType, double, double)>& visit) const {
  if (every_cell_) return every_cell_->for_each_cell(visit);
  if (!centres_whole()) throw std::logic_error("Tissue::for_each_cell: the cells' centres were freed");
  for (std::size_t c = 0; c < type.size(); ++c) visit(static_cast<int>(c), type[c], x_um[c], y_um[c]);
}

void Tissue::for_each_centre(const std::function<void(int, double, double)>& visit) const {
  for_each_cell([&visit](int cell, CellType, double x_um, double y_um) { visit(cell, x_um, y_um); });
}

void Tissue::for_each_type(const std::function<void(int, CellType)>& visit) const {
  if (cells_partial_) return for_each_cell([&visit](int cell, CellType t, double, double) { visit(cell, t); });
  for (std::size_t c = 0; c < type.size(); ++c) visit(static_cast<int>(c), type[c]);
}

int Tissue::add_cell(CellType t, double x, double y) {
  type.push_back(t);
  x_um.push_back(x);
  y_um.push_back(y);
  return static_cast<int>(type.size()) - 1;
}

int Tissue::add_particle(int cell, double x, double y, double r) {
  particles.push_back({x, y, r, cell});
  return static_cast<int>(particles.size()) - 1;
}

int Tissue::add_collagen_particle(double x, double y, double r) {
  collagen.push_back({x, y, r, -1});
  return static_cast<int>(collagen.size()) - 1;
}

void Tissue::add_bond(int p, int q) {
  bonds.push_back({p, q});
  const int a = particles[p].cell, b = particles[q].cell;
  if (a != b) cell_edges.emplace_back(std::min(a, b), std::max(a, b));
}

void Tissue::finalise() {
  std::sort(cell_edges.begin(), cell_edges.end());
  cell_edges.erase(std::unique(cell_edges.begin(), cell_edges.end()), cell_edges.end());
  // A junction's bonds each added its pair (up to 4 on the brick sheets):
  // the room they took is returned (47 MB on an 846,279-cell sheet).
  cell_edges.shrink_to_fit();
}

void Tissue::release_particles(std::shared_ptr<const TissueImprint> imprint) {
  imprint_ = std::move(imprint);
  released_bounds_um_ = bounds_um();
  released_particles_ = built_particles();
  released_bonds_ = built_bonds();
  particles_released_ = true;
  for (auto* v : {&particles, &collagen}) std::vector<Particle>().swap(*v);
  for (auto* v : {&bonds, &collagen_bonds}) std::vector<Bond>().swap(*v);
}

void Tissue::release_unbuilt_particles(std::size_t particle_count, std::size_t bond_count,
                                       const std::array<double, 4>& bounds_um) {
  release_particles();
  released_particles_ = particle_count;
  released_bonds_ = bond_count;
  released_bounds_um_ = bounds_um;
}

void Tissue::keep_part_of_graph(std::vector<std::pair<int, int>> kept, std::size_t edges) {
  cell_edges = std::move(kept);
  graph_partial_ = true;
  built_cell_edges_ = edges;
}

int add_myocyte(Tissue& tissue, double x, double y, double angle) {
  const int cell = tissue.add_cell(CellType::myocyte, x, y);
  const double ax = angle == 0.0 ? 0.0 : -std::sin(angle);
  const double ay = angle == 0.0 ? 1.0 : std::cos(angle);
  // The particles of one myocyte form a rigid clump: no bonds inside it.
  for (int k = 0; k < kMyocyteParticles; ++k) {
    const double a = -kMyocyteEndOffset_um + k * kParticleSpacing_um;
    tissue.add_particle(cell, x + a * ax, y + a * ay, kParticleRadius_um);
  }
  return cell;
}

int add_vertical_myocyte(Tissue& tissue, double x, double y0) {
  return add_myocyte(tissue, x, y0 + kMyocyteLength_um / 2, 0.0);
}

int add_round_fibroblast(Tissue& tissue, double x, double y) {
  const int cell = tissue.add_cell(CellType::fibroblast, x, y);
  tissue.add_particle(cell, x, y, kParticleRadius_um);
  return cell;
}

int CellComponents::largest() const {
  if (size.empty()) return -1;
  return static_cast<int>(std::max_element(size.begin(), size.end()) - size.begin());
}

bool end_to_end(const Tissue& tissue, int i, int j) {
  return std::abs(tissue.centre_of(i).x_um - tissue.centre_of(j).x_um) < kParticleRadius_um;
}

CellComponents cell_graph_components(const Tissue& tissue) {
  const std::size_t n = tissue.cell_count();
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&parent](int a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  for (const auto& [a, b] : tissue.cell_edges) {
    const int ra = find(a), rb = find(b);
    if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);  // root = lowest cell
  }
  CellComponents c;
  c.component.assign(n, -1);
  std::vector<int> index_of_root(n, -1);
  for (std::size_t i = 0; i < n; ++i) {
    const int r = find(static_cast<int>(i));
    if (index_of_root[r] < 0) {
      index_of_root[r] = static_cast<int>(c.size.size());
      c.size.push_back(0);
    }
    c.component[i] = index_of_root[r];
    ++c.size[index_of_root[r]];
  }
  return c;
}

}  // namespace fibrodem
