// An Integrator advances a CellSystem in time and reports each of its own
// steps (so biomarkers see every step, not only output samples) and the
// states at requested sample times.
#pragma once

#include <limits>
#include <memory>
#include <vector>
#include <string>

#include "integrate/cell_system.hpp"
#include "integrate/solver_spec.hpp"

namespace fibrodem {

class StepObserver {
 public:
  virtual ~StepObserver() = default;
  // The next time at which the observer wants the state (+inf: none).
  virtual double next_sample_ms() const = 0;
  // The populations hold the state at t.
  virtual void on_sample(double t_ms) = 0;
  // One integrator step done; the populations hold the state at t_new.
  // dVdt (per held cell, CellSystem::numbering) is the integrator's own
  // derivative at t_new where it has one (CVODE); null means: use the
  // difference quotient over the step.
  virtual void on_step(double t_old_ms, double t_new_ms, const double* dVdt) = 0;
  // Optional work per cell that can share the step's threads: a fixed-step
  // integrator calls it, before on_step, once every cell's V at t_new is in
  // V_new (per held cell, CellSystem::numbering), on each of its threads
  // for a disjoint range of cells [begin, end), the ranges together
  // covering every held cell; it then
  // sets CellSystem::voltages_observed for on_step. (Not where the coupling
  // is split off: V changes again after the cells' step.)
  virtual void on_step_voltages(double /*t_old_ms*/, double /*t_new_ms*/, const double* /*V_new*/,
                                std::size_t /*begin*/, std::size_t /*end*/) {}
};

class Integrator {
 public:
  virtual ~Integrator() = default;
  // Advances from t_start to t_end.
  virtual void advance(CellSystem& system, double t_start_ms, double t_end_ms,
                       StepObserver& observer) = 0;
  virtual std::string describe() const = 0;
  // What the integrator did in the last advance(), for run.log (empty: nothing to say).
  virtual std::string report() const { return {}; }
};

// The integrators by `solver.method` name: the one place that registers one
// (docs/guide/plugins.md#adding-an-integrator-or-a-tissue-builder). "auto" is not
// here: it
// chooses among these (method_choice.hpp).
struct IntegratorEntry {
  const char* name;
  bool fixed_step;  // steps of solver.dt_ms (Euler, Rush-Larsen); else error-controlled
  // Reads every cell's a and b from the populations' own arrays (else from
  // each block's scratch tile only: Population::reset(false) saves them).
  bool reads_population_derivatives;
  std::unique_ptr<Integrator> (*make)(const SolverSpec& solver);
};
const std::vector<IntegratorEntry>& integrators();

// Whether the method's integrator reads the populations' a and b arrays
// (true for a name that is not registered).
bool reads_population_derivatives(const std::string& method);

// The solver's method's integrator (std::invalid_argument for an unknown one).
std::unique_ptr<Integrator> make_integrator(const SolverSpec& solver);

}  // namespace fibrodem
