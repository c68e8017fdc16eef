"""fibrodem from Python: the same core library as the `fibrodem` command line.

    import fibrodem
    scene = fibrodem.load_scene("examples/cell_pair_passive.json")
    scene.set("coupling.D_f_nS", 2.0)          # as --set coupling.D_f_nS=2
    result = fibrodem.run(scene)               # in memory; out="dir" writes the run's folder
    result.trace("V", 0), result.biomarkers, result.summary["mean_biomarkers"]
    swept = fibrodem.sweep("examples/sweep_cell_pair.json", out="out/s")  # as `fibrodem sweep`
    swept.table, swept.stats
    ab = fibrodem.compare(scene, a_set={"coupling.D_f_nS": 1}, b_set={"coupling.D_f_nS": 4})
    ab.rows, ab.paired                         # as `fibrodem compare`

Units follow the manifest: time ms, voltage mV, current pA (whole cell),
capacitance pF, conductance nS, concentration mM, length um.
"""

import numbers
import os
import threading
from collections.abc import Mapping

import numpy as np

from . import _core
from ._errors import ManifestError, PluginError, RunError
from ._progress import TextBar
from ._result import Result, biomarker_array, read, read_sweep
from ._study import Comparison, SweepResult, compare, restitution, sweep, sweep_executable, vulnerable_window

__version__ = _core.version
__all__ = ["Scene", "load_scene", "run", "read", "read_sweep", "plugins", "simulate_cell", "pacing", "Result",
           "CellLog", "ManifestError", "PluginError", "RunError", "sweep", "SweepResult", "sweep_executable", "compare",
           "Comparison", "vulnerable_window", "restitution"]


def _type_name(value):
    return type(value).__name__


def _on_main_thread():
    # Signal handlers belong to the main thread: only there does a run take Ctrl-C.
    return threading.current_thread() is threading.main_thread()


class Scene:
    """A manifest, checked as `fibrodem validate` checks it before building.

    Made by load_scene(); changed by set(); run by run(). What only the plugins
    and the built tissue can check (model, variant and parameter names, traced
    variables) is checked when it runs, raising ManifestError.
    """

    def __init__(self, handle):
        if not isinstance(handle, _core.Scene):
            raise TypeError("Scene(): use fibrodem.load_scene(path_or_dict) to make a scene")
        self._handle = handle

    def set(self, path, value):
        """Sets the manifest value at `path` (dotted, ``[i]`` for list entries,
        e.g. ``"coupling.D_f_nS"``, ``"stimulus[0].amplitude_pA"``) to `value`
        (any JSON-like Python value, in the unit the key names), exactly as the
        command line's ``--set PATH=VALUE`` does, then checks the whole manifest.

        Raises ManifestError (with .path and .expected) and leaves the scene
        unchanged if the result is not a valid manifest; TypeError if `path` is
        not a str or `value` not JSON-like. Returns the scene (calls chain).
        """
        if not isinstance(path, str):
            raise TypeError("Scene.set(): path must be a str like 'coupling.D_f_nS', not %s" % _type_name(path))
        self._handle.set(path, value)
        return self

    def copy(self):
        """An independent copy (set() on it leaves this one alone)."""
        return Scene(self._handle.copy())

    @property
    def manifest(self):
        """The manifest as a dict (a copy: change it with set())."""
        return self._handle.manifest()

    @property
    def name(self):
        """The manifest's name."""
        return self.manifest.get("name", "")

    @property
    def duration_ms(self):
        """The simulated time [ms]."""
        return float(self.manifest["duration_ms"])

    def __repr__(self):
        return "<fibrodem.Scene %r, %g ms>" % (self.name, self.duration_ms)


def load_scene(source):
    """A Scene from a manifest file (str or os.PathLike, JSON) or a dict of the
    manifest (the JSON format of docs/reference/manifest.md: durations in ms, currents in pA,
    conductances in nS).

    Raises ManifestError naming the JSON path of a bad value and what was
    expected (as the command line's exit status 2 reports it); TypeError for
    anything but a path or a dict.
    """
    if isinstance(source, (str, os.PathLike)):
        return Scene(_core.Scene.from_file(os.fspath(source)))
    if isinstance(source, Mapping):
        return Scene(_core.Scene.from_dict(dict(source)))
    raise TypeError("load_scene(): source must be a manifest file path (str or os.PathLike) or a dict, not %s"
                    % _type_name(source))


def _progress_callable(progress, duration_ms):
    if progress is None or progress is False:
        return None, None
    if progress is True:
        bar = TextBar(duration_ms)
        return bar, bar
    if callable(progress):
        return (lambda t_ms: progress(t_ms, duration_ms)), None
    raise TypeError("run(): progress must be None, True (a text bar) or a callable(t_ms, duration_ms), not %s"
                    % _type_name(progress))


def run(scene, out=None, progress=None, overwrite=False):
    """Runs `scene` with the core library (no subprocess) and returns a Result.

    Args:
        scene: a Scene (from load_scene).
        out: None (default): nothing is written to disk, the manifest's
            output.dir is ignored; else a folder (str or os.PathLike) that gets
            what ``fibrodem run --out`` writes (summary.json, traces.csv,
            biomarkers.csv, run.log, pictures).
        progress: None (default, silent), True (a text bar on stderr, for a
            terminal or a notebook) or a callable(t_ms, duration_ms) [ms, ms],
            called every output.progress_every_s [s] of wall time (default 1 s)
            and once at the end.
        overwrite: replace another run's files in `out` (``--overwrite``).

    The run holds no GIL (other Python threads go on). Ctrl-C (SIGINT, when
    run from the main thread) stops it at the end of the step in progress,
    with every output written (with `out`, summary.json says ``interrupted``),
    and raises KeyboardInterrupt whose ``.result`` holds the Result so far.

    Raises ManifestError (bad manifest), PluginError (missing or faulty
    plugin), RunError (the run failed, e.g. a blow-up; ``.result`` holds what
    was computed), TypeError (wrong argument types).
    """
    if not isinstance(scene, Scene):
        raise TypeError("run(): scene must be a fibrodem.Scene (from fibrodem.load_scene), not %s" % _type_name(scene))
    if out is not None and not isinstance(out, (str, os.PathLike)):
        raise TypeError("run(): out must be None or a folder path (str or os.PathLike), not %s" % _type_name(out))
    if not isinstance(overwrite, bool):
        raise TypeError("run(): overwrite must be a bool, not %s" % _type_name(overwrite))
    duration_ms = scene.duration_ms
    callback, bar = _progress_callable(progress, duration_ms)
    try:
        raw = _core.run(scene._handle, "" if out is None else os.fspath(out), overwrite, callback, _on_main_thread())
        if callback is not None:
            callback(raw["summary"].get("simulated_ms", duration_ms))
    finally:
        if bar is not None:
            bar.close()
    return _ended(raw, Result._from_core(raw))


def _ended(raw, result):
    """`result`, or the exception its run's status calls for (with `.result`)."""
    if raw["status"] == "interrupted":
        stop = KeyboardInterrupt(raw["message"])
        stop.result = result
        raise stop
    if raw["status"] == "failed":
        raise RunError(raw["message"], result)
    return result


def plugins():
    """The cell models on the command line's search path (FIBRODEM_PLUGIN_PATH,
    then beside the build's `fibrodem`), as `fibrodem plugins --json` lists
    them: a list of dicts with name, version, kind, description, reference,
    file, sha256; states (name, unit, initial, lower, upper: the physical range,
    None where unbounded, gate); parameters (name, unit, default, description);
    inputs and outputs (name, unit); variants (name, description, the
    parameters and initial states they set; the first is the default).

    Raises PluginError if a plugin on the path cannot be loaded.
    """
    found = _core.plugins()
    if found["errors"]:
        raise PluginError("; ".join(found["errors"]))
    return found["models"]


def pacing(period_ms=1000.0, amplitude_pA=2000.0, duration_ms=2.0, start_ms=50.0, count=None, target=None):
    """One stimulus entry of a manifest: rectangular pulses of `amplitude_pA`
    [pA, whole cell, positive depolarising] lasting `duration_ms` [ms], from
    `start_ms` [ms] every `period_ms` [ms], `count` times (None: to the end),
    on `target` (None: cell 0; a cell type, a list of cells or a region).
    """
    entry = {"start_ms": start_ms, "duration_ms": duration_ms, "amplitude_pA": amplitude_pA, "period_ms": period_ms,
             "target": [0] if target is None else target}
    if count is not None:
        entry["count"] = count
    return entry


class CellLog(dict):
    """simulate_cell's result: a dict "t_ms" [ms] and each logged variable (in
    its unit) -> numpy array, as Myokit's DataLog. Also:

    Attributes:
        biomarkers: structured array, one row per beat (cell, type, beat,
            activation_ms [ms], rmp_mV [mV], apo_mV [mV], apd90_ms [ms],
            dvdt_max_mV_per_ms [mV/ms]; NaN but rmp_mV where the cell did not
            fire in the beat).
        integration_s: wall time of the run itself [s] (the rest of the call
            is set-up and conversion).
        integration_cpu_s: CPU time of the run itself [s] (on a loaded
            machine the honest measure of its cost).
        set_up_s: wall time of setting the cell up [s] (plugin look-up, the
            model's parameters and, for fixed-step methods, its lookup tables).
    """

    biomarkers = None
    integration_s = 0.0
    integration_cpu_s = 0.0
    set_up_s = 0.0


def _stimulus_list(stimulus):
    if stimulus is None:
        return []
    entries = [stimulus] if isinstance(stimulus, Mapping) else stimulus
    if not isinstance(entries, (list, tuple)):
        raise TypeError("simulate_cell(): stimulus must be None, a dict (see fibrodem.pacing) or a list of them, not %s"
                        % _type_name(stimulus))
    checked = []
    for entry in entries:
        if not isinstance(entry, Mapping):
            raise TypeError("simulate_cell(): stimulus entries must be dicts, not %s" % _type_name(entry))
        checked.append(entry if "target" in entry else dict(entry, target=[0]))
    return checked


def simulate_cell(model, variant=None, parameters=None, stimulus=None, duration_ms=1000.0, solver=None,
                  log=("V",), log_every_ms=None, cell_type="myocyte", initial_state=None):
    """Simulates one uncoupled cell of `model` and returns a CellLog; for
    calibration loops of thousands of calls (no files, no summary).

    Args:
        model: a plugin's name, e.g. "colman" (see plugins()).
        variant: one of the model's variants (None: its default).
        parameters: dict name -> value in the parameter's unit (overrides).
        stimulus: None (no stimulus), a stimulus dict (fibrodem.pacing(...):
            pA, ms) or a list of them; entries without a target hit the cell.
        duration_ms: simulated time [ms].
        solver: None (the manifest default, "auto"), a method name ("cvode",
            "rush_larsen", ...) or a solver dict ({"method": "rush_larsen",
            "dt_ms": 0.01}).
        log: the states and outputs to record, e.g. ["V", "Ca_i"].
        log_every_ms: sampling interval [ms] (None: the manifest default).
        cell_type: "myocyte" or "fibroblast" (what the cell counts as in
            biomarkers; use "fibroblast" for a fibroblast model).
        initial_state: dict state name -> initial value (its unit).

    Raises ManifestError, PluginError, RunError, TypeError as run() does.
    """
    if not isinstance(model, str):
        raise TypeError("simulate_cell(): model must be a str (a plugin's name), not %s" % _type_name(model))
    if variant is not None and not isinstance(variant, str):
        raise TypeError("simulate_cell(): variant must be None or a str, not %s" % _type_name(variant))
    if parameters is None:
        parameters = {}
    elif not isinstance(parameters, Mapping):
        raise TypeError("simulate_cell(): parameters must be a dict name -> value, not %s" % _type_name(parameters))
    if not isinstance(duration_ms, numbers.Real) or isinstance(duration_ms, bool):
        raise TypeError("simulate_cell(): duration_ms must be a number [ms], not %s" % _type_name(duration_ms))
    if isinstance(solver, str):
        solver = {"method": solver}
    elif solver is not None and not isinstance(solver, Mapping):
        raise TypeError("simulate_cell(): solver must be None, a method name or a dict, not %s" % _type_name(solver))
    if isinstance(log, str) or not all(isinstance(v, str) for v in log):
        raise TypeError("simulate_cell(): log must be a list of variable names (str), not %r" % (log,))
    if log_every_ms is not None and (not isinstance(log_every_ms, numbers.Real) or isinstance(log_every_ms, bool)):
        raise TypeError("simulate_cell(): log_every_ms must be None or a number [ms], not %s"
                        % _type_name(log_every_ms))
    if not isinstance(cell_type, str):
        raise TypeError("simulate_cell(): cell_type must be 'myocyte' or 'fibroblast', not %s" % _type_name(cell_type))
    if initial_state is not None and not isinstance(initial_state, Mapping):
        raise TypeError("simulate_cell(): initial_state must be None or a dict state -> value, not %s"
                        % _type_name(initial_state))
    raw = _core.simulate_cell(model, variant, dict(parameters), None if initial_state is None else dict(initial_state),
                              _stimulus_list(stimulus), float(duration_ms), None if solver is None else dict(solver),
                              list(log), None if log_every_ms is None else float(log_every_ms), cell_type,
                              _on_main_thread())
    logged = CellLog(t_ms=raw["t_ms"])
    for name, samples in raw["columns"].items():
        logged[name[:-2] if name.endswith("_0") else name] = samples
    logged.biomarkers = biomarker_array(raw["biomarkers"])
    logged.integration_s = raw["run_s"]
    logged.set_up_s = raw["set_up_s"]
    logged.integration_cpu_s = raw["run_cpu_s"]
    return _ended(raw, logged)
