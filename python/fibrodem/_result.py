"""Result: a run's traces, biomarkers, summary and maps as numpy arrays, from
memory (fibrodem.run) or from a folder the command line wrote (fibrodem.read)."""

import csv
import json
import os

import numpy as np

from . import _core

# biomarkers.csv's columns (core/run/simulation_outputs.cpp record_beat) and their types.
BIOMARKER_DTYPE = np.dtype([("cell", "i8"), ("type", "U10"), ("beat", "i8"), ("activation_ms", "f8"),
                            ("rmp_mV", "f8"), ("apo_mV", "f8"), ("apd90_ms", "f8"),
                            ("dvdt_max_mV_per_ms", "f8"), ("apd50_ms", "f8")])
MAP_FIELDS = ("activation_ms", "apd90_ms", "rmp_mV", "apo_mV")


def _pandas():
    try:
        import pandas
        return pandas
    except ImportError:
        return None


def _table(array):
    """A structured array as a pandas DataFrame when pandas is installed."""
    pandas = _pandas()
    return pandas.DataFrame(array) if pandas is not None else array


def biomarker_array(columns):
    """The biomarkers' columns (name -> sequence) as one structured array."""
    n = len(columns["cell"])
    array = np.empty(n, dtype=BIOMARKER_DTYPE)
    for name in BIOMARKER_DTYPE.names:
        array[name] = columns[name]
    return array


def split_column(name):
    """traces.csv's column name -> (variable, cell); cell None for tissue-wide
    columns (eps_xx, eps_yy, eps_xy, dt_ms)."""
    variable, _, cell = name.rpartition("_")
    if variable and cell.isdigit():
        return variable, int(cell)
    return name, None


class Result:
    """One run's outputs.

    Attributes:
        t_ms: sample times [ms], shape (samples,).
        traces: dict, traces.csv's column name (``"V_0"``: variable V of cell 0;
            ``"eps_xx"``, ``"dt_ms"``: tissue-wide) -> samples, shape (samples,),
            in the variable's unit (``fibrodem.plugins()`` lists them).
        biomarkers: one row per cell and beat (biomarkers.csv): cell, type, beat,
            activation_ms [ms], rmp_mV [mV], apo_mV [mV], apd90_ms [ms],
            dvdt_max_mV_per_ms [mV/ms], apd50_ms [ms]; a pandas DataFrame when
            pandas is installed, else a numpy structured array. A beat in which
            the cell did not fire (it rose less than 20 mV) has NaN for all but
            cell, type, beat and rmp_mV.
        summary: summary.json as a dict (status, simulated_ms, mean_biomarkers, ...).
        maps: dict activation_ms [ms], apd90_ms [ms], rmp_mV [mV], apo_mV [mV]
            -> array over all cells (index = cell), the last beat of each cell as
            activation_map.png and maps.vtk draw it; NaN where a cell had none
            or did not fire in it (rmp_mV excepted).
        cell_types: array of "myocyte" / "fibroblast", one per cell.
        status: "completed", "interrupted" or "failed".
        out_dir: the output folder, or None for a run kept in memory.
    """

    def __init__(self, t_ms, traces, biomarkers, summary, cell_types, out_dir):
        self.t_ms = np.asarray(t_ms, dtype=float)
        self.traces = dict(traces)
        self._biomarkers = biomarkers
        self.biomarkers = _table(biomarkers)
        self.summary = summary
        self.cell_types = np.asarray(cell_types, dtype="U10")
        self.maps = self._maps()
        self.status = summary.get("status", "")
        self.out_dir = out_dir

    @classmethod
    def _from_core(cls, raw):
        return cls(raw["t_ms"], raw["columns"], biomarker_array(raw["biomarkers"]), raw["summary"],
                   raw["cell_types"], raw["out_dir"])

    def _maps(self):
        # As write_maps (core/run/tissue_snapshots.cpp): rows in order, the last beat of a cell wins.
        # (numpy leaves the winner of a repeated index in one assignment open: the
        # last row of each cell is picked explicitly.)
        maps = {name: np.full(len(self.cell_types), np.nan) for name in MAP_FIELDS}
        cells = self._biomarkers["cell"]
        if len(cells) == 0:
            return maps
        reversed_cells = cells[::-1]
        unique, first_in_reversed = np.unique(reversed_cells, return_index=True)
        last = len(cells) - 1 - first_in_reversed
        for name in MAP_FIELDS:
            maps[name][unique] = self._biomarkers[name][last]
        return maps

    @property
    def variables(self):
        """The traced variables' names, in traces.csv's order."""
        names = []
        for column in self.traces:
            variable, _ = split_column(column)
            if variable not in names:
                names.append(variable)
        return names

    def cells(self, variable="V"):
        """The cells whose `variable` was traced."""
        return [cell for v, cell in map(split_column, self.traces) if v == variable and cell is not None]

    def trace(self, variable, cell=None):
        """Samples of `variable` of `cell` (None: a tissue-wide column), in its unit.

        Raises KeyError naming what was traced if it was not.
        """
        name = variable if cell is None else "%s_%d" % (variable, cell)
        try:
            return self.traces[name]
        except KeyError:
            raise KeyError("%r was not traced; traced: %s" % (name, ", ".join(self.traces) or "nothing")) from None

    def plot(self, path=None, variable="V"):
        """V of every traced cell against t [ms], and each cell's APD90 [ms] per
        beat, in one matplotlib figure (returned; saved to `path` if given).

        Raises ImportError if matplotlib is not installed (it is optional).
        """
        from . import _plot
        return _plot.plot_result(self, path=path, variable=variable)

    def __repr__(self):
        return "<fibrodem.Result %s: %d samples of %d traces, %d beats%s>" % (
            self.status, len(self.t_ms), len(self.traces), len(self._biomarkers),
            ", in " + self.out_dir if self.out_dir else "")


def _read_traces(path):
    if not os.path.exists(path):
        return np.empty(0), {}
    with open(path, newline="") as f:
        header = next(csv.reader(f))
    values = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    if values.size == 0:
        values = np.empty((0, len(header)))
    return values[:, 0].copy(), {name: values[:, k].copy() for k, name in enumerate(header[1:], start=1)}


def _read_biomarkers(path):
    columns = {name: [] for name in BIOMARKER_DTYPE.names}
    if os.path.exists(path):
        with open(path, newline="") as f:
            for row in csv.DictReader(f):
                for name in BIOMARKER_DTYPE.names:
                    # (apd50_ms is absent from folders written before it was a column.)
                    columns[name].append(row.get(name) or "nan")
    return biomarker_array(columns)


def read(directory):
    """The Result of a run the command line (or fibrodem.run with out=) wrote in `directory`.

    Reads summary.json, traces.csv and biomarkers.csv; the cell types come from
    rebuilding the tissue of summary.json's manifest (no plugin is loaded). The
    numbers are those the run computed, bit for bit (the files hold shortest
    round-trip decimals). Raises FileNotFoundError if there is no summary.json.
    """
    if not isinstance(directory, (str, os.PathLike)):
        raise TypeError("read(): directory must be a path (str or os.PathLike), not %s" % type(directory).__name__)
    directory = os.fspath(directory)
    with open(os.path.join(directory, "summary.json")) as f:
        summary = json.load(f)
    t_ms, traces = _read_traces(os.path.join(directory, "traces.csv"))
    biomarkers = _read_biomarkers(os.path.join(directory, "biomarkers.csv"))
    cell_types = _core.tissue_cell_types(summary["manifest"]) if "manifest" in summary else []
    return Result(t_ms, traces, biomarkers, summary, cell_types, directory)


def _csv_table(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header, rows = rows[0], rows[1:]
    fields = []
    for k, name in enumerate(header):
        column = [row[k] for row in rows]
        try:
            values = [float(v) if v != "" else np.nan for v in column]
            fields.append((name, np.array(values, dtype=float)))
        except ValueError:
            fields.append((name, np.array(column, dtype=str)))
    array = np.empty(len(rows), dtype=[(name, v.dtype) for name, v in fields])
    for name, values in fields:
        array[name] = values
    return array


def read_sweep(directory, stats=False):
    """A sweep's table (sweep.csv that `fibrodem sweep` wrote in `directory`):
    one row per run, its --set values and results in the units its header names.

    With stats=True, sweep_stats.csv instead (sweeps over tissue seeds).
    A pandas DataFrame when pandas is installed, else a numpy structured array
    (numeric columns as float, empty cells NaN, others str).
    """
    if not isinstance(directory, (str, os.PathLike)):
        raise TypeError("read_sweep(): directory must be a path (str or os.PathLike), not %s"
                        % type(directory).__name__)
    return _table(_csv_table(os.path.join(os.fspath(directory), "sweep_stats.csv" if stats else "sweep.csv")))
