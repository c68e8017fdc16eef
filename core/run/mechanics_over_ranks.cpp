#include "run/mechanics_over_ranks.hpp"

#include <stdexcept>

namespace fibrodem {

MechanicsOverRanks::MechanicsOverRanks(RankGroup& ranks, const std::vector<int>& owned, const RankLayout& layout)
    : ranks_(ranks), owned_(owned), layout_(layout), own_ratio_(owned.size(), 1.0) {}

void MechanicsOverRanks::advance(double t_ms, const CellSystem& system, MechanicsCoupling* mechanics) {
  const std::vector<double>& stretch = system.stretch_by_cell();
  for (std::size_t i = 0; i < owned_.size(); ++i) own_ratio_[i] = stretch[static_cast<std::size_t>(owned_[i])];
  gather_by_cell(ranks_, layout_, own_ratio_.data(), gathered_, ratio_by_cell_);
  if (ranks_.rank() != 0) return;
  if (!mechanics) throw std::logic_error("split over ranks: rank 0 holds no mechanics to step");
  mechanics->advance(t_ms, ratio_by_cell_);
}

}  // namespace fibrodem
