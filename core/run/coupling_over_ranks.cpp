#include "run/coupling_over_ranks.hpp"

#include <algorithm>

namespace fibrodem {

namespace {

// The halo plan in the CG's numbering: a rank's own cells by their place in
// `owned`, its ghosts by theirs in `ghosts` from first_ghost.
RankCells numbered_for_cg(const RankCells& share, long first_ghost) {
  const auto place = [](const std::vector<int>& cells, int cell) {
    return static_cast<int>(std::lower_bound(cells.begin(), cells.end(), cell) - cells.begin());
  };
  RankCells numbered;
  numbered.rank = share.rank;
  for (const HaloNeighbour& neighbour : share.neighbours) {
    HaloNeighbour n{neighbour.rank, {}, {}};
    for (int cell : neighbour.send) n.send.push_back(place(share.owned, cell));
    for (int cell : neighbour.receive) n.receive.push_back(static_cast<int>(first_ghost) + place(share.ghosts, cell));
    numbered.neighbours.push_back(std::move(n));
  }
  return numbered;
}

}  // namespace

// The rows the CG holds come from a Laplacian of this rank's rows alone: a
// rank never holds the whole tissue's coupling.
CouplingOverRanks::CouplingOverRanks(const Tissue& tissue, const JunctionConductances& g_nS,
                                     const std::vector<double>& capacitance_pF,
                                     const std::vector<CouplingRegion>& regions, const CouplingField* field,
                                     RankGroup& ranks, const RankCells& share)
    : cells_(tissue.cell_count()),
      owned_(share.owned),
      reductions_(ranks),
      cg_(
          [&] {
            std::vector<char> own(tissue.cell_count(), 0);
            for (int cell : share.owned) own[static_cast<std::size_t>(cell)] = 1;
            return junction_laplacian_nS(tissue, g_nS, regions, field, &own);
          }(),
          capacitance_pF, share.owned, share.ghosts, *this),
      halo_(ranks, numbered_for_cg(share, cg_.first_ghost())),
      own_V_mV_(share.owned.size(), 0.0) {
  cell_of_column_.assign(static_cast<std::size_t>(cg_.first_ghost()), -1);
  std::copy(owned_.begin(), owned_.end(), cell_of_column_.begin());
  cell_of_column_.insert(cell_of_column_.end(), share.ghosts.begin(), share.ghosts.end());
  row_of_cell_.assign(cells_, -1);
  for (std::size_t k = 0; k < owned_.size(); ++k)
    row_of_cell_[static_cast<std::size_t>(owned_[k])] = static_cast<int>(k);
  // GapJunctionCoupler's: the largest 2 L_ii / C_i, over every rank's cells.
  const std::vector<double> own_total_nS = cg_.diagonal_nS();
  for (std::size_t k = 0; k < owned_.size(); ++k)
    max_rate_per_ms_ =
        std::max(max_rate_per_ms_, 2.0 * own_total_nS[k] / capacitance_pF[static_cast<std::size_t>(owned_[k])]);
  double unused = 0;
  reductions_.reduce(unused, max_rate_per_ms_);
}

void CouplingOverRanks::add_current(const double* V_mV, double* i_ext_pA) const {
  for (std::size_t k = 0; k < owned_.size(); ++k)
    i_ext_pA[owned_[k]] += cg_.row_current(static_cast<long>(k), V_mV, cell_of_column_.data());
}

void CouplingOverRanks::current_into(const double* V_mV, const int* cells, std::size_t count,
                                     double* current_pA) const {
  for (std::size_t k = 0; k < count; ++k)
    current_pA[k] = cg_.row_current(row_of_cell_[static_cast<std::size_t>(cells[k])], V_mV, cell_of_column_.data());
}

std::vector<double> CouplingOverRanks::total_conductance_nS() const {
  std::vector<double> total(cells_, 0.0);
  const std::vector<double> own = cg_.diagonal_nS();
  for (std::size_t k = 0; k < owned_.size(); ++k) total[static_cast<std::size_t>(owned_[k])] = own[k];
  return total;
}

void CouplingOverRanks::implicit_step(double* V_mV, double dt_ms, double tolerance_mV) {
  for (std::size_t k = 0; k < owned_.size(); ++k) own_V_mV_[k] = V_mV[owned_[k]];
  cg_.solve(own_V_mV_.data(), dt_ms, tolerance_mV);
  for (std::size_t k = 0; k < owned_.size(); ++k) V_mV[owned_[k]] = own_V_mV_[k];
}

}  // namespace fibrodem
