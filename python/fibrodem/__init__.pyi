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
