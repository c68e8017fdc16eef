"""The Python module's cost per simulate_cell call beyond the integration
(the target: at most 1 ms). The overhead of a call is its time less the run's
own (Simulation::run: the steps and their observers): argument checks, the
manifest and its checks, the cell's set-up, the results as numpy arrays.
Measured twice: in wall time, and in CPU time (process CPU time of the call
less the run's thread CPU time), which a loaded machine does not inflate.

    PYTHONPATH=build/python python3 scripts/bench_python.py [--calls 1000]

Report the figures with `uptime` beside them.
"""

import argparse
import statistics
import time

import fibrodem

parser = argparse.ArgumentParser()
parser.add_argument("--calls", type=int, default=1000)
args = parser.parse_args()

CASES = {
    # a 1-ms passive fibroblast: almost nothing but overhead
    "passive_fibroblast 1 ms rush_larsen": (args.calls, dict(
        model="passive_fibroblast", duration_ms=1.0, cell_type="fibroblast",
        solver={"method": "rush_larsen", "dt_ms": 0.01}, log_every_ms=0.5)),
    # colman, one 400-ms beat, CVODE (the auto choice for one cell), V and Ca_i every 0.1 ms
    "colman 400 ms cvode": (max(20, args.calls // 20), dict(
        model="colman", duration_ms=400.0, solver="cvode", log=["V", "Ca_i"], stimulus=fibrodem.pacing(start_ms=10))),
    # colman at a fixed step: its lookup tables come from the process-wide cache
    # (sampled once for these parameters, model/voltage_table_cache.hpp)
    "colman 10 ms rush_larsen": (max(20, args.calls // 5), dict(
        model="colman", duration_ms=10.0, solver={"method": "rush_larsen", "dt_ms": 0.01}, log_every_ms=1.0)),
    # the same with a new g_Kr_scale every call (a calibration loop): a new key,
    # so the tables are sampled afresh each time
    "colman 10 ms rush_larsen, new params": (max(20, args.calls // 5), dict(
        model="colman", duration_ms=10.0, solver={"method": "rush_larsen", "dt_ms": 0.01}, log_every_ms=1.0)),
}
VARIED = {"colman 10 ms rush_larsen, new params"}

for name, (calls, kwargs) in CASES.items():
    fibrodem.simulate_cell(**kwargs)  # plugin loaded
    wall, cpu, set_up = [], [], []
    for i in range(calls):
        if name in VARIED:
            kwargs["parameters"] = {"g_Kr_scale": 1.0 + 1e-6 * (i + 1)}
        start, start_cpu = time.perf_counter(), time.process_time()
        logged = fibrodem.simulate_cell(**kwargs)
        wall.append(time.perf_counter() - start - logged.integration_s)
        cpu.append(time.process_time() - start_cpu - logged.integration_cpu_s)
        set_up.append(logged.set_up_s)
    print("%-40s %4d calls, overhead per call [ms]: CPU median %.3f mean %.3f; wall median %.3f mean %.3f "
          "(of which the cell's set-up, wall, median %.3f)"
          % (name, calls, 1e3 * statistics.median(cpu), 1e3 * statistics.mean(cpu), 1e3 * statistics.median(wall),
             1e3 * statistics.mean(wall), 1e3 * statistics.median(set_up)))
