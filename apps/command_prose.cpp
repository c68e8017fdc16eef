// The hand-written prose of docs/reference/command_line.md, by command (the
// rest of the page is generated from the declarations: command_reference.cpp).
// Markdown; links are relative to docs/reference/.
#include "apps/command_reference.hpp"

namespace fibrodem::cli {

const std::map<std::string, CommandProse>& command_prose() {
  static const std::map<std::string, CommandProse> prose = {
      {"",
       {{},
        R"(`fibrodem COMMAND [ARGS]`: exactly one command. `fibrodem --help` lists them,
`fibrodem COMMAND --help` gives a command's options, `fibrodem --version`
prints the version; a first word that is no command is named as such, with
the nearest command, and exits 109. Options that take a value repeat where
marked (repeatable).
`--set PATH=VALUE` everywhere overrides a manifest value: a dotted path, `[i]`
for list entries; VALUE is JSON, or else a string (`--set coupling.D_f_nS=1`,
`--set 'output.checkpoint={"every_ms": 50}'`). Exit codes:
[exit_codes.md](exit_codes.md). The program writes this page
(`fibrodem schema command-line > docs/reference/command_line.md`) from its
own declarations, and a test checks that the page is what it writes.)",
        R"(## Environment

| variable | what |
|---|---|
| `FIBRODEM_PLUGIN_PATH` | `:`-separated directories searched for plugins after a manifest's `plugin_path` ([plugins.md](../guide/plugins.md#where-plugins-are-found)) |
| `FIBRODEM_CACHE_DIR` | the cache folder: settled initial states go to its `settle/` (else `$XDG_CACHE_HOME/fibrodem/settle/`, else `~/.cache/fibrodem/settle/`) |
| `OMP_WAIT_POLICY`, `GOMP_SPINCOUNT` | when neither is set and the command may run a thread team (a tissue, or `solver.threads` above 1; `compare`, `sweep`, `vulnerable-window`, `restitution`, `bench`), fibrodem sets `GOMP_SPINCOUNT=10000` (it starts itself again once with it) so that idle OpenMP threads sleep soon; a single cell on automatic threads starts without that restart |
| `OMP_PLACES`, `OMP_PROC_BIND` | when `OMP_PLACES` is set, or `OMP_PROC_BIND` to anything but `false`, fibrodem does not start itself again (above): libgomp pins the first thread to one CPU as it loads, and a restarted process would keep only that CPU; OpenMP's spinning is then libgomp's own unless `GOMP_SPINCOUNT` is set |)"}},
      {"run",
       {{},
        "",
        R"(A folder holding another run's `summary.json` is refused without
`--overwrite`. Guide: [guide/running.md](../guide/running.md). Output:
[outputs.md](outputs.md).)"}},
      {"resume",
       {{},
        "",
        R"(Continues from the newest good checkpoint
([guide/checkpoints.md](../guide/checkpoints.md)).)"}},
      {"report",
       {{},
        "",
        R"(Writes `DIR/report.html` from the folder's files alone; works for a failed,
interrupted or killed run too ([guide/reports.md](../guide/reports.md)).)"}},
      {"validate",
       {{},
        "",
        R"(Reads the manifest, applies the overrides, loads the plugins and builds the
scene without running it; prints what would be built and the estimated memory
and output size (checkpoints included). Under `mpirun -n N` it splits the scene
as `run` would and prints each rank's memory
([guide/parallel.md](../guide/parallel.md#memory-per-rank)).)"}},
      {"compare",
       {{},
        R"(The manifests are two (A and B), or one made into two by `--a` and `--b`.)",
        R"(Guide: [guide/compare.md](../guide/compare.md).)"}},
      {"sweep",
       {{"mpirun -n N fibrodem sweep SWEEP [...]"},
        "",
        R"(`--set` applies after the sweep file's own `set`. The sweep file:
[sweep_file.md](sweep_file.md). Guide: [guide/sweeps.md](../guide/sweeps.md).)"}},
      {"vulnerable-window",
       {{},
        R"(Scans the S2 coupling interval (`stimulus[1].start_ms` after the last onset
of `stimulus[0]`), one run per interval and seed, then refines each boundary
between re-entry and none by bisection. Without `output.reentry` in the
manifest one is added (`every_ms` 2, `tau_ms` 10) with a note. Without
`--from`, `--to` and `--step` (all three or none), the scan runs from the
manifest's interval - 100 to + 100 ms by 10 ms, from at least 10 ms.)",
        R"(Writes `report.html`, `vulnerable_window.csv`, `vulnerable_window.json`,
`vulnerable_window.png` and `runs/ci_<interval>ms_seed_<seed>/`; exit status
4 if a run failed. Guide: [arrhythmia.md](../topics/arrhythmia.md#vulnerable-window).)"}},
      {"restitution",
       {{},
        R"(Moves S2 (`stimulus[1]`) to each coupling interval after the last onset of
S1 (`stimulus[0]`, a train with `count`), one run per interval, and tabulates
the S2 action potential's APD90 and APD50 against the diastolic interval;
then bisects the effective refractory period. The default intervals: S1's
period, then 800, 600, 500, 400, 350, 300, by 25 ms to 200, by 10 ms to 100;
the table holds medians over the captured cells.)",
        R"(Writes `restitution.csv`, `restitution.json`, `restitution.png` and
`runs/ci_<interval>ms/`; exit status 4 if a run failed. Guide:
[arrhythmia.md](../topics/arrhythmia.md#restitution).)"}},
      {"tune-cv",
       {{},
        R"(As openCARP's tuneCV: runs a short strand (builder `strand`) or sheet
(`fibrotic_sheet`, without its fibrosis) of the manifest's cells and
solver, paced once from one edge with `stimulus[0]`'s pulse, measures the
conduction velocity as `summary.json` does, and updates `coupling.D_m_nS`
(along) and `D_m_side_nS` (across) by the power law CV ~ D^p until every
CV is within the tolerance of its target. Prints each iteration, then the
conductances with the CVs reached. The preset `atrium-control` targets
0.98 m/s along, `atrium-caf` 0.69 m/s, across from AugmentA's anisotropy;
the `--cv-*` options override its values.)",
        R"(Exit status 2 for a target the layout cannot reach (the message gives the
closest reachable CV across), 4 when the iterations run out. Guide:
[fibrosis.md](../topics/fibrosis.md#tuning-conduction-velocity).)"}},
      {"plugins",
       {{},
        "",
        R"(Lists the cell-model plugins found on the search path, with their states
(unit, initial value, bounds), parameters (unit, default, description) and
variants; then the contact laws, each with its file and parameters. `--json`
prints the cell models as JSON instead of text (the contact laws are listed in
the text form only). Exit 3 when any plugin on the search path fails to load.)"}},
      {"plot",
       {{},
        "",
        R"(Series may carry CI bars; a null breaks a line.)"}},
      {"check-plugin",
       {{},
        "",
        R"(Exit 0 when all checks pass, 3 otherwise. The checks:
[plugins.md](../guide/plugins.md#checking-a-plugin).)"}},
      {"new-model",
       {{},
        "",
        R"(Writes a working, commented plugin skeleton: `NAME.cpp`, a `CMakeLists.txt`
for the SDK, and `NAME_test.json`. `NAME` takes letters of either case, digits
and `_`, starts with a letter and has at most 64 characters; the C++ class is
`NAME` in CamelCase (`my_model`: `MyModel`), with `Model` (`Law` for a
contact law) after it where it would be one of the skeleton's own
`State`, `Param`, `Input`, `Output`. See
[plugins.md](../guide/plugins.md#plugin-sdk).)"}},
      {"import-cellml",
       {{},
        R"(`--voltage` overrides the oxmeta annotation `membrane_voltage` and the name
rules ([cellml_import.md](../topics/cellml_import.md)); the variable is exposed as
the plugin's state `V`. `--stimulus` overrides the annotation
`membrane_stimulus_current`, the name rules and the structure rule; fibrodem's
`i_ext` replaces it wherever the model uses it. Unit inconsistencies are
warnings by default, the numbers used as written
([cellml_units.md](../topics/cellml_units.md)).)",
        R"(Exit 5 when the model is refused (the message names the element's path and
line), 1 on any other error. Guide: [cellml.md](../topics/cellml.md).)"}},
      {"bench",
       {{"fibrodem bench [--benchmark_* flags]"},
        R"(`fibrodem bench` runs the Google Benchmark suites (cell-steps/s of the kernels,
one cell for one second, the DEM step); Google Benchmark's own
`--benchmark_filter`, `--benchmark_repetitions`, ... pass through (an unknown
`--benchmark_*` flag: exit 2).)",
        ""}},
      {"bench headline",
       {{},
        R"(The headline speed figures (kernels, Fig. 3 scenes, CVODE, DEM), and the gain
from threads: [performance.md](../topics/performance.md). With `--baseline`, each
figure's ratio to the other build, and after the table every figure more
than 5 % worse than the baseline's, named with how much (a throughput lower,
or a time longer).)",
        ""}},
      {"bench accuracy",
       {{},
        R"(Runs a scene with each integrator over a ladder of steps and tolerances and
measures each against a CVODE reference: [numerics.md](../topics/numerics.md#what-accuracy-costs).)",
        R"(Lists are comma-separated.)"}},
      {"schema",
       {{},
        "",
        R"([manifest.md](manifest.md), [sweep_file.md](sweep_file.md) and this page are
this command's output. `--json` gives the JSON Schema as built into the
program (for an editor's completion or another tool's validator).)"}},
  };
  return prose;
}

}  // namespace fibrodem::cli
