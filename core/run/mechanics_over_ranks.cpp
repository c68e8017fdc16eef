#include "run/mechanics_over_ranks.hpp"

#include <stdexcept>

namespace fibrodem {

MechanicsOverRanks::MechanicsOverRanks(RankGroup& ranks, const std::vector<int>& owned,
                                       const std::vector<int>& cells_in_rank_order, const std::vector<int>& counts,
                                       const std::vector<int>& offsets)
    : ranks_(ranks),
      owned_(owned),
      cells_in_rank_order_(cells_in_rank_order),
      counts_(counts),
      offsets_(offsets),
      own_ratio_(owned.size(), 1.0) {
  if (ranks_.rank() != 0) return;
  gathered_.assign(cells_in_rank_order_.size(), 1.0);
  ratio_by_cell_.assign(cells_in_rank_order_.size(), 1.0);
}

void MechanicsOverRanks::advance(double t_ms, const CellSystem& system, MechanicsCoupling* mechanics) {
  const std::vector<double>& stretch = system.stretch_by_cell();
  for (std::size_t i = 0; i < owned_.size(); ++i) own_ratio_[i] = stretch[static_cast<std::size_t>(owned_[i])];
  ranks_.gather_into(own_ratio_.data(), own_ratio_.size(), gathered_.data(), counts_.data(), offsets_.data());
  if (ranks_.rank() != 0) return;
  if (!mechanics) throw std::logic_error("split over ranks: rank 0 holds no mechanics to step");
  for (std::size_t k = 0; k < gathered_.size(); ++k)
    ratio_by_cell_[static_cast<std::size_t>(cells_in_rank_order_[k])] = gathered_[k];
  mechanics->advance(t_ms, ratio_by_cell_);
}

}  // namespace fibrodem
