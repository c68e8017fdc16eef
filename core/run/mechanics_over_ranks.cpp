#include "run/mechanics_over_ranks.hpp"

#include <stdexcept>

namespace fibrodem {

MechanicsOverRanks::MechanicsOverRanks(RankGroup& ranks, const RankLayout& layout) : ranks_(ranks), layout_(layout) {}

void MechanicsOverRanks::advance(double t_ms, const CellSystem& system, MechanicsCoupling* mechanics) {
  gather_by_cell(ranks_, layout_, system.stretch_by_cell(), own_ratio_, gathered_, ratio_by_cell_);
  if (ranks_.rank() != 0) return;
  if (!mechanics) throw std::logic_error("split over ranks: rank 0 holds no mechanics to step");
  mechanics->advance(t_ms, ratio_by_cell_);
}

}  // namespace fibrodem
