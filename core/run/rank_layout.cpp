#include "run/rank_layout.hpp"

namespace fibrodem {

RankLayout rank_layout_counts(const std::vector<std::size_t>& cells_per_part) {
  RankLayout layout;
  layout.counts.assign(cells_per_part.size(), 0);
  layout.offsets.assign(cells_per_part.size(), 0);
  for (std::size_t r = 0; r < cells_per_part.size(); ++r) {
    layout.counts[r] = static_cast<int>(cells_per_part[r]);
    if (r > 0) layout.offsets[r] = layout.offsets[r - 1] + layout.counts[r - 1];
  }
  return layout;
}

RankLayout rank_layout(const CellPartition& partition) {
  RankLayout layout = rank_layout_counts(partition.sizes());
  layout.cells_in_rank_order.resize(partition.part_of.size());
  std::vector<int> next = layout.offsets;
  for (std::size_t cell = 0; cell < partition.part_of.size(); ++cell)
    layout.cells_in_rank_order[static_cast<std::size_t>(next[static_cast<std::size_t>(partition.part_of[cell])]++)] =
        static_cast<int>(cell);
  return layout;
}

void gather_by_cell(RankGroup& ranks, const RankLayout& layout, const double* own, std::vector<double>& gathered,
                    std::vector<double>& by_cell) {
  const bool on_rank0 = ranks.rank() == 0;
  if (on_rank0) {
    gathered.resize(layout.cell_count());
    by_cell.resize(layout.cell_count());
  }
  ranks.gather_into(own, static_cast<std::size_t>(layout.counts[static_cast<std::size_t>(ranks.rank())]),
                    on_rank0 ? gathered.data() : nullptr, layout.counts.data(), layout.offsets.data());
  if (!on_rank0) return;
  for (std::size_t k = 0; k < gathered.size(); ++k)
    by_cell[static_cast<std::size_t>(layout.cells_in_rank_order[k])] = gathered[k];
}

void gather_by_cell(RankGroup& ranks, const RankLayout& layout, const std::vector<double>& per_cell,
                    std::vector<double>& own, std::vector<double>& gathered, std::vector<double>& by_cell) {
  const std::span<const int> cells = layout.cells_of(ranks.rank());
  own.resize(cells.size());
  for (std::size_t i = 0; i < cells.size(); ++i) own[i] = per_cell[static_cast<std::size_t>(cells[i])];
  gather_by_cell(ranks, layout, own.data(), gathered, by_cell);
}

}  // namespace fibrodem
