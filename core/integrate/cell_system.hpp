// The system of ODEs the integrators advance: every population's cell states,
// driven by the stimulus and, when the scene calls for coupling, by the
// gap-junction currents between cells.
#pragma once

#include <memory>
#include <utility>
#include <vector>

#include "coupling/coupler.hpp"
#include "model/population.hpp"
#include "stimulus/stimulus.hpp"

namespace fibrodem {

struct CellSystem {
  std::vector<Population> populations;
  std::unique_ptr<Coupler> coupler;  // null: coupling not built
  std::vector<std::pair<int, int>> coupled_pairs;  // cell-graph edges the coupler joins
  bool implicit_coupling = false;    // coupling advanced by backward Euler (split)
  Stimulus stimulus;
  std::vector<std::pair<int, int>> where;  // global cell -> (population, local index)
  std::vector<double> V_mV, i_ext_pA;      // per global cell

  std::size_t cell_count() const { return where.size(); }
  std::size_t state_count() const;

  void gather_voltage();   // populations -> V_mV
  void scatter_voltage();  // V_mV -> populations
  // Sets every cell's i_ext input: the stimulus at t_stim plus, when coupling
  // is explicit, the gap-junction current at the present potentials.
  void compute_inputs(double t_stim_ms);
  // Evaluates a, b (and outputs) of every population at time t.
  void evaluate(double t_ms);
};

}  // namespace fibrodem
