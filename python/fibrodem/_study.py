"""Studies over many runs: fibrodem.sweep and fibrodem.compare, the engines
of `fibrodem sweep` and `fibrodem compare` (core/study/), and their results."""

import json
import numbers
import os
import threading
from collections.abc import Mapping

import numpy as np

from . import _core
from ._errors import RunError
from ._result import _table, read

RUNNERS = ("process", "in_process")


def _type_name(value):
    return type(value).__name__


def _on_main_thread():
    return threading.current_thread() is threading.main_thread()


def sweep_executable():
    """The `fibrodem` executable a sweep's points run in (one child process
    each): $FIBRODEM_EXE if set (FileNotFoundError if it is not an executable
    file), else the command line built with this module (in
    fibrodem._core.cli_dir) if it is there, else None (points run in this
    process). A `fibrodem` on PATH is not used: it may be another build."""
    given = os.environ.get("FIBRODEM_EXE")
    if given:
        if not (os.path.isfile(given) and os.access(given, os.X_OK)):
            raise FileNotFoundError("FIBRODEM_EXE=%s is not an executable file (unset it to run a sweep's points in "
                                    "this process, or point it to a fibrodem executable)" % given)
        return given
    exe = os.path.join(_core.cli_dir, "fibrodem")
    return exe if os.path.isfile(exe) and os.access(exe, os.X_OK) else None


def _executable(runner):
    if runner == "in_process":
        return ""
    exe = sweep_executable()
    if runner == "process" and exe is None:
        raise FileNotFoundError("sweep(runner='process'): no fibrodem executable (set FIBRODEM_EXE to one, or "
                                "build the command line beside the module, in %s)" % _core.cli_dir)
    if runner is None or runner == "process":
        return exe or ""
    raise ValueError("sweep(): runner must be None (a process per point if the fibrodem executable is found, "
                     "else in this process), 'process' or 'in_process', not %r" % (runner,))


def _assignments(entries, what):
    """`set`: a dict path -> value, or a list of 'PATH=VALUE' strings (as --set)."""
    if entries is None:
        return []
    if isinstance(entries, Mapping):
        return [(str(path), value) for path, value in entries.items()]
    if isinstance(entries, str) or not isinstance(entries, (list, tuple)):
        raise TypeError("%s must be a dict path -> value or a list of 'PATH=VALUE' strings, not %s"
                        % (what, _type_name(entries)))
    return list(entries)


def _manifest_source(source, what):
    """A manifest as the core takes it: a path (str) or a dict."""
    from . import Scene  # (the package's own class; imported late, it imports this module)
    if isinstance(source, Scene):
        return source.manifest
    if isinstance(source, (str, os.PathLike)):
        return os.fspath(source)
    if isinstance(source, Mapping):
        return dict(source)
    raise TypeError("%s must be a manifest file path, a dict or a fibrodem.Scene, not %s" % (what, _type_name(source)))


def _cell_text(value):
    # As sweep.csv writes a grid value: a str as it is, anything else as JSON.
    return value if isinstance(value, str) else json.dumps(value)


def _column(values):
    """A column as read_sweep reads sweep.csv: float (NaN for None) if every
    value is a number, else str."""
    if all(v is None or (isinstance(v, numbers.Real) and not isinstance(v, bool)) for v in values):
        return np.array([np.nan if v is None else float(v) for v in values], dtype=float)
    return np.array([_cell_text(v) for v in values], dtype=str)


def _structured(columns):
    """name -> column (in order) as one structured array."""
    n = len(next(iter(columns.values()))) if columns else 0
    array = np.empty(n, dtype=[(name, column.dtype) for name, column in columns.items()])
    for name, column in columns.items():
        array[name] = column
    return array


class SweepResult:
    """A sweep's outcome (what ``fibrodem sweep`` writes in `out_dir`).

    Attributes:
        table: sweep.csv's rows: run, the grid values, each summary metric
            (fm_ratio, <type>_rmp_mV [mV], _apo_mV [mV], _apd90_ms [ms],
            _dvdt_max_mV_per_ms [mV/ms], cv_cm_per_s [cm/s], peak_eps_xx,
            peak_eps_yy, reentry_detected (1 or 0), reentry_duration_ms; NaN
            where a run has none) and status; a pandas
            DataFrame when pandas is installed, else a numpy structured array
            (as fibrodem.read_sweep reads it).
        stats: with tissue seeds, sweep_stats.csv's rows (per grid point:
            the grid values, seeds_completed, and per metric _mean, _sd,
            _ci95_low, _ci95_high over the seeds); None without seeds.
        statuses: per run, "completed", "failed", "interrupted" or "crashed".
        errors: per run, why it did not complete ("" if it did).
        summaries: per run, its summary.json as a dict (None if it wrote none).
        values: per run, its grid values (dict path -> value, with "seed").
        reused: how many runs had completed before with the same manifest (kept).
        markdown: sweep.md's text.
        out_dir: the sweep's folder (run k in out_dir/run_<k>).
        runner: "process: <the fibrodem executable>" or "in_process".
    """

    def __init__(self, raw, runner):
        self.out_dir = raw["out_dir"]
        self.markdown = raw["markdown"]
        self.reused = raw["reused"]
        self.runner = runner
        self.seeds = list(raw["seeds"])
        runs = raw["runs"]
        self.values = [run["values"] for run in runs]
        self.statuses = [run["status"] for run in runs]
        self.errors = [run["error"] for run in runs]
        self.summaries = [run["summary"] for run in runs]
        names = raw["metric_names"]
        columns = {"run": np.arange(len(runs), dtype=float)}
        for path in (runs[0]["values"] if runs else {}):
            columns[path] = _column([run["values"][path] for run in runs])
        for name in names:
            columns[name] = np.array([run["metrics"][name] for run in runs], dtype=float)
        columns["status"] = np.array(self.statuses, dtype=str)
        self._rows = _structured(columns)
        self.table = _table(self._rows)
        self._stats = self._statistics(raw["statistics"], names) if self.seeds else None
        self.stats = None if self._stats is None else _table(self._stats)

    @staticmethod
    def _statistics(points, names):
        columns = {}
        for path in (points[0]["values"] if points else {}):
            columns[path] = _column([p["values"][path] for p in points])
        columns["seeds_completed"] = np.array([p["completed"] for p in points], dtype=float)
        for name in names:
            for field, suffix in (("mean", "_mean"), ("sd", "_sd"), ("ci95_low", "_ci95_low"),
                                  ("ci95_high", "_ci95_high")):
                columns[name + suffix] = np.array([p["metrics"][name][field] for p in points], dtype=float)
        return _structured(columns)

    @property
    def completed(self):
        """True if every run completed (else ``fibrodem sweep`` exits with status 4)."""
        return all(status == "completed" for status in self.statuses)

    def result(self, k):
        """Run k's Result, read from its folder (fibrodem.read)."""
        return read(os.path.join(self.out_dir, "run_%d" % k))

    def __len__(self):
        return len(self.statuses)

    def __repr__(self):
        done = sum(status == "completed" for status in self.statuses)
        return "<fibrodem.SweepResult %d of %d runs completed, in %s>" % (done, len(self), self.out_dir)


def sweep(sweep, out=None, jobs=0, set=None, overwrite=False, report=True, runner=None):
    """Runs a sweep as ``fibrodem sweep`` does and returns a SweepResult.

    Args:
        sweep: a sweep file's path (its manifest relative to it) or its
            content as a dict (docs/reference/sweep_file.md; its "manifest" a
            path relative to the current folder, or the manifest itself as a
            dict or a fibrodem.Scene).
        out: the sweep's folder (``--out``; None: out/sweep_<manifest name>).
            Run k goes to out/run_<k>/; a run completed before with the same
            manifest is kept, not run again.
        jobs: runs at a time (``--jobs``; 0: one per core).
        set: overrides after the sweep file's own ``set`` (``--set``): a
            dict path -> value or a list of 'PATH=VALUE' strings.
        overwrite: run every point again (``--overwrite``).
        report: write report.html, the sweep's and each run's (False: ``--no-report``).
        runner: None (default): each run in a `fibrodem` process of its own
            (a run that crashes cannot take the sweep down) when the executable
            is found (sweep_executable(): $FIBRODEM_EXE, else the one built
            with this module), else in this process; "process" or
            "in_process" to choose. Runs are single-threaded either way, and
            their numbers equal those of ``fibrodem sweep``.

    Ctrl-C (from the main thread) stops the runs in progress at the end of a
    step and starts no other, writes the tables, and raises KeyboardInterrupt
    whose ``.result`` holds the SweepResult (run the same sweep again to
    finish it: completed runs are kept). A run that fails is in the result
    (status "failed", its error), not raised.

    Raises ManifestError (a bad sweep file or manifest), TypeError (wrong
    argument types), FileNotFoundError (runner="process" without an executable).
    """
    manifest = None
    base_dir = ""
    if isinstance(sweep, (str, os.PathLike)):
        source = os.fspath(sweep)
    elif isinstance(sweep, Mapping):
        source = dict(sweep)
        given = source.get("manifest")
        if given is not None and not isinstance(given, str):
            manifest = _manifest_source(given, "sweep(): sweep['manifest']")
            if isinstance(manifest, str):
                source["manifest"] = manifest
                manifest = None
            else:
                source["manifest"] = manifest.get("name", "manifest")
    else:
        raise TypeError("sweep(): sweep must be a sweep file path (str or os.PathLike) or a dict, not %s"
                        % _type_name(sweep))
    if out is not None and not isinstance(out, (str, os.PathLike)):
        raise TypeError("sweep(): out must be None or a folder path (str or os.PathLike), not %s" % _type_name(out))
    if not isinstance(jobs, int) or isinstance(jobs, bool) or jobs < 0:
        raise TypeError("sweep(): jobs must be an int >= 0 (0: one per core), not %r" % (jobs,))
    for name, flag in (("overwrite", overwrite), ("report", report)):
        if not isinstance(flag, bool):
            raise TypeError("sweep(): %s must be a bool, not %s" % (name, _type_name(flag)))
    executable = _executable(runner)
    raw = _core.sweep(source, manifest, base_dir, _assignments(set, "sweep(): set"),
                      "" if out is None else os.fspath(out), jobs, overwrite, report, executable, _on_main_thread())
    result = SweepResult(raw, "process: " + executable if executable else "in_process")
    if raw["interrupted"] is not None:
        stop = KeyboardInterrupt("the sweep was stopped by %s" % raw["interrupted"])
        stop.result = result
        raise stop
    return result


class Comparison:
    """An A/B comparison's outcome (what ``fibrodem compare`` writes in `out_dir`).

    Attributes:
        rows: comparison.csv's rows, the (first) pair's per-cell-type mean
            biomarkers: type, metric, a, b, b_minus_a, relative_diff ((b - a) / |a|;
            NaN when a is 0); a pandas DataFrame when pandas is installed,
            else a numpy structured array.
        paired: with seeds, paired.csv's rows: metric, pairs, a_mean, b_mean,
            b_minus_a_mean, b_minus_a_sd, ci95_low, ci95_high (of B - A), t
            and p (paired t-test, two-sided); None without seeds.
        seeds: the tissues' seeds (empty without seeds).
        summaries_a, summaries_b: each run's summary.json as a dict, per seed.
        markdown: the table ``fibrodem compare`` prints.
        out_dir: the comparison's folder; a_dir, b_dir: the (first) pair's runs.
    """

    def __init__(self, raw):
        self.out_dir = raw["out_dir"]
        self.a_dir = raw["a_dir"]
        self.b_dir = raw["b_dir"]
        self.markdown = raw["markdown"]
        self.seeds = list(raw["seeds"])
        self.summaries_a = raw["summaries_a"]
        self.summaries_b = raw["summaries_b"]
        rows = raw["rows"]
        self._rows = _structured({
            "type": np.array([r["type"] for r in rows], dtype=str),
            "metric": np.array([r["metric"] for r in rows], dtype=str),
            **{name: np.array([r[name] for r in rows], dtype=float)
               for name in ("a", "b", "b_minus_a", "relative_diff")}})
        self.rows = _table(self._rows)
        self._paired = None
        if self.seeds:
            paired = raw["paired"]
            self._paired = _structured({
                "metric": np.array([p["metric"] for p in paired], dtype=str),
                **{name: np.array([p[name] for p in paired], dtype=float)
                   for name in ("pairs", "a_mean", "b_mean", "b_minus_a_mean", "b_minus_a_sd", "ci95_low",
                                "ci95_high", "t", "p")}})
        self.paired = None if self._paired is None else _table(self._paired)

    @property
    def a(self):
        """The (first) A run's Result, read from its folder."""
        return read(self.a_dir)

    @property
    def b(self):
        """The (first) B run's Result, read from its folder."""
        return read(self.b_dir)

    def __repr__(self):
        return "<fibrodem.Comparison %s%s>" % (
            self.out_dir, ", over %d tissue seeds" % len(self.seeds) if self.seeds else "")


def compare(a, b=None, out=None, set=None, a_set=None, b_set=None, seeds=0, overwrite=False, report=True,
            quiet=True):
    """Runs variants A and B as ``fibrodem compare`` does (in this process)
    and returns a Comparison.

    Args:
        a, b: manifests (file paths, dicts or fibrodem.Scene); b None: a
            again, made different by a_set / b_set.
        out: the comparison's folder (``--out``; None: out/compare_<A's name>).
        set: overrides of both (``--set``); a_set, b_set: of A alone
            (``--a``), of B alone (``--b``); each a dict path -> value or a
            list of 'PATH=VALUE' strings.
        seeds: 0, or A and B on this many tissues (A's seed and the ones
            after it) with paired statistics (``--seeds``).
        overwrite: replace earlier runs' files in out (``--overwrite``).
        report: write report.html (False: ``--no-report``).
        quiet: False: the runs' logs also on stderr (as without ``--quiet``).

    Both variants are checked before either runs. Raises ManifestError (a bad
    manifest, naming the variant), PluginError, RunError (a run failed),
    KeyboardInterrupt (Ctrl-C from the main thread: the run in progress stops
    at the end of a step, its outputs written), TypeError.
    """
    if not isinstance(seeds, int) or isinstance(seeds, bool) or seeds < 0:
        raise TypeError("compare(): seeds must be an int >= 0, not %r" % (seeds,))
    if out is not None and not isinstance(out, (str, os.PathLike)):
        raise TypeError("compare(): out must be None or a folder path (str or os.PathLike), not %s" % _type_name(out))
    for name, flag in (("overwrite", overwrite), ("report", report), ("quiet", quiet)):
        if not isinstance(flag, bool):
            raise TypeError("compare(): %s must be a bool, not %s" % (name, _type_name(flag)))
    raw = _core.compare(_manifest_source(a, "compare(): a"), None if b is None else _manifest_source(b, "compare(): b"),
                        _assignments(set, "compare(): set"), _assignments(a_set, "compare(): a_set"),
                        _assignments(b_set, "compare(): b_set"), "" if out is None else os.fspath(out), seeds,
                        overwrite, report, not quiet, _on_main_thread())
    if raw["status"] == "interrupted":
        raise KeyboardInterrupt(raw["message"])
    if raw["status"] == "failed":
        raise RunError(raw["message"])
    return Comparison(raw)


def vulnerable_window(manifest, out=None, from_ms=None, to_ms=None, step_ms=None,
                      resolution_ms=_core.vulnerable_window_defaults["resolution_ms"], seeds=0, jobs=0,
                      capture_fraction=_core.vulnerable_window_defaults["capture_fraction"], set=None,
                      overwrite=False, runner=None):
    """Finds the S1-S2 coupling intervals that induce re-entry, as
    ``fibrodem vulnerable-window`` does (docs/topics/arrhythmia.md), and returns a dict.

    Args:
        manifest: a manifest file path, a dict or a fibrodem.Scene with S1
            (stimulus[0]) and S2 (stimulus[1]); output.reentry is added if missing.
        out: the search's folder (``--out``; None: out/vulnerable_window_<name>).
        from_ms, to_ms, step_ms: the scan (all three, or none: the manifest's
            interval +- 100 ms by 10 ms).
        resolution_ms: the bisection's resolution (``--resolution``).
        seeds: > 0: search on this many tissue seeds (``--seeds``).
        jobs: runs at a time (0: one per core).
        capture_fraction: ``--capture-fraction``.
        set: overrides of the manifest (a dict path -> value or 'PATH=VALUE' strings).
        overwrite: run every interval again.
        runner: as sweep(): None, "process" or "in_process".

    Returns a dict: ``per_seed`` (seed, windows), ``overall`` (the union over
    the seeds), each window a dict lower_ms, upper_ms, open_below, open_above;
    ``runs`` (interval_ms, seed, outcome, duration_ms, ps_max, stage, run,
    error, reused: the rows of vulnerable_window.csv); ``out_dir``,
    ``reentry_output_added``, ``reused``.
    """
    scan = (from_ms, to_ms, step_ms)
    if any(x is not None for x in scan) and any(x is None for x in scan):
        raise ValueError("vulnerable_window(): give from_ms, to_ms and step_ms together, or none of them")
    for name, x in zip(("from_ms", "to_ms", "step_ms"), scan):
        if x is not None and (isinstance(x, bool) or not isinstance(x, (int, float))):
            raise TypeError("vulnerable_window(): %s must be a number, not %r" % (name, x))
    if out is not None and not isinstance(out, (str, os.PathLike)):
        raise TypeError("vulnerable_window(): out must be None or a folder path, not %s" % _type_name(out))
    if not isinstance(seeds, int) or isinstance(seeds, bool) or seeds < 0:
        raise TypeError("vulnerable_window(): seeds must be an int >= 0, not %r" % (seeds,))
    if not isinstance(jobs, int) or isinstance(jobs, bool) or jobs < 0:
        raise TypeError("vulnerable_window(): jobs must be an int >= 0 (0: one per core), not %r" % (jobs,))
    return _core.vulnerable_window(_manifest_source(manifest, "vulnerable_window(): manifest"),
                                   _assignments(set, "vulnerable_window(): set"),
                                   "" if out is None else os.fspath(out),
                                   float(from_ms or 0), float(to_ms or 0), float(step_ms or 0), float(resolution_ms),
                                   seeds, jobs, float(capture_fraction), overwrite, _executable(runner))


def restitution(manifest, out=None, intervals_ms=None, cells=None,
                resolution_ms=_core.restitution_defaults["resolution_ms"], jobs=0,
                capture_fraction=_core.restitution_defaults["capture_fraction"], set=None, overwrite=False,
                runner=None):
    """S1-S2 action-potential restitution and the effective refractory period,
    as ``fibrodem restitution`` computes them (docs/topics/arrhythmia.md#restitution),
    returned as a dict.

    Args:
        manifest: a manifest file path, a dict or a fibrodem.Scene with S1
            (stimulus[0], a train with count) and S2 (stimulus[1]).
        out: the runs' folder (``--out``; None: out/restitution_<name>).
        intervals_ms: the S1-S2 coupling intervals (None: S1's period, then
            800 ... 100 ms).
        cells: the measured cells' indices (None: every myocyte).
        resolution_ms: the ERP's bisection resolution (0: no bisection).
        jobs: runs at a time (0: one per core).
        capture_fraction: ``--capture-fraction``.
        set: overrides of the manifest (a dict path -> value or 'PATH=VALUE' strings).
        overwrite: run every interval again.
        runner: as sweep(): None, "process" or "in_process".

    Returns a dict: ``points`` (the rows of restitution.csv, by interval,
    decreasing: interval_ms, captured, cells_measured, cells_captured,
    s1_apd90_ms, s2_apd90_ms, s2_apd50_ms, di_ms [ms, NaN where not
    captured], stage, run, error, reused), ``erp_ms`` (None when not
    bracketed) and ``out_dir``.
    """
    if out is not None and not isinstance(out, (str, os.PathLike)):
        raise TypeError("restitution(): out must be None or a folder path, not %s" % _type_name(out))
    intervals = [] if intervals_ms is None else list(intervals_ms)
    for x in intervals:
        if isinstance(x, bool) or not isinstance(x, (int, float)):
            raise TypeError("restitution(): intervals_ms must be numbers, not %r" % (x,))
    chosen = [] if cells is None else list(cells)
    for c in chosen:
        if isinstance(c, bool) or not isinstance(c, int):
            raise TypeError("restitution(): cells must be cell indices (ints), not %r" % (c,))
    if not isinstance(jobs, int) or isinstance(jobs, bool) or jobs < 0:
        raise TypeError("restitution(): jobs must be an int >= 0 (0: one per core), not %r" % (jobs,))
    return _core.restitution(_manifest_source(manifest, "restitution(): manifest"),
                             _assignments(set, "restitution(): set"), "" if out is None else os.fspath(out),
                             [float(x) for x in intervals], chosen, float(resolution_ms), jobs,
                             float(capture_fraction), overwrite, _executable(runner))
