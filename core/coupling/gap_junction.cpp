#include "coupling/gap_junction.hpp"

#include <algorithm>

#include "model/work_split.hpp"

namespace fibrodem {

namespace {

Eigen::SparseMatrix<double, Eigen::RowMajor> laplacian_of(const Tissue& tissue, const JunctionConductances& g_nS) {
  const auto n = static_cast<Eigen::Index>(tissue.cell_count());
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(4 * tissue.cell_edges.size());
  const bool anisotropic = g_nS.D_m_side_nS != g_nS.D_m_nS;  // (else the junction's direction is not asked)
  for (const auto& [i, j] : tissue.cell_edges) {
    const bool both_myocytes =
        tissue.type[i] == CellType::myocyte && tissue.type[j] == CellType::myocyte;
    const double g = !both_myocytes                              ? g_nS.D_f_nS
                     : !anisotropic || end_to_end(tissue, i, j) ? g_nS.D_m_nS
                                                                 : g_nS.D_m_side_nS;
    if (g == 0.0) continue;
    entries.emplace_back(i, i, g);
    entries.emplace_back(j, j, g);
    entries.emplace_back(i, j, -g);
    entries.emplace_back(j, i, -g);
  }
  Eigen::SparseMatrix<double, Eigen::RowMajor> laplacian(n, n);
  laplacian.setFromTriplets(entries.begin(), entries.end());
  laplacian.makeCompressed();
  return laplacian;
}

}  // namespace

// (L exists whole only while the CG slices it.)
GapJunctionCoupler::GapJunctionCoupler(const Tissue& tissue, const JunctionConductances& g_nS,
                                       std::vector<double> capacitance_pF)
    : cg_(laplacian_of(tissue, g_nS), capacitance_pF), max_rate_per_ms_(0.0) {
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
