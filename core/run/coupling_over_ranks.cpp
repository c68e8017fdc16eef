#include "run/coupling_over_ranks.hpp"

#include <algorithm>

#include "tissue/cell_numbering.hpp"

namespace fibrodem {


// The rows the CG holds come from a Laplacian of this rank's rows alone, in
// its held numbers: a rank never holds the whole tissue's coupling, nor an
// array of every tissue cell beside the graph.
CouplingOverRanks::CouplingOverRanks(const Tissue& tissue, const JunctionConductances& g_nS,
                                     const std::vector<double>& capacitance_pF,
                                     const std::vector<CouplingRegion>& regions, const CouplingField* field,
                                     RankGroup& ranks, const RankCells& share, const CellNumbering& held)
    : owned_(held.own()),
      held_(held.held()),
      reductions_(ranks),
      cg_(junction_laplacian_nS(tissue, g_nS, regions, field, &held), capacitance_pF, held, *this),
      halo_(ranks, numbered_from_ghost(share, static_cast<std::size_t>(cg_.first_ghost()))) {
  // The CG's columns in held numbers: own rows first (padded to
  // first_ghost), then the ghosts.
  cell_of_column_.assign(static_cast<std::size_t>(cg_.first_ghost()), -1);
  for (std::size_t k = 0; k < owned_; ++k) cell_of_column_[k] = static_cast<int>(k);
  for (std::size_t c = owned_; c < held_; ++c) cell_of_column_.push_back(static_cast<int>(c));
  // GapJunctionCoupler's: the largest 2 L_ii / C_i, over every rank's cells.
  const std::vector<double> own_total_nS = cg_.diagonal_nS();
  for (std::size_t k = 0; k < owned_; ++k)
    max_rate_per_ms_ = std::max(max_rate_per_ms_, 2.0 * own_total_nS[k] / capacitance_pF[k]);
  double unused = 0;
  reductions_.reduce(unused, max_rate_per_ms_);
}

void CouplingOverRanks::add_current(const double* V_mV, double* i_ext_pA) const {
  for (std::size_t k = 0; k < owned_; ++k)
    i_ext_pA[k] += cg_.row_current(static_cast<long>(k), V_mV, cell_of_column_.data());
}

void CouplingOverRanks::current_into(const double* V_mV, const int* cells, std::size_t count,
                                     double* current_pA) const {
  for (std::size_t k = 0; k < count; ++k) current_pA[k] = cg_.row_current(cells[k], V_mV, cell_of_column_.data());
}

std::vector<double> CouplingOverRanks::total_conductance_nS() const {
  std::vector<double> total = cg_.diagonal_nS();
  total.resize(held_, 0.0);
  return total;
}

// (The own cells' potentials are the first of V_mV: the CG takes them in place.)
void CouplingOverRanks::implicit_step(double* V_mV, double dt_ms, double tolerance_mV) {
  cg_.solve(V_mV, dt_ms, tolerance_mV);
}

}  // namespace fibrodem
