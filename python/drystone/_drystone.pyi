"""Type stubs of the compiled module `drystone._drystone` (PyO3). Import from `drystone`."""

from __future__ import annotations

import os
from typing import Any, Callable, Dict, List, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

class DrystoneError(Exception):
    """Base of every error drystone raises; the message is the library's."""

class InputError(DrystoneError):
    """A file, key or value drystone refused."""

    file: Optional[str]
    """The file at fault, where the library names it."""
    key: Optional[str]
    """The key at fault (e.g. `geometry.top_width_m`, `blocks[b3]`), where named."""
    line: Optional[int]
    """The 1-based line in the file, where the parser gives it."""

class SolverError(DrystoneError):
    """A run that could not finish: the engine blew up, or the layout does not stand."""

class Wall:
    """A checked wall description (the TOML format of `studies/walls/*.toml`)."""

    @staticmethod
    def from_toml(path: Union[str, os.PathLike[str]]) -> Wall:
        """Reads and checks a wall file. Raises `InputError` naming the file, key and line."""
    @staticmethod
    def from_dict(spec: Dict[str, Any], path: Optional[Union[str, os.PathLike[str]]] = None) -> Wall:
        """A wall from a dict with the TOML format's keys; `path` names it in errors and is
        where named distributions are looked up from."""
    @property
    def name(self) -> str: ...
    @property
    def source(self) -> str:
        """The file it came from."""
    @property
    def length_m(self) -> float:
        """Wall length L (x), m."""
    @property
    def height_m(self) -> float:
        """Wall height H (z), m."""
    @property
    def base_width_m(self) -> float:
        """Base width B (y), m."""
    @property
    def top_width_m(self) -> float:
        """Top width b (y), m."""
    def generate(self, seed: int, realization: int = 0) -> Layout:
        """Realization `realization` from master seed `seed`: the same layout bit for bit
        on every call. Raises `InputError` if this realization cannot be built."""

class Layout:
    """The blocks of a wall (convex polyhedra), table frame: x along the wall, y out of
    plane (the side the wall falls to), z up, m."""

    @staticmethod
    def from_json(text: str) -> Layout:
        """A layout from its JSON text (the `drystone generate` format)."""
    @staticmethod
    def from_file(path: Union[str, os.PathLike[str]]) -> Layout:
        """Reads and checks a layout JSON file."""
    def to_json(self) -> str:
        """The JSON text; `Layout.from_json(l.to_json()) == l`."""
    def save(self, path: Union[str, os.PathLike[str]]) -> None:
        """Writes the JSON text to `path`."""
    def __len__(self) -> int:
        """Number of blocks n."""
    @property
    def name(self) -> str: ...
    @property
    def seed(self) -> Optional[int]:
        """Master seed it was generated from (None when read from JSON)."""
    @property
    def realization(self) -> Optional[int]:
        """Realization index (None when read from JSON)."""
    @property
    def block_ids(self) -> List[str]:
        """Block ids, length n, layout order."""
    @property
    def materials(self) -> List[str]:
        """Material name of every block, length n."""
    @property
    def material_table(self) -> List[Dict[str, Any]]:
        """The materials as written: density_kg_per_m3, kn_pa_per_m, ks_pa_per_m,
        friction_deg, cohesion_pa, tensile_strength_pa."""
    @property
    def courses(self) -> List[Optional[int]]:
        """Course index of every block (0 at the base), None where not given."""
    @property
    def wedge(self) -> npt.NDArray[np.bool_]:
        """(n,) whether each block is a wedge stone."""
    @property
    def fixed(self) -> npt.NDArray[np.bool_]:
        """(n,) whether each block is fixed."""
    @property
    def vertices(self) -> List[npt.NDArray[np.float64]]:
        """n arrays of shape (v_i, 3): each block's vertices, m."""
    @property
    def vertices_flat(self) -> npt.NDArray[np.float64]:
        """(V, 3) every block's vertices stacked, m."""
    @property
    def vertex_offsets(self) -> npt.NDArray[np.int64]:
        """(n + 1,) block i's rows of `vertices_flat` are offsets[i]:offsets[i + 1]."""
    @property
    def bounds(self) -> npt.NDArray[np.float64]:
        """(2, 3) min and max corners of the blocks, m."""

class Study:
    """A checked study file."""

    @staticmethod
    def from_toml(path: Union[str, os.PathLike[str]], realizations: Optional[int] = None) -> Study:
        """Reads and checks a study file; `realizations` replaces the file's count."""
    @property
    def name(self) -> str: ...
    @property
    def path(self) -> str: ...
    @property
    def seed(self) -> int: ...
    @property
    def realizations(self) -> int:
        """Realizations per group and sweep point."""
    @property
    def protocol(self) -> str:
        """`tilt`, `lateral` or `shake`."""
    @property
    def groups(self) -> List[str]: ...
    @property
    def points(self) -> List[str]:
        """Sweep point labels."""
    @property
    def items(self) -> int:
        """Work items: realizations of every group at every sweep point."""
    @property
    def discrepancy_settings(self) -> Dict[str, Any]:
        """The study's `[discrepancy]` settings with their defaults."""

def _tilt(
    layout: Layout,
    solver: Any = None,
    params: Optional[Dict[str, Any]] = None,
    by_hand: Optional[Dict[str, Any]] = None,
) -> Dict[str, Any]: ...
def _lateral(layout: Layout, solver: Any = None, params: Optional[Dict[str, Any]] = None) -> Dict[str, Any]: ...
def _pushover(layout: Layout, solver: Any = None, params: Optional[Dict[str, Any]] = None) -> Dict[str, Any]: ...
def _in_plane(layout: Layout, solver: Any = None, params: Optional[Dict[str, Any]] = None) -> Dict[str, Any]: ...
def _compression(layout: Layout, solver: Any = None, params: Optional[Dict[str, Any]] = None) -> Dict[str, Any]: ...
def _supports(protocol: str, solver: str) -> Tuple[bool, str]: ...
def _run_study(
    study: str,
    realizations: Optional[int] = None,
    out: Optional[str] = None,
    threads: Optional[int] = None,
    shard: Optional[str] = None,
    resume: bool = False,
    force: bool = False,
    progress: Optional[Callable[[int, int, Dict[str, Any]], Any]] = None,
) -> Dict[str, Any]: ...
def _discrepancy(
    study: str,
    settings: Optional[Dict[str, Any]] = None,
    realizations: Optional[int] = None,
    out: Optional[str] = None,
    threads: Optional[int] = None,
) -> Dict[str, Any]: ...
def _effects(study: Optional[str] = None) -> List[Dict[str, Any]]: ...
