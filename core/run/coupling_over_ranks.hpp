// The gap-junction coupling of a run split over ranks (docs/guide/parallel.md):
// this rank's rows of the tissue's L only (coupling/gap_junction.hpp), in a
// CG of its own (coupling/coupling_cg.hpp, split over ranks). It reads and
// writes per-cell arrays in the rank's held numbers (tissue/cell_numbering.hpp:
// its own cells, then its ghosts). Its currents are its own cells' (each row
// summed as one process sums it, reading its ghosts' potentials as the run's
// halo exchange refreshed them). Its
// implicit step (the adaptive method's Crank-Nicolson solve, and
// coupling.scheme "implicit") exchanges the ghosts' entries before each
// product and reduces its sums over the ranks: every rank constructs it and
// calls implicit_step at the same point of the run.
#pragma once

#include <string>
#include <vector>

#include "coupling/coupler.hpp"
#include "coupling/coupling_cg.hpp"
#include "coupling/gap_junction.hpp"
#include "run/halo_exchange.hpp"
#include "util/rank_group.hpp"
#include "run/rank_reductions.hpp"
#include "tissue/cell_numbering.hpp"
#include "tissue/rank_cells.hpp"

namespace fibrodem {

class CouplingOverRanks final : public Coupler, private CouplingCg::Ranks {
 public:
  // As GapJunctionCoupler's, for `share`'s cells, held as `held` numbers
  // them (capacitances by held cell). (At set-up it reads the whole
  // tissue's graph.)
  CouplingOverRanks(const Tissue& tissue, const JunctionConductances& g_nS, const std::vector<double>& capacitance_pF,
                    const std::vector<CouplingRegion>& regions, const CouplingField* field, RankGroup& ranks,
                    const RankCells& share, const CellNumbering& held);
  CouplingOverRanks(const CouplingOverRanks&) = delete;  // the CG and halo point into it
  CouplingOverRanks& operator=(const CouplingOverRanks&) = delete;

  // Own cells' rows only (another rank's cell's current is its owner's).
  void add_current(const double* V_mV, double* i_ext_pA) const override;
  // `cells`: this rank's.
  void current_into(const double* V_mV, const int* cells, std::size_t count, double* current_pA) const override;
  // This rank's cells' potentials are advanced (its ghosts' are left as
  // they are).
  void implicit_step(double* V_mV, double dt_ms, double tolerance_mV) override;
  void restart_implicit() override { cg_.restart(); }
  std::string describe_solves() const override { return cg_.describe_statistics(); }
  // The whole tissue's (reduced over the ranks at construction).
  double max_rate_per_ms() const override { return max_rate_per_ms_; }
  // Per held cell: its own cells' L_ii, 0 for the ghosts'.
  std::vector<double> total_conductance_nS() const override;

  long long exchanges() const { return halo_.exchanges(); }

 private:
  void refresh_ghosts(double* vector) override { halo_.refresh(vector); }
  void reduce(double& sum, double& largest) override { reductions_.reduce(sum, largest); }

  std::size_t owned_, held_;  // this rank's own cells, and with its ghosts
  RankReductions reductions_;
  CouplingCg cg_;
  HaloExchange halo_;  // of the CG's vectors (own cells, then ghosts from cg_.first_ghost())
  std::vector<int> cell_of_column_;  // the CG's columns' held cells (padding rows: -1, never read)
  double max_rate_per_ms_ = 0;
};

}  // namespace fibrodem
