#include "integrate/cell_system.hpp"

#include <algorithm>

namespace fibrodem {

std::size_t CellSystem::state_count() const {
  std::size_t n = 0;
  for (const auto& p : populations) n += p.n_states() * p.size();
  return n;
}

void CellSystem::gather_voltage() {
  for (auto& pop : populations) {
    const double* v = pop.voltage();
    for (std::size_t c = 0; c < pop.size(); ++c) V_mV[pop.cells[c]] = v[c];
  }
}

void CellSystem::scatter_voltage() {
  for (auto& pop : populations) {
    double* v = pop.voltage();
    for (std::size_t c = 0; c < pop.size(); ++c) v[c] = V_mV[pop.cells[c]];
  }
}

void CellSystem::compute_inputs(double t_stim_ms) {
  std::fill(i_ext_pA.begin(), i_ext_pA.end(), 0.0);
  stimulus.add_current(t_stim_ms, i_ext_pA.data());
  if (coupler && !implicit_coupling) {
    gather_voltage();
    coupler->add_current(V_mV.data(), i_ext_pA.data());
  }
  for (auto& pop : populations) {
    double* in = pop.i_ext();
    for (std::size_t c = 0; c < pop.size(); ++c) in[c] = i_ext_pA[pop.cells[c]];
  }
}

void CellSystem::evaluate(double t_ms) {
  for (auto& pop : populations) pop.evaluate(t_ms);
}

}  // namespace fibrodem
