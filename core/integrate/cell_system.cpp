#include "integrate/cell_system.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>

namespace fibrodem {

void CellSystem::gather_voltage() {
  for (auto& pop : populations) {
    const double* v = pop.voltage();
    for_each_cell(static_cast<long>(pop.size()), [&](long c) { V_mV[pop.cells[c]] = v[c]; });
  }
}

void CellSystem::scatter_voltage() {
  for (auto& pop : populations) {
    double* v = pop.voltage();
    for (std::size_t c = 0; c < pop.size(); ++c) v[c] = V_mV[pop.cells[c]];
  }
}

void CellSystem::record_rest_lengths(bool stretch_read) {
  // (Only for a reader, the mechanics: without it, 8 bytes a cell unread.)
  stretch_by_cell_.assign(stretch_read ? numbering.tissue_cells() : 0, 1.0);
  for (auto& m : myofilaments) {
    m.pop.evaluate(0.0);
    const std::size_t n = m.pop.size();
    m.rest_sarcomere_length.assign(m.pop.outputs.begin() + m.sarcomere_output * n,
                                   m.pop.outputs.begin() + (m.sarcomere_output + 1) * n);
  }
}

// i_ext of the cells [begin, end) of ionic population p: the stimulus (step 2),
// the gap-junction current (computed now if refreshed this step, else held),
// and the stretch-activated current, in that order.
void CellSystem::block_inputs(std::size_t p, std::size_t begin, std::size_t end) {
  Population& pop = populations[p];
  const int* cells = pop.cells.data();
  const bool gap = coupler && !implicit_coupling;
  double* held = gap_current_pA.empty() ? nullptr : gap_current_pA[p].data();
  if (refresh_gap_current_) coupler->current_into(V_mV.data(), cells + begin, end - begin, held + begin);
  const Myofilament* sarcomere = nullptr;
  const bool stretched = sac.on && sac.host_on[p];
  if (stretched && !sac.tissue_stretch)
    for (const auto& m : myofilaments)
      if (m.host == static_cast<int>(p)) sarcomere = &m;
  const double* tissue_stretch = stretched && sac.tissue_stretch ? sac.tissue_stretch->data() : nullptr;
  double* in = pop.i_ext();
  for (std::size_t c = begin; c < end; ++c) {
    double current = i_ext_pA[cells[c]];
    if (gap) current += held[c];
    if (sarcomere) current -= stretch_activated_pA(*sarcomere, pop, c);
    if (tissue_stretch)
      current -= sac.current_pA(tissue_stretch[numbering.tissue_cell(static_cast<std::size_t>(cells[c]))],
                                pop.y[pop.voltage_state * pop.size() + c]);
    in[c] = current;
  }
}

// I_SAC [pA, + outward] at lambda = SL / SL_rest of the cell's myofilament model.
double CellSystem::stretch_activated_pA(const Myofilament& m, const Population& host, std::size_t c) const {
  const std::size_t n = host.size();
  const double lambda = m.pop.outputs[m.sarcomere_output * n + c] / m.rest_sarcomere_length[c];
  return sac.current_pA(lambda, host.y[host.voltage_state * n + c]);
}

namespace {
using Clock = std::chrono::steady_clock;
}  // namespace

// Every block of every ionic population, with its cells' myofilaments, in one
// parallel loop (one fork and join per step).
double CellSystem::evaluate_ionic(double t_ms, const AfterPopulationBlock& after,
                                  const BlockSchedule::AfterAll& after_all) {
  hosts_myofilament_.assign(populations.size(), false);
  for (const auto& m : myofilaments) hosts_myofilament_[static_cast<std::size_t>(m.host)] = true;
  blocks_.clear();  // (keeps its capacity)
  for (std::size_t p = 0; p < populations.size(); ++p)
    for (std::size_t begin = 0; begin < populations[p].size(); begin += kCellsPerBlock)
      blocks_.push_back({p, begin, std::min(populations[p].size(), begin + kCellsPerBlock), populations[p].cells.data()});
  std::atomic<double> myofilament_s{0};
  const auto evaluate_piece = [&](const CellRange& piece) {
    Population& pop = populations[piece.population];
    if (hosts_myofilament_[piece.population]) {
      const auto started = Clock::now();
      for (auto& m : myofilaments)
        if (m.host == static_cast<int>(piece.population)) evaluate_myofilament(m, piece, t_ms, after);
      myofilament_s.fetch_add(std::chrono::duration<double>(Clock::now() - started).count(),
                              std::memory_order_relaxed);
    }
    block_inputs(piece.population, piece.begin, piece.end);
    if (!after) return pop.evaluate_cells(piece.begin, piece.end, t_ms);
    pop.evaluate_cells(piece.begin, piece.end, t_ms, [&](const BlockView& block) { after(pop, block); }, false);
  };
  if (blocks_.size() == 1 && myofilaments.empty()) {
    // One block and no myofilament to share the time with (a single cell):
    // on this thread without the schedule's two clock readings, which CVODE's
    // thousands of evaluations per simulated second paid (4 % of a CRN cell's run).
    evaluate_piece(blocks_[0]);
    if (after_all) after_all(0, 1);
    for (const auto& pop : populations) pop.rethrow_model_fault();
    return 0.0;
  }
  schedule_.run(blocks_, evaluate_piece, after_all);
  for (const auto& m : myofilaments) m.pop.rethrow_model_fault();
  for (const auto& pop : populations) pop.rethrow_model_fault();
  return schedule_.busy_s() > 0 ? myofilament_s.load() / schedule_.busy_s() : 0.0;
}

// A myofilament model over the cells of one piece of its host, first in the
// piece's work: it reads the host's Ca_i (a host state, not yet advanced), and
// its outputs for these cells (troponin flux, sarcomere length) feed the
// host's inputs and stretch-activated current for the same cells only.
void CellSystem::evaluate_myofilament(Myofilament& m, const CellRange& piece, double t_ms,
                                      const AfterPopulationBlock& after) {
  const Population& host = populations[static_cast<std::size_t>(m.host)];
  const std::size_t n = host.size();
  std::copy(host.y.begin() + m.host_ca_state * n + piece.begin, host.y.begin() + m.host_ca_state * n + piece.end,
            m.pop.inputs.begin() + piece.begin);
  if (!after) m.pop.evaluate_cells(piece.begin, piece.end, t_ms);
  else m.pop.evaluate_cells(piece.begin, piece.end, t_ms, [&](const BlockView& block) { after(m.pop, block); });
  if (!m.rest_sarcomere_length.empty() && !stretch_by_cell_.empty()) {  // (the run has started; the mechanics read it)
    const double* length = m.pop.outputs.data() + m.sarcomere_output * n;
    for (std::size_t c = piece.begin; c < piece.end; ++c)
      stretch_by_cell_[numbering.tissue_cell(static_cast<std::size_t>(host.cells[c]))] =
          length[c] / m.rest_sarcomere_length[c];
  }
  if (m.host_trpn_input < 0) return;
  // Troponin flux back into the host's Ca balance (calcium feedback).
  Population& host_inputs = populations[static_cast<std::size_t>(m.host)];
  std::copy(m.pop.outputs.begin() + m.trpn_flux_output * n + piece.begin,
            m.pop.outputs.begin() + m.trpn_flux_output * n + piece.end,
            host_inputs.inputs.begin() + m.host_trpn_input * n + piece.begin);
}

void CellSystem::evaluate(double t_stim_ms, double t_ms, const AfterPopulationBlock& after,
                          const BlockSchedule::AfterAll& after_all) {
  // One clock reading per phase boundary (each reading ends one phase and starts
  // the next): with CVODE on a single cell this runs ~2000 times per simulated
  // second, where pairs of readings per phase cost a few per cent.
  auto clock = Clock::now();
  auto lap = [&](Timer timer) {
    const auto now = Clock::now();
    seconds[timer] += std::chrono::duration<double>(now - clock).count();
    clock = now;
  };
  // 1. Currents into each cell: the stimulus here; the gap-junction and
  // stretch-activated currents block by block in step 2, in parallel.
  // (Zeros between pulses stand: not rewritten every step, their cache lines
  // stay shared by the cores that read them. A pulse writes its own cells
  // only, a rank's own over ranks: not every cell of the tissue.)
  const bool pulse = stimulus.on(t_stim_ms);
  if (stimulus_in_i_ext_ || pulse) {
    stimulus.clear_current(i_ext_pA.data());
    stimulus.add_current(t_stim_ms, i_ext_pA.data());
  }
  stimulus_in_i_ext_ = pulse;
  refresh_gap_current_ = false;
  if (coupler && !implicit_coupling && (refresh_coupling || gap_current_pA.size() != populations.size())) {
    if (!voltage_fresh) gather_voltage();
    if (refresh_ghost_voltages) refresh_ghost_voltages(V_mV.data());
    gap_current_pA.resize(populations.size());
    for (std::size_t p = 0; p < populations.size(); ++p) gap_current_pA[p].resize(populations[p].size());
    refresh_gap_current_ = true;
  }
  voltage_fresh = false;  // the states are about to change
  lap(kCoupling);
  // 2. The myofilament and ionic models, piece by piece of cells (each piece:
  // myofilaments from their host's Ca_i, then the host). The loop's wall time
  // is shared between the two in proportion to their time in the pieces.
  const double myofilament_share = evaluate_ionic(t_ms, after, after_all);
  const auto now = Clock::now();
  const double loop_s = std::chrono::duration<double>(now - clock).count();
  seconds[kMyofilament] += myofilament_share * loop_s;
  seconds[kIonic] += (1 - myofilament_share) * loop_s;
}

}  // namespace fibrodem
