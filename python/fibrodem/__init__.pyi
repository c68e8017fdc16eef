# Type stub of the fibrodem package (units: ms, mV, pA, pF, nS, mM, um).
import os
from typing import Any, Callable, Mapping, Optional, Sequence, Union

import numpy as np

__version__: str
PathLike = Union[str, os.PathLike]
JSONValue = Union[None, bool, int, float, str, Sequence[Any], Mapping[str, Any]]

class ManifestError(ValueError):
    path: str       # dotted JSON path of the offending value ("" : the whole manifest)
    expected: str   # what was expected there
    def __init__(self, message: str, path: str = ..., expected: str = ...) -> None: ...

class PluginError(RuntimeError): ...

class RunError(RuntimeError):
    result: Any     # Result (run) or CellLog (simulate_cell) up to the failure
    def __init__(self, message: str, result: Any = ...) -> None: ...

class Scene:
    def set(self, path: str, value: JSONValue) -> "Scene": ...
    def copy(self) -> "Scene": ...
    @property
    def manifest(self) -> dict: ...
    @property
    def name(self) -> str: ...
    @property
    def duration_ms(self) -> float: ...

class Result:
    t_ms: np.ndarray                 # [ms]
    traces: dict[str, np.ndarray]    # "V_0" -> samples in the variable's unit
    biomarkers: Any                  # pandas.DataFrame if pandas is installed, else a structured np.ndarray
    summary: dict
    maps: dict[str, np.ndarray]      # activation_ms, apd90_ms, rmp_mV, apo_mV per cell (last beat)
    cell_types: np.ndarray
    status: str                      # "completed", "interrupted", "failed"
    out_dir: Optional[str]
    @property
    def variables(self) -> list[str]: ...
    def cells(self, variable: str = ...) -> list[int]: ...
    def trace(self, variable: str, cell: Optional[int] = ...) -> np.ndarray: ...
    def plot(self, path: Optional[PathLike] = ..., variable: str = ...) -> Any: ...

class CellLog(dict[str, np.ndarray]):
    biomarkers: np.ndarray
    integration_s: float             # [s]
    integration_cpu_s: float         # [s]
    set_up_s: float                  # [s]

def load_scene(source: Union[PathLike, Mapping[str, Any]]) -> Scene: ...
def run(scene: Scene, out: Optional[PathLike] = ...,
        progress: Union[None, bool, Callable[[float, float], Any]] = ..., overwrite: bool = ...) -> Result: ...
def read(directory: PathLike) -> Result: ...
def read_sweep(directory: PathLike, stats: bool = ...) -> Any: ...
def plugins() -> list[dict]: ...
def pacing(period_ms: float = ..., amplitude_pA: float = ..., duration_ms: float = ..., start_ms: float = ...,
           count: Optional[int] = ..., target: Any = ...) -> dict: ...
def simulate_cell(model: str, variant: Optional[str] = ..., parameters: Optional[Mapping[str, float]] = ...,
                  stimulus: Union[None, Mapping[str, Any], Sequence[Mapping[str, Any]]] = ...,
                  duration_ms: float = ..., solver: Union[None, str, Mapping[str, Any]] = ...,
                  log: Sequence[str] = ..., log_every_ms: Optional[float] = ..., cell_type: str = ...,
                  initial_state: Optional[Mapping[str, float]] = ...) -> CellLog: ...

Overrides = Union[None, Mapping[str, JSONValue], Sequence[str]]   # {path: value} or ["PATH=VALUE", ...]
ManifestSource = Union[PathLike, Mapping[str, Any], Scene]

class SweepResult:
    table: Any                       # sweep.csv's rows: DataFrame if pandas is installed, else a structured np.ndarray
    stats: Any                       # sweep_stats.csv's rows (with seeds), else None
    statuses: list[str]              # "completed", "failed", "interrupted", "crashed"
    errors: list[str]
    summaries: list[Optional[dict]]
    values: list[dict[str, Any]]     # grid path -> value per run (with "seed")
    seeds: list[int]
    reused: int
    markdown: str
    out_dir: str
    runner: str                      # "process: <executable>" or "in_process"
    @property
    def completed(self) -> bool: ...
    def result(self, k: int) -> Result: ...
    def __len__(self) -> int: ...

class Comparison:
    rows: Any                        # comparison.csv's rows
    paired: Any                      # paired.csv's rows (with seeds), else None
    seeds: list[int]
    summaries_a: list[dict]
    summaries_b: list[dict]
    markdown: str
    out_dir: str
    a_dir: str
    b_dir: str
    @property
    def a(self) -> Result: ...
    @property
    def b(self) -> Result: ...

def sweep_executable() -> Optional[str]: ...
def sweep(sweep: Union[PathLike, Mapping[str, Any]], out: Optional[PathLike] = ..., jobs: int = ...,
          set: Overrides = ..., overwrite: bool = ..., report: bool = ...,
          runner: Optional[str] = ...) -> SweepResult: ...   # runner: None, "process", "in_process"
def vulnerable_window(manifest: ManifestSource, out: Optional[PathLike] = ..., from_ms: Optional[float] = ...,
                      to_ms: Optional[float] = ..., step_ms: Optional[float] = ..., resolution_ms: float = ...,
                      seeds: int = ..., jobs: int = ..., capture_fraction: float = ..., set: Overrides = ...,
                      overwrite: bool = ..., runner: Optional[str] = ...) -> Mapping[str, Any]: ...
def restitution(manifest: ManifestSource, out: Optional[PathLike] = ..., intervals_ms: Optional[Sequence[float]] = ...,
                cells: Optional[Sequence[int]] = ..., resolution_ms: float = ..., jobs: int = ...,
                capture_fraction: float = ..., set: Overrides = ..., overwrite: bool = ...,
                runner: Optional[str] = ...) -> Mapping[str, Any]: ...
def compare(a: ManifestSource, b: Optional[ManifestSource] = ..., out: Optional[PathLike] = ...,
            set: Overrides = ..., a_set: Overrides = ..., b_set: Overrides = ..., seeds: int = ...,
            overwrite: bool = ..., report: bool = ..., quiet: bool = ...) -> Comparison: ...
