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

CouplingOverRanks::CouplingOverRanks(std::unique_ptr<GapJunctionCoupler> whole, RankGroup& ranks,
                                     const RankCells& share)
    : whole_(std::move(whole)),
      owned_(share.owned),
      reductions_(ranks),
      cg_(whole_->solver(), share.owned, share.ghosts, *this),
      halo_(ranks, numbered_for_cg(share, cg_.first_ghost())),
      own_V_mV_(share.owned.size(), 0.0) {}

void CouplingOverRanks::implicit_step(double* V_mV, double dt_ms, double tolerance_mV) {
  for (std::size_t k = 0; k < owned_.size(); ++k) own_V_mV_[k] = V_mV[owned_[k]];
  cg_.solve(own_V_mV_.data(), dt_ms, tolerance_mV);
  for (std::size_t k = 0; k < owned_.size(); ++k) V_mV[owned_[k]] = own_V_mV_[k];
}

}  // namespace fibrodem
