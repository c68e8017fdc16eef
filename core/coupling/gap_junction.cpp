#include "coupling/gap_junction.hpp"

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>

#include "model/work_split.hpp"
#include "util/manifest_error.hpp"

namespace fibrodem {

namespace {

// The error for a region or map that holds no junction: its extent beside the
// tissue's, so that one off the tissue is seen at once.
ManifestError holds_no_junction(const Tissue& tissue, const std::string& path, const std::string& why, double x_min_um,
                                double x_max_um, double y_min_um, double y_max_um) {
  const auto b = tissue.bounds_um();
  return ManifestError(path, fmt::format("holds no junction ({}its x_mm [{:g}, {:g}], y_mm [{:g}, {:g}]; the tissue "
                                         "spans x [{:g}, {:g}] mm, y [{:g}, {:g}] mm)",
                                         why, x_min_um / 1000, x_max_um / 1000, y_min_um / 1000, y_max_um / 1000,
                                         b[0] / 1000, b[1] / 1000, b[2] / 1000, b[3] / 1000));
}

// The junction's conductance [nS] (0: none), its place counted.
double junction_conductance_nS(const Tissue& tissue, const JunctionConductances& base_nS,
                               const std::vector<CouplingRegion>& regions, const CouplingField* field, int i, int j,
                               CouplingPlaces& places) {
  const JunctionPlace place = places.count(tissue, i, j);
  const JunctionConductances* g_nS =
      place.region >= 0 ? &regions[static_cast<std::size_t>(place.region)].g_nS : &base_nS;
  const bool both_myocytes = tissue.type_of(i) == CellType::myocyte && tissue.type_of(j) == CellType::myocyte;
  const bool anisotropic = g_nS->D_m_side_nS != g_nS->D_m_nS;  // (else the junction's direction is not asked)
  double g = !both_myocytes                              ? g_nS->D_f_nS
             : !anisotropic || end_to_end(tissue, i, j) ? g_nS->D_m_nS
                                                         : g_nS->D_m_side_nS;
  if (place.in_field) g *= field->scale_at(place.x_um, place.y_um);
  return g;
}

}  // namespace

CouplingPlaces::CouplingPlaces(const std::vector<CouplingRegion>& regions, const CouplingField* field)
    : regions_(regions), field_(field), junctions_held_(regions.size(), 0) {}

JunctionPlace CouplingPlaces::count(const Tissue& tissue, int i, int j) {
  // The midpoint, asked only by regions and maps (a tissue made for a test
  // of the coupling alone may have no cell positions).
  if (regions_.empty() && !field_) return {};
  return count(tissue.centre_of(i), tissue.centre_of(j));
}

JunctionPlace CouplingPlaces::count(const CellCentre& i, const CellCentre& j) {
  JunctionPlace place;
  if (regions_.empty() && !field_) return place;
  place.x_um = 0.5 * (i.x_um + j.x_um);
  place.y_um = 0.5 * (i.y_um + j.y_um);
  place.region = regions_.empty() ? -1 : region_holding(regions_, place.x_um, place.y_um);
  place.in_field = field_ && field_->contains(place.x_um, place.y_um);
  if (place.region >= 0) ++junctions_held_[static_cast<std::size_t>(place.region)];
  junctions_in_field_ += place.in_field;
  return place;
}

void CouplingPlaces::check(const Tissue& tissue) const {
  // A region that holds no junction is named: it lies off the tissue,
  // between its cells, or under later regions.
  for (std::size_t k = 0; k < regions_.size(); ++k) {
    if (junctions_held_[k] > 0) continue;
    const CouplingRegion& r = regions_[k];
    throw holds_no_junction(tissue, r.path, "none has its midpoint in it and in no later region; ", r.x_min_um,
                            r.x_max_um, r.y_min_um, r.y_max_um);
  }
  if (field_ && junctions_in_field_ == 0)
    throw holds_no_junction(tissue, field_->path, "", field_->x_min_um, field_->x_max_um, field_->y_min_um,
                            field_->y_max_um);
}

// L is written row by row in place (compressed rows, columns ascending:
// those below the diagonal, the diagonal, those above), with a double a
// junction of the rows beside it while it is made. Gathered as triplets and
// summed by Eigen's setFromTriplets (four 16-byte triplets a junction, and a
// transposed copy) it took ~100 MB on a rank of the 846,279-cell sheet split
// 4 ways, and a sixth of one process's set-up. The cell edges are sorted
// (i < j, by i then j), so row r's entries below the diagonal come in
// increasing column as the junctions (c, r) go by, and those above as the
// junctions (r, c) do; its diagonal adds the junctions' conductances in the
// junctions' order, as summing the triplets did: the same matrix, bit for
// bit (tests/coupling/test_coupling_cg.cpp). Split over ranks, rows and
// columns are held numbers but each row's entries stay in the tissue's
// column order (a ghost's column may come before the diagonal): the same
// terms in the same order as the whole tissue's row.
CouplingCg::Laplacian junction_laplacian_nS(const Tissue& tissue, const JunctionConductances& base_nS,
                                            const std::vector<CouplingRegion>& regions, const CouplingField* field,
                                            const CellNumbering* held) {
  const std::size_t n = held ? held->held() : tissue.cell_count();
  const long own_rows = held ? static_cast<long>(held->own()) : static_cast<long>(n);
  CouplingPlaces places(regions, field);
  // A cell's row (its held number split over ranks), and whether it is an
  // own row.
  const auto row_of = [held](int cell) { return held ? held->held_cell(cell) : static_cast<long>(cell); };
  const auto own = [own_rows](long row) { return row >= 0 && row < own_rows; };
  // Pass 1: the conductance of each junction of an own row (0: none, left
  // out) and each row's entries below and above the diagonal.
  std::vector<double> g_of_junction;
  std::vector<int> below(n, 0), above(n, 0);
  for (const auto& [cell_i, cell_j] : tissue.cell_edges) {
    const double g = junction_conductance_nS(tissue, base_nS, regions, field, cell_i, cell_j, places);
    const long i = row_of(cell_i), j = row_of(cell_j);
    if (!(own(i) || own(j))) continue;
    if (i < 0 || j < 0)
      throw std::logic_error(fmt::format("coupling over ranks: a rank's cell {} reaches cell {}, which it does not "
                                         "hold as a ghost", i < 0 ? cell_j : cell_i, i < 0 ? cell_i : cell_j));
    g_of_junction.push_back(g);
    if (g == 0.0) continue;
    if (own(i)) ++above[static_cast<std::size_t>(i)];
    if (own(j)) ++below[static_cast<std::size_t>(j)];
  }
  // (A tissue holding part of its graph was checked where its whole graph went by.)
  if (!tissue.graph_partial()) places.check(tissue);
  CouplingCg::Laplacian laplacian(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
  int* outer = laplacian.outerIndexPtr();
  outer[0] = 0;
  for (std::size_t r = 0; r < n; ++r) {
    const int entries = below[r] + above[r];
    outer[r + 1] = outer[r] + (entries > 0 ? entries + 1 : 0);  // (a row with entries has its diagonal)
  }
  laplacian.resizeNonZeros(outer[n]);
  int* column = laplacian.innerIndexPtr();
  double* value = laplacian.valuePtr();
  // Pass 2: below[r] and above[r] become the places of row r's next entries
  // below and above its diagonal, at diagonal_at[r].
  std::vector<int> diagonal_at(n, -1);
  for (std::size_t r = 0; r < n; ++r) {
    if (outer[r + 1] == outer[r]) continue;
    diagonal_at[r] = outer[r] + below[r];
    column[diagonal_at[r]] = static_cast<int>(r);
    value[diagonal_at[r]] = 0.0;
    below[r] = outer[r];
    above[r] = diagonal_at[r] + 1;
  }
  std::size_t junction = 0;
  for (const auto& [cell_i, cell_j] : tissue.cell_edges) {
    const long i = row_of(cell_i), j = row_of(cell_j);
    if (!(own(i) || own(j))) continue;
    const double g = g_of_junction[junction++];
    if (g == 0.0) continue;
    if (own(i)) {
      const auto r = static_cast<std::size_t>(i);
      column[above[r]] = static_cast<int>(j);
      value[above[r]++] = -g;
      value[diagonal_at[r]] += g;
    }
    if (own(j)) {
      const auto r = static_cast<std::size_t>(j);
      column[below[r]] = static_cast<int>(i);
      value[below[r]++] = -g;
      value[diagonal_at[r]] += g;
    }
  }
  return laplacian;
}

// (L exists whole only while the CG slices it.)
GapJunctionCoupler::GapJunctionCoupler(const Tissue& tissue, const JunctionConductances& g_nS,
                                       std::vector<double> capacitance_pF, const std::vector<CouplingRegion>& regions,
                                       const CouplingField* field)
    : cg_(junction_laplacian_nS(tissue, g_nS, regions, field), capacitance_pF), max_rate_per_ms_(0.0) {
  const std::vector<double> total = total_conductance_nS();
  for (std::size_t i = 0; i < total.size(); ++i)
    max_rate_per_ms_ = std::max(max_rate_per_ms_, 2.0 * total[i] / capacitance_pF[i]);
}

void GapJunctionCoupler::add_current(const double* V, double* i_ext) const {
  for_each_cell(cg_.rows(), [&](long row) { i_ext[row] += cg_.row_current(row, V); });
}

void GapJunctionCoupler::current_into(const double* V, const int* cells, std::size_t count, double* current) const {
  for (std::size_t k = 0; k < count; ++k) current[k] = cg_.row_current(cells[k], V);
}

void GapJunctionCoupler::implicit_step(double* V, double dt_ms, double tolerance_mV) {
  cg_.solve(V, dt_ms, tolerance_mV);
}

std::string GapJunctionCoupler::describe_solves() const { return cg_.describe_statistics(); }

std::vector<double> GapJunctionCoupler::total_conductance_nS() const { return cg_.diagonal_nS(); }

double GapJunctionCoupler::max_rate_per_ms() const { return max_rate_per_ms_; }

}  // namespace fibrodem
