// The gap-junction coupling of a run split over ranks (docs/guide/parallel.md).
// Its currents are the whole tissue's coupler's (each rank asks for its own
// cells', their ghosts' potentials refreshed by the run's halo exchange).
// Its implicit step (the adaptive method's Crank-Nicolson solve, and
// coupling.scheme "implicit") solves this rank's rows by a CG of its own
// (coupling/coupling_cg.hpp, split over ranks), which exchanges the ghosts'
// entries before each product and reduces its sums over the ranks: every
// rank calls implicit_step at the same point of the run.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "coupling/coupler.hpp"
#include "coupling/coupling_cg.hpp"
#include "coupling/gap_junction.hpp"
#include "run/halo_exchange.hpp"
#include "run/rank_group.hpp"
#include "run/rank_reductions.hpp"
#include "tissue/rank_cells.hpp"

namespace fibrodem {

class CouplingOverRanks final : public Coupler, private CouplingCg::Ranks {
 public:
  CouplingOverRanks(std::unique_ptr<GapJunctionCoupler> whole, RankGroup& ranks, const RankCells& share);
  CouplingOverRanks(const CouplingOverRanks&) = delete;  // the CG and halo point into it
  CouplingOverRanks& operator=(const CouplingOverRanks&) = delete;

  void add_current(const double* V_mV, double* i_ext_pA) const override { whole_->add_current(V_mV, i_ext_pA); }
  void current_into(const double* V_mV, const int* cells, std::size_t count, double* current_pA) const override {
    whole_->current_into(V_mV, cells, count, current_pA);
  }
  // V_mV per global cell: this rank's cells' potentials are advanced (the
  // others' are left as they are).
  void implicit_step(double* V_mV, double dt_ms, double tolerance_mV) override;
  void restart_implicit() override { cg_.restart(); }
  std::string describe_solves() const override { return cg_.describe_statistics(); }
  double max_rate_per_ms() const override { return whole_->max_rate_per_ms(); }
  std::vector<double> total_conductance_nS() const override { return whole_->total_conductance_nS(); }

  long long exchanges() const { return halo_.exchanges(); }

 private:
  void refresh_ghosts(double* vector) override { halo_.refresh(vector); }
  void reduce(double& sum, double& largest) override { reductions_.reduce(sum, largest); }

  std::unique_ptr<GapJunctionCoupler> whole_;
  std::vector<int> owned_;
  RankReductions reductions_;
  CouplingCg cg_;
  HaloExchange halo_;  // of the CG's vectors (own cells, then ghosts from cg_.first_ghost())
  std::vector<double> own_V_mV_;
};

}  // namespace fibrodem
