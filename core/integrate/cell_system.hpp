// The system of ODEs the integrators advance: every cell's electrophysiology
// (one ionic population per cell type) and, where the scene calls for
// contraction, its myofilament model (a second population over the same cells,
// driven by the host's Ca_i), coupled by gap-junction currents and, with
// mechano-electric feedback, a stretch-activated current.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "coupling/coupler.hpp"
#include "model/block_schedule.hpp"
#include "model/population.hpp"
#include "stimulus/stimulus.hpp"
#include "tissue/cell_numbering.hpp"

namespace fibrodem {

// A myofilament population riding on an ionic one (same cells, same order).
struct Myofilament {
  Population pop;
  int host = -1;                // index of the ionic population
  int host_ca_state = -1;       // host state read as the myofilament's Ca_i input
  int host_trpn_input = -1;     // host input receiving troponin flux (calcium feedback), or -1
  int trpn_flux_output = -1;    // myofilament output dTRPN_Ca_dt
  int sarcomere_output = -1;    // myofilament output sarcomere_length
  std::vector<double> rest_sarcomere_length;  // per cell, at the start of the run
};

// Stretch-activated current, I_SAC = G (lambda - 1)/(lambda_max - 1) (V - E)
// for lambda > 1 (mechano_electric_feedback): lambda = SL / SL_rest of the
// host's myofilament model, or, when tissue_stretch is set, the cell's fibre
// stretch in the DEM tissue (by tissue cell number; NaN, a cell whose strain
// is unresolved: no current). On for the populations whose host_on is set
// (mechano_electric_feedback.cell_types).
struct StretchActivatedCurrent {
  bool on = false;
  double G_nS = 0, E_mV = 0, lambda_max = 1.1;
  std::vector<char> host_on;                           // per ionic population
  const std::vector<double>* tissue_stretch = nullptr;  // the mechanics' (MechanicsCoupling::fibre_stretch)
  double current_pA(double lambda, double V_mV) const {
    if (!(lambda > 1.0)) return 0.0;  // (NaN too)
    return G_nS * (lambda - 1.0) / (lambda_max - 1.0) * (V_mV - E_mV);
  }
};

struct CellSystem {
  std::vector<Population> populations;  // ionic, one per cell type present
  std::vector<Myofilament> myofilaments;
  std::unique_ptr<Coupler> coupler;  // null: coupling not built
  // The cell-graph edges the coupler joins: a view of the tissue's own list
  // (Tissue::cell_edges, which outlives the system), not a copy.
  std::span<const std::pair<int, int>> coupled_pairs;
  bool implicit_coupling = false;    // coupling advanced by backward Euler (split)
  // Multirate coupling (fixed-step methods): the coupling is updated every
  // coupling_every cell steps; in between an explicit current is held.
  int coupling_every = 1;
  bool refresh_coupling = true;          // set by the integrator for each step
  // The explicit coupling current last computed, per ionic population and
  // local cell (each block writes its own stretch).
  std::vector<std::vector<double>> gap_current_pA;
  Stimulus stimulus;
  StretchActivatedCurrent sac;
  // The cells held and their numbers: the tissue's every cell in one
  // process; split over ranks, this rank's own cells, then its ghosts. Every
  // per-cell array below (and each population's `cells`) is in these
  // numbers.
  CellNumbering numbering;
  // Held cell -> (ionic population, index in it); 32 bits for the index
  // (8 bytes a cell, not 16), UINT32_MAX for a ghost (its population named
  // for its type).
  std::vector<std::pair<int, std::uint32_t>> where;
  std::vector<double> V_mV;                        // per held cell
  // Set by the fixed-step integrator when its update has left every cell's
  // new V in V_mV (written to next_V_mV on the way, then swapped): the
  // observer and the next evaluation need not gather it. The evaluation that
  // next runs clears it; a gather never sets it, since other integrators
  // (CVODE, adaptive) change states between gathers.
  bool voltage_fresh = false;
  // Set by the fixed-step integrator when it has shown the step's new
  // potentials to its observer's on_step_voltages, on the step's threads.
  bool voltages_observed = false;
  std::vector<double> next_V_mV;
  std::vector<double> i_ext_pA;                    // per held cell: the stimulus of the step
  // A run split over ranks (run/halo_exchange.hpp): the populations hold this
  // rank's cells only, and this refreshes the other ranks' cells joined to
  // them (ghosts) in V_mV before the explicit gap currents read it. Null in
  // one process.
  std::function<void(double* V_mV)> refresh_ghost_voltages;
  // Split over ranks: the largest of every rank's value (an adaptive step's
  // error, its next stop), the same on every rank, so that every rank takes
  // the step control's decisions alike. Null in one process.
  std::function<double(double)> largest_over_ranks;
  double last_step_ms = 0;                         // the integrator's last step (trace dt_ms)
  // Set by an integrator that checked every state against its population's
  // limits while updating it: the observer then need not scan them again
  // unless one was out (to find and name it).
  bool states_checked = false, states_in_limits = true;
  // Wall time spent [s]: myofilament models, coupling currents, ionic models.
  std::array<double, 3> seconds{0, 0, 0};
  enum Timer { kMyofilament, kCoupling, kIonic };

  std::size_t cell_count() const { return where.size(); }

  void gather_voltage();   // populations -> V_mV
  void scatter_voltage();  // V_mV -> populations
  // Work on one block of a population right after its evaluation.
  // (The view is the block's own: see AfterBlock in population.hpp.)
  using AfterPopulationBlock = std::function<void(Population&, const BlockView& block)>;
  // Evaluates every derivative at time t, piece by piece of cells: a piece's
  // myofilaments from their host's Ca_i, then its cells' i_ext (stimulus at
  // t_stim, explicit coupling current, stretch-activated current), then its
  // ionic model. (Each cell's inputs depend on its own states and on the
  // potentials at the step's start only.) after(pop, block), if
  // given, runs on each block as soon as it is evaluated: a fixed-step
  // integrator updates the block's states there, while they are in cache (the
  // inputs every cell needs were all taken before any state changes). The
  // ionic models then write no outputs (nothing reads them between samples;
  // the trace recorder evaluates afresh); myofilaments still do (stretch and
  // troponin flux feed the cells and the mechanics).
  //
  // after_all(thread, threads), if given, runs on each of the ionic models'
  // threads once every block is done (each thread once), for work over every
  // cell that can share the step's threads.
  void evaluate(double t_stim_ms, double t_ms, const AfterPopulationBlock& after = nullptr,
                const BlockSchedule::AfterAll& after_all = nullptr);
  // The run's thread count: fixed, or for solver.threads "auto" chosen
  // between one thread and the cores by measuring both; cores lent to the
  // writer while it draws (model/thread_governor.hpp).
  ThreadGovernor& thread_governor() { return schedule_.governor(); }
  const ThreadGovernor& thread_governor() const { return schedule_.governor(); }
  // Calls f(population, local index) for each block a cell's states live in:
  // its ionic population, then its myofilament if any.
  template <class F>
  void for_each_part(std::size_t cell, F&& f) {
    const auto [p, c] = where[cell];
    f(populations[p], c);
    for (auto& m : myofilaments)
      if (m.host == p) f(m.pop, c);
  }
  // Every population, ionic and myofilament.
  template <class F>
  void for_each_population(F&& f) {
    for (auto& p : populations) f(p);
    for (auto& m : myofilaments) f(m.pop);
  }
  // Records each cell's sarcomere length as its rest length (call at t = 0),
  // and keeps stretch_by_cell() if something reads it (stretch_read).
  void record_rest_lengths(bool stretch_read);
  // Per tissue cell, its length relative to rest (SL / SL_rest) at the last
  // evaluation; 1 without a myofilament (and, split over ranks, for another
  // rank's cell); empty unless record_rest_lengths was told it is read. (Taken piece by piece in the cells'
  // parallel loop: over the Fig. 3 tissue a serial pass cost ~5 us a step.)
  const std::vector<double>& stretch_by_cell() const { return stretch_by_cell_; }

 private:
  void block_inputs(std::size_t population, std::size_t begin, std::size_t end);
  double stretch_activated_pA(const Myofilament& m, const Population& host, std::size_t local) const;
  bool refresh_gap_current_ = false;  // this step computes gap_current_pA afresh
  // Returns the myofilaments' share of the loop's busy time.
  double evaluate_ionic(double t_ms, const AfterPopulationBlock& after, const BlockSchedule::AfterAll& after_all);
  void evaluate_myofilament(Myofilament& m, const CellRange& piece, double t_ms, const AfterPopulationBlock& after);
  std::vector<bool> hosts_myofilament_;  // per ionic population
  std::vector<CellRange> blocks_;  // every block of every ionic population
  std::vector<double> stretch_by_cell_;
  bool stimulus_in_i_ext_ = true;  // i_ext_pA may hold a pulse's current (else all zeros)
  BlockSchedule schedule_;  // which thread runs which of blocks_
};

}  // namespace fibrodem
