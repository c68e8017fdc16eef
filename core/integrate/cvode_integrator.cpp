#include "integrate/cvode_integrator.hpp"

#include "integrate/block_preconditioner.hpp"
#include "integrate/cvode_vector_ops.hpp"
#include "integrate/gate_elimination_lu.hpp"

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_band.h>
#include <sunlinsol/sunlinsol_spgmr.h>
#include <sunmatrix/sunmatrix_band.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace fibrodem {

namespace {

// Where each cell's states live in CVODE's vector: cell by cell, each cell's
// ionic states first (so its potential is at offset + voltage_state), then its
// myofilament states.
struct Layout {
  std::vector<std::size_t> offset;  // per cell
  std::vector<std::size_t> states;  // per cell
  std::size_t size = 0;
  long half_bandwidth = 0;

  explicit Layout(CellSystem& sys) {
    offset.resize(sys.cell_count());
    states.resize(sys.cell_count());
    for (std::size_t cell = 0; cell < sys.cell_count(); ++cell) {
      offset[cell] = size;
      sys.for_each_part(cell, [&](const Population& pop, std::size_t) { states[cell] += pop.n_states(); });
      size += states[cell];
      // A cell's derivatives depend on all its own states ...
      half_bandwidth = std::max(half_bandwidth, static_cast<long>(states[cell]) - 1);
    }
    // ... and, through the coupling current, on its neighbours' potentials.
    if (sys.coupler)
      for (const auto& [i, j] : sys.coupled_pairs)
        half_bandwidth = std::max({half_bandwidth, reach(sys, i, j), reach(sys, j, i)});
  }

 private:
  // Farthest distance from the rows of `cell` to the potential of `neighbour`.
  long reach(const CellSystem& sys, int cell, int neighbour) const {
    const long v = static_cast<long>(offset[neighbour]) +
                   sys.populations[sys.where[neighbour].first].voltage_state;
    const long first = static_cast<long>(offset[cell]);
    const long last = first + static_cast<long>(states[cell]) - 1;
    return std::max(std::abs(first - v), std::abs(last - v));
  }
};

// Where entry i of CVODE's vector lives in the populations: its state y and its
// linear form dy/dt = a + b y. Built once per advance() (the populations' arrays
// keep their addresses during a run), so the right-hand side, called thousands
// of times per simulated second, is three flat loops with no lookups.
struct StateMap {
  std::vector<double*> y;
  std::vector<const double*> a, b;

  StateMap(const Layout& layout, CellSystem& sys) : y(layout.size), a(layout.size), b(layout.size) {
    for (std::size_t cell = 0; cell < sys.cell_count(); ++cell) {
      std::size_t i = layout.offset[cell];
      sys.for_each_part(cell, [&](Population& pop, std::size_t c) {
        const std::size_t n = pop.size();
        for (std::size_t k = 0; k < pop.n_states(); ++k, ++i) {
          y[i] = &pop.y[k * n + c];
          a[i] = &pop.a[k * n + c];
          b[i] = &pop.b[k * n + c];
        }
      });
    }
  }

  // CVODE's vector -> the populations.
  void unpack(const double* from) const {
    for (std::size_t i = 0; i < y.size(); ++i) *y[i] = from[i];
  }
  // The populations -> CVODE's vector.
  void pack(double* to) const {
    for (std::size_t i = 0; i < y.size(); ++i) to[i] = *y[i];
  }
};

struct Context {
  CellSystem* system = nullptr;
  const StateMap* map = nullptr;
  double t_stimulus = 0;  // the stimulus is evaluated here for the whole interval
  std::string error;
  // What a callback caught (a model that threw): exceptions must not cross
  // CVODE's C frames, so the callback returns -1 and check() throws this.
  std::string fault;
  std::unique_ptr<BlockPreconditioner> preconditioner;  // Krylov solver only
};

// The system's derivatives f(t, y); false if any is not finite.
bool evaluate_rhs(Context& ctx, double t, const double* y, double* f) {
  const StateMap& map = *ctx.map;
  map.unpack(y);
  ctx.system->evaluate(ctx.t_stimulus, t);
  // One finiteness test for the whole vector: a NaN or infinity in any entry
  // makes the sum non-finite.
  double sum = 0;
  for (std::size_t i = 0; i < map.y.size(); ++i) {
    f[i] = *map.a[i] + *map.b[i] * y[i];
    sum += f[i];
  }
  return std::isfinite(sum);
}

int right_hand_side(double t, N_Vector y, N_Vector ydot, void* user) {
  auto& ctx = *static_cast<Context*>(user);
  try {
    // 1: recoverable, CVODE retries with a smaller step.
    return evaluate_rhs(ctx, t, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot)) ? 0 : 1;
  } catch (const std::exception& e) {
    ctx.fault = e.what();
    return -1;  // unrecoverable: CVODE stops
  }
}

int preconditioner_setup(double t, N_Vector y, N_Vector fy, sunbooleantype jok, sunbooleantype* jcur,
                         double gamma, void* user) {
  auto& ctx = *static_cast<Context*>(user);
  try {
    const bool ok = ctx.preconditioner->setup(
        N_VGetArrayPointer(y), N_VGetArrayPointer(fy), jok, gamma,
        [&](const double* yp, double* fp) { return evaluate_rhs(ctx, t, yp, fp); });
    *jcur = jok ? SUNFALSE : SUNTRUE;
    return ok ? 0 : 1;
  } catch (const std::exception& e) {
    ctx.fault = e.what();
    return -1;
  }
}

int preconditioner_solve(double, N_Vector, N_Vector, N_Vector r, N_Vector z, double, double, int, void* user) {
  static_cast<Context*>(user)->preconditioner->solve(N_VGetArrayPointer(r), N_VGetArrayPointer(z));
  return 0;
}

std::unique_ptr<BlockPreconditioner> make_preconditioner(CellSystem& sys, const Layout& layout) {
  std::vector<std::size_t> v_rows(sys.cell_count());
  std::vector<double> coupling(sys.cell_count(), 0.0);
  const std::vector<double> total = sys.coupler ? sys.coupler->total_conductance_nS() : std::vector<double>();
  for (std::size_t cell = 0; cell < sys.cell_count(); ++cell) {
    const Population& host = sys.populations[sys.where[cell].first];
    v_rows[cell] = layout.offset[cell] + static_cast<std::size_t>(host.voltage_state);
    if (!total.empty()) coupling[cell] = -total[cell] / host.capacitance_pF;
  }
  return std::make_unique<BlockPreconditioner>(layout.offset, layout.states, v_rows, coupling);
}

// CVODE keeps the Jacobian it last computed and, at each linear-solver set-up
// (~130 per simulated second of one CRN cell), copies it into the Newton
// matrix and forms M = I - gamma J there. SUNDIALS' dense ops do both entry by
// entry through the matrix's column pointers, ~30 instructions an entry: 11 %
// of a one-cell run. A dense matrix's entries are one column-major array, so
// these do the same in one pass. (Each SUNMatrix owns its ops; a clone, CVODE's
// saved Jacobian, gets them too.)
void use_one_pass_dense_ops(SUNMatrix A);

int copy_dense(SUNMatrix from, SUNMatrix to) {
  if (SM_LDATA_D(from) != SM_LDATA_D(to)) return SUNMAT_ILL_INPUT;
  std::copy_n(SM_DATA_D(from), SM_LDATA_D(from), SM_DATA_D(to));
  return SUNMAT_SUCCESS;
}

int scale_add_identity_dense(double c, SUNMatrix A) {
  double* a = SM_DATA_D(A);
  const sunindextype rows = SM_ROWS_D(A), diagonal = std::min(rows, SM_COLUMNS_D(A));
  for (sunindextype i = 0; i < SM_LDATA_D(A); ++i) a[i] *= c;
  for (sunindextype i = 0; i < diagonal; ++i) a[i * rows + i] += 1.0;
  return SUNMAT_SUCCESS;
}

SUNMatrix clone_dense(SUNMatrix A) {
  SUNMatrix B = SUNDenseMatrix(SM_ROWS_D(A), SM_COLUMNS_D(A), A->sunctx);
  if (B) use_one_pass_dense_ops(B);
  return B;
}

void use_one_pass_dense_ops(SUNMatrix A) {
  A->ops->copy = copy_dense;
  A->ops->scaleaddi = scale_add_identity_dense;
  A->ops->clone = clone_dense;
}

// CVODE's dense direct solve with the gate rows eliminated first (see
// gate_elimination_lu.hpp): a SUNDIALS linear solver over CVODE's dense matrix
// M = I - gamma J, which CVODE still forms (finite-difference Jacobian).
GateEliminationLu& gate_lu(SUNLinearSolver s) { return *static_cast<GateEliminationLu*>(s->content); }

SUNLinearSolver make_gate_elimination_solver(sunindextype n, SUNContext sun) {
  SUNLinearSolver s = SUNLinSolNewEmpty(sun);
  if (!s) throw std::runtime_error("CVODE: cannot create the linear solver");
  s->content = new GateEliminationLu(static_cast<std::size_t>(n));
  s->ops->gettype = [](SUNLinearSolver) { return SUNLINEARSOLVER_DIRECT; };
  s->ops->getid = [](SUNLinearSolver) { return SUNLINEARSOLVER_CUSTOM; };
  // A singular matrix is recoverable: CVODE retries with a smaller step.
  s->ops->setup = [](SUNLinearSolver self, SUNMatrix A) {
    return gate_lu(self).factor(SM_DATA_D(A)) ? SUNLS_SUCCESS : SUNLS_LUFACT_FAIL;
  };
  s->ops->solve = [](SUNLinearSolver self, SUNMatrix, N_Vector x, N_Vector b, double) {
    N_VScale(1.0, b, x);
    gate_lu(self).solve(N_VGetArrayPointer(x));
    return SUNLS_SUCCESS;
  };
  s->ops->free = [](SUNLinearSolver self) {
    delete static_cast<GateEliminationLu*>(self->content);
    self->content = nullptr;
    SUNLinSolFreeEmpty(self);
    return 0;
  };
  return s;
}

void record_error(int /*code*/, const char* module, const char* function, char* message, void* user) {
  auto& ctx = *static_cast<Context*>(user);
  ctx.error = std::string(module) + "::" + function + ": " + message;
}

void check(int flag, const char* what, const Context& ctx) {
  if (flag < 0 && !ctx.fault.empty()) throw std::runtime_error(ctx.fault);
  if (flag < 0)
    throw std::runtime_error(std::string("CVODE ") + what + " failed (flag " + std::to_string(flag) +
                             ")" + (ctx.error.empty() ? "" : ": " + ctx.error));
}

// A population of one cell evaluates its model on the scalar path while CVODE
// advances it: on the SIMD path one cell fills one lane of a register and
// every state is loaded and stored lane by lane (simd::load's padding), which
// cost CRN and Ni 2017 ~25 % more CPU per simulated second than the same
// equations in double. Restores each population's own choice afterwards.
class ScalarPathForOneCell {
 public:
  explicit ScalarPathForOneCell(CellSystem& system) : system_(system) {
    system_.for_each_population([&](Population& pop) {
      kept_.push_back(pop.scalar_reference);
      if (pop.size() == 1) pop.scalar_reference = true;
    });
  }
  ~ScalarPathForOneCell() {
    std::size_t k = 0;
    system_.for_each_population([&](Population& pop) { pop.scalar_reference = kept_[k++]; });
  }
  ScalarPathForOneCell(const ScalarPathForOneCell&) = delete;
  ScalarPathForOneCell& operator=(const ScalarPathForOneCell&) = delete;

 private:
  CellSystem& system_;
  std::vector<bool> kept_;
};

}  // namespace

void CvodeIntegrator::advance(CellSystem& system, double t_start, double t_end, StepObserver& observer) {
  const Layout layout(system);
  system.for_each_population([](Population& pop) { pop.use_derivatives(); });  // (the map points into them)
  const StateMap map(layout, system);
  const ScalarPathForOneCell scalar_path(system);
  Context ctx;
  ctx.system = &system;
  ctx.map = &map;

  SUNContext sun = nullptr;
  if (SUNContext_Create(nullptr, &sun) != 0) throw std::runtime_error("CVODE: cannot create a context");
  struct Guard {
    SUNContext sun;
    void* mem = nullptr;
    N_Vector y = nullptr, dky = nullptr;
    SUNMatrix A = nullptr;
    SUNLinearSolver ls = nullptr;
    ~Guard() {
      if (ls) SUNLinSolFree(ls);
      if (A) SUNMatDestroy(A);
      if (y) N_VDestroy(y);
      if (dky) N_VDestroy(dky);
      if (mem) CVodeFree(&mem);
      SUNContext_Free(&sun);
    }
  } g{sun};

  const auto n = static_cast<sunindextype>(layout.size);
  g.y = N_VNew_Serial(n, sun);
  g.dky = N_VNew_Serial(n, sun);
  use_compiled_vector_ops(g.y);  // before CVodeInit: CVODE's work vectors are clones of y
  use_compiled_vector_ops(g.dky);
  double* y = N_VGetArrayPointer(g.y);
  map.pack(y);

  g.mem = CVodeCreate(CV_BDF, sun);
  check(CVodeSetErrHandlerFn(g.mem, record_error, &ctx), "SetErrHandlerFn", ctx);
  check(CVodeInit(g.mem, right_hand_side, t_start, g.y), "Init", ctx);
  check(CVodeSStolerances(g.mem, spec_.rtol, spec_.atol), "SStolerances", ctx);
  check(CVodeSetUserData(g.mem, &ctx), "SetUserData", ctx);
  check(CVodeSetMaxNumSteps(g.mem, 10000000), "SetMaxNumSteps", ctx);

  // Dense for small systems; band when the band is narrow compared with the
  // system; otherwise GMRES with the per-cell block preconditioner.
  const long half = std::min<long>(layout.half_bandwidth, n - 1);
  std::string choice = spec_.linear_solver;
  if (choice == "auto") choice = n <= 200 ? "dense" : 4 * (2 * half + 1) < n && half < 200 ? "band" : "krylov";
  if (choice == "band") {
    g.A = SUNBandMatrix(n, half, half, sun);
    g.ls = SUNLinSol_Band(g.y, g.A, sun);
    linear_solver_used_ = "band (half-bandwidth " + std::to_string(half) + ")";
  } else if (choice == "dense") {
    g.A = SUNDenseMatrix(n, n, sun);
    use_one_pass_dense_ops(g.A);
    g.ls = make_gate_elimination_solver(n, sun);
    linear_solver_used_ = "dense (gate rows eliminated first)";
  } else {
    g.ls = SUNLinSol_SPGMR(g.y, SUN_PREC_LEFT, 0, sun);
    ctx.preconditioner = make_preconditioner(system, layout);
    linear_solver_used_ = "GMRES with a per-cell block-diagonal preconditioner";
  }
  check(CVodeSetLinearSolver(g.mem, g.ls, g.A), "SetLinearSolver", ctx);
  if (ctx.preconditioner)
    check(CVodeSetPreconditioner(g.mem, preconditioner_setup, preconditioner_solve), "SetPreconditioner", ctx);

  // No cap on the step by default: the stop at each stimulus edge already keeps
  // CVODE from stepping over a pulse, and between edges the right-hand side is
  // smooth, so the error test alone should choose the step (Myokit does the same).
  if (spec_.max_step_ms > 0) check(CVodeSetMaxStep(g.mem, spec_.max_step_ms), "SetMaxStep", ctx);

  // Row of each cell's potential, for the dV/dt handed to the observer.
  std::vector<std::size_t> v_row(system.cell_count());
  for (std::size_t cell = 0; cell < system.cell_count(); ++cell)
    v_row[cell] = layout.offset[cell] + system.populations[system.where[cell].first].voltage_state;
  std::vector<double> dVdt(system.cell_count());

  // CVodeReInit zeroes CVODE's counters: the run's work is summed over the
  // intervals between stimulus edges.
  work_ = {};
  const auto add_interval_work = [&] {
    long steps = 0, rhs = 0, jacobians = 0, jacobian_rhs = 0;
    CVodeGetNumSteps(g.mem, &steps);
    CVodeGetNumRhsEvals(g.mem, &rhs);
    CVodeGetNumJacEvals(g.mem, &jacobians);
    CVodeGetNumLinRhsEvals(g.mem, &jacobian_rhs);
    work_.steps += steps;
    work_.rhs_evaluations += rhs + jacobian_rhs;
    work_.jacobians += jacobians;
  };

  double t = t_start;
  while (observer.next_sample_ms() <= t + kTimeEpsilon_ms) observer.on_sample(observer.next_sample_ms());
  while (t < t_end - kTimeEpsilon_ms) {
    // One interval between stimulus edges: the stimulus is constant in it, CVODE
    // stops exactly at its end (tstop) and restarts from there at low order, as
    // the derivative jumps at an edge.
    const double stop = std::min(t_end, system.stimulus.next_edge_after(t));
    ctx.t_stimulus = 0.5 * (t + stop);
    if (t > t_start) {
      add_interval_work();
      check(CVodeReInit(g.mem, t, g.y), "ReInit", ctx);
    }
    check(CVodeSetStopTime(g.mem, stop), "SetStopTime", ctx);
    while (t < stop - kTimeEpsilon_ms) {
      const double t_old = t;
      const int flag = CVode(g.mem, stop, g.y, &t, CV_ONE_STEP);
      check(flag, "step", ctx);
      // Samples inside the step, from CVODE's interpolating polynomial.
      while (observer.next_sample_ms() <= t + kTimeEpsilon_ms) {
        const double ts = observer.next_sample_ms();
        check(CVodeGetDky(g.mem, std::min(ts, t), 0, g.dky), "GetDky", ctx);
        map.unpack(N_VGetArrayPointer(g.dky));
        observer.on_sample(ts);
      }
      map.unpack(y);
      check(CVodeGetDky(g.mem, t, 1, g.dky), "GetDky", ctx);
      const double* dy = N_VGetArrayPointer(g.dky);
      for (std::size_t cell = 0; cell < system.cell_count(); ++cell) dVdt[cell] = dy[v_row[cell]];
      system.last_step_ms = t - t_old;
      observer.on_step(t_old, t, dVdt.data());
    }
    t = stop;
  }
  map.unpack(y);
  add_interval_work();
}

std::string CvodeIntegrator::describe() const {
  std::ostringstream s;
  s << "CVODE BDF/Newton, rtol " << spec_.rtol << ", atol " << spec_.atol << ", "
    << (linear_solver_used_.empty() ? spec_.linear_solver : linear_solver_used_) << " linear solver";
  if (work_.steps > 0)
    s << "; last run " << work_.steps << " steps, " << work_.rhs_evaluations << " right-hand sides, "
      << work_.jacobians << " Jacobians";
  return s.str();
}

}  // namespace fibrodem
