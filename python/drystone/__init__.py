"""drystone from Python: seeded dry stone wall layouts, tilting-table and static lateral
load tests with a rigid-block DEM, studies as polars DataFrames, and the model-discrepancy
analysis. The computations are the Rust library's own (no shelling out); long runs release
the GIL.

Units are SI (m, Pa, N, s) except angles in degrees and the study tables' displacements in
cm, as in the files and tables of the command-line tool. Frame: the table frame, x along
the wall, y out of plane (positive: the side the wall falls to), z up; the table is z = 0.

    import drystone
    wall = drystone.Wall.from_toml("studies/walls/sbl.toml")
    layout = wall.generate(seed=20210917, realization=0)
    res = drystone.tilt(layout)
    study = drystone.run_study("studies/tilting_table.toml", realizations=2, out="out/py")
    df = study.realizations
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Dict, List, Optional, Tuple, Union

import numpy as np

from . import _drystone as _native
from ._drystone import (
    DrystoneError,
    InputError,
    Layout,
    SolverError,
    Study,
    Wall,
    __version__,
)

__all__ = [
    "__version__",
    "DrystoneError",
    "InputError",
    "SolverError",
    "Wall",
    "Layout",
    "Study",
    "Mechanism",
    "TiltResult",
    "LateralResult",
    "PushoverResult",
    "StudyResult",
    "Discrepancy",
    "Effect",
    "tilt",
    "lateral",
    "pushover",
    "in_plane",
    "compression",
    "supports",
    "run_study",
    "discrepancy",
    "effects",
]

PathLike = Union[str, "os.PathLike[str]"]


@dataclass(frozen=True)
class Mechanism:
    """How a wall failed, read from the motion between its last stable and first unstable
    state (`loading::mechanism` of the library).

    `kind`: `toppling`, `sliding`, `mixed` or `none` (the wall stood). `joint`: the
    governing joint, `table/ID` or `ID_A/ID_B`. `joints`: every failing joint with its kind,
    lowest first. `blocks`: ids of the blocks that moved. `failure_height_fraction`: the
    lowest bed joint of the moving part over the wall height (0: the table joint);
    `failure_kind`: toppling, sliding, mixed or bending; `start`: `uniform`, `centre` or
    `end`; `extent_fraction`: share of the length the moving blocks span (None when nothing
    moved). `str(mechanism)` is its kind.
    """

    kind: str
    joint: str
    joints: List[Tuple[str, str]]
    blocks: List[str]
    failure_height_fraction: Optional[float] = None
    failure_kind: Optional[str] = None
    start: Optional[str] = None
    extent_fraction: Optional[float] = None

    @staticmethod
    def _from(d: Dict[str, Any]) -> "Mechanism":
        r = d.get("reading") or {}
        return Mechanism(
            kind=d["kind"],
            joint=d["joint"],
            joints=[(j, k) for j, k in d.get("joints", [])],
            blocks=list(d.get("blocks", [])),
            failure_height_fraction=r.get("failure_height_fraction"),
            failure_kind=r.get("kind"),
            start=r.get("start"),
            extent_fraction=r.get("extent_fraction"),
        )

    def __str__(self) -> str:
        return self.kind


@dataclass(frozen=True)
class TiltResult:
    """The tilting-table test of one layout (`loading::tilt::TiltResult`).

    The collapse bracket `[last_stable_deg, first_unstable_deg]` (degrees) holds the
    collapse angle to the resolution; `first_unstable_deg` is None if the wall stood to
    `max_angle_deg`. `bracket_reliable` is False when the first unstable trial ran out of
    its step budget (`collapse_reason == "step_budget"`, at stiff joints): the collapse angle
    is then a lower bound, not a bracket. Histories, one entry per increment tried (stable ones in increasing
    tilt, then the unstable trials): `alpha_deg` (n,), `stable` (n,) bool, `increment_steps`
    (n,), `unbalanced_ratio` (n,), and `displacement_m` (n, m): the out-of-plane (y)
    displacement of each monitor point since the settled state at 0°, m, in the order of
    `monitors` (by default `top_left`, `top_centre`, `top_right`).
    """

    last_stable_deg: float
    first_unstable_deg: Optional[float]
    collapse_angle_deg: float
    collapse_reason: Optional[str]
    bracket_reliable: bool
    mechanism: Mechanism
    monitors: List[str]
    alpha_deg: np.ndarray
    stable: np.ndarray
    displacement_m: np.ndarray
    increment_steps: np.ndarray
    unbalanced_ratio: np.ndarray
    steps: int
    iterations: int
    dt_s: float
    wall_time_s: float
    _raw: Dict[str, Any] = field(repr=False, compare=False)

    @property
    def collapsed(self) -> bool:
        """Whether the wall collapsed below `max_angle_deg`."""
        return self.first_unstable_deg is not None

    def to_dict(self) -> Dict[str, Any]:
        """The library's result as a dict (the `drystone tilt --json` object)."""
        return dict(self._raw)


@dataclass(frozen=True)
class LateralResult:
    """The static lateral load on one layout (`loading::lateral::LateralResult`).

    `equilibrium`: the wall carried the load (else `collapse_reason`). `displacement_m`
    (m,): the y displacement of each monitor point from the gravity-only state, m, in the
    order of `monitors`; `max_displacement_m`, `drift` (max displacement / height; these
    and `height_m`, `width_m` None by limit analysis, which has no displacements);
    `resultant_n` (3,): the resultant of the pressure, N, table frame.
    """

    equilibrium: bool
    collapse_reason: Optional[str]
    monitors: List[str]
    displacement_m: np.ndarray
    max_displacement_m: Optional[float]
    drift: Optional[float]
    height_m: Optional[float]
    width_m: Optional[float]
    resultant_n: np.ndarray
    weight_n: float
    steps: int
    dt_s: float
    wall_time_s: float
    _raw: Dict[str, Any] = field(repr=False, compare=False)

    def to_dict(self) -> Dict[str, Any]:
        """The library's result as a dict (the `drystone lateral --json` object)."""
        return dict(self._raw)


@dataclass(frozen=True)
class PushoverResult:
    """The DEM pushover of the lateral pressure (`loading::lateral_pushover::LateralPushover`).

    The pressure of `lateral` scaled by a load multiplier λ, doubled from 1 then bisected:
    the collapse multiplier lies in `[lambda_stable, lambda_unstable]` (`lambda_unstable`
    None: the wall stood to the largest multiplier tried). Histories, one entry per
    increment or trial (the stable ones by λ, then the unstable ones): `load_multiplier`
    (n,), `stable` (n,) bool, and `displacement_m` (n, m): the y displacement of each
    monitor from the gravity-only state, m, in the order of `monitors`.
    """

    lambda_stable: float
    lambda_unstable: Optional[float]
    collapse_reason: Optional[str]
    mechanism: Optional[Mechanism]
    monitors: List[str]
    load_multiplier: np.ndarray
    stable: np.ndarray
    displacement_m: np.ndarray
    weight_n: float
    steps: int
    dt_s: float
    wall_time_s: float
    _raw: Dict[str, Any] = field(repr=False, compare=False)

    @property
    def collapsed(self) -> bool:
        """Whether the wall collapsed below the largest multiplier tried."""
        return self.lambda_unstable is not None

    def to_dict(self) -> Dict[str, Any]:
        """The library's result as a dict (the `drystone lateral --pushover --json` object,
        less the fields the command adds)."""
        return dict(self._raw)


def _layout_of(layout: Any) -> Layout:
    if isinstance(layout, Layout):
        return layout
    if isinstance(layout, (str, os.PathLike)):
        return Layout.from_file(os.fspath(layout))
    raise TypeError(f"expected a drystone.Layout or a layout file path, got {type(layout).__name__}")


def tilt(layout: Any, solver: Any = None, by_hand: Any = None, **params: Any) -> TiltResult:
    """Tilts `layout` (a `Layout` or a layout JSON path) to collapse on the tilting table.

    `solver`: None (the penalty DEM), a solver name (`penalty`, `implicit`, `accelerated`,
    `relaxation`, `nscd`, `limit`) or a dict of solver parameters (`SolverParams` keys, e.g.
    `{"kind": "penalty", "damping": 0.8}`; the penalty DEM's solve settings in its
    `penalty` dict: `{"penalty": {"tolerance": 1e-4, "max_steps": 400000, "predictor":
    True}}`). `params`: `TiltParams` keys, e.g. `step_deg=0.5`, `resolution_deg=0.125`,
    `max_angle_deg=80` (`tolerance`, `max_steps_per_increment` and `predictor` still work
    here, with a `DeprecationWarning`). `by_hand`: None, True or a
    dict of `HandTilt` keys (`increment_deg` 5, `rate_deg_per_s` 2.5, `ramp_s` 0.1,
    `hold_s` 1, `axis_depth_m` 0.34): the table rolled by hand, each increment run as a
    motion that kicks the wall at its stop (`drystone tilt --by-hand`; with
    `solver="nscd"` only). With `solver="limit"`, limit analysis: `last_stable_deg`,
    `first_unstable_deg` and `collapse_angle_deg` all α_max = atan λ, the mechanism of the
    dual, no histories (`to_dict()["limit_analysis"]`: the whole analysis). Every solver
    `supports("tilt", solver)` admits runs here. The GIL is released while it runs. Raises
    `InputError` for an unknown key or a value out of range or a solver that does not run
    the test, `SolverError` if the layout does not stand at 0° or the engine blows up.
    """
    hand = None if by_hand is None or by_hand is False else ({} if by_hand is True else dict(by_hand))
    raw = _native._tilt(_layout_of(layout), solver, params or None, hand)
    r = raw["result"]
    return TiltResult(
        last_stable_deg=r["last_stable_deg"],
        first_unstable_deg=r["first_unstable_deg"],
        collapse_angle_deg=raw["collapse_angle_deg"],
        collapse_reason=r["collapse_reason"],
        bracket_reliable=r["bracket_reliable"],
        mechanism=Mechanism._from(r["mechanism"]),
        monitors=list(r["monitors"]),
        alpha_deg=raw["alpha_deg"],
        stable=raw["stable"],
        displacement_m=raw["displacement_m"],
        increment_steps=raw["increment_steps"],
        unbalanced_ratio=raw["unbalanced_ratio"],
        steps=r["steps"],
        iterations=r["iterations"],
        dt_s=r["dt_s"],
        wall_time_s=r["wall_time_s"],
        _raw=r,
    )


def lateral(layout: Any, solver: Any = None, **params: Any) -> LateralResult:
    """Loads `layout` with a static out-of-plane pressure (linear from `pressure_base_pa`
    at the base to `pressure_top_pa` at the top, Pa; `LateralParams` keys) and solves for
    its equilibrium. `solver` as in `tilt`. A wall that does not carry the load is a result
    (`equilibrium` False), not an error. With `solver="limit"`, limit analysis of rigid
    blocks: `equilibrium` whether the collapse load multiplier λ reaches 1, no displacements
    (`max_displacement_m`, `drift`, `height_m` and `width_m` None, no monitors;
    `to_dict()["limit_analysis"]`: the whole analysis).
    """
    raw = _native._lateral(_layout_of(layout), solver, params or None)
    r = raw["result"]
    return LateralResult(
        equilibrium=r["equilibrium"],
        collapse_reason=r["collapse_reason"],
        monitors=list(r["monitors"]),
        displacement_m=raw["displacement_m"],
        max_displacement_m=r["max_displacement_m"],
        drift=r["drift"],
        height_m=r["height_m"],
        width_m=r["width_m"],
        resultant_n=raw["resultant_n"],
        weight_n=r["weight_n"],
        steps=r["steps"],
        dt_s=r["dt_s"],
        wall_time_s=r["wall_time_s"],
        _raw=r,
    )


def in_plane(layout: Any, solver: Any = None, **params: Any) -> Dict[str, Any]:
    """The in-plane shear-compression test of `layout`: a loading beam on the top course
    under the vertical stress `sigma0_mpa` (MPa), its horizontal displacement imposed at the
    shear span `shear_span_m` (m) to `drift_pct` (%), monotonic or `history="cyclic"`
    (`InPlaneParams` keys: `amplitudes_pct`, `cycles`, `beam_rotation`, `step_mm`,
    `quarter_increments`, `measuring_height_m`). By the penalty DEM (the default): a dict
    with the arrays `top_mm` (the displacement at the measuring point, the actuator's height
    by default), `drift_pct` (that displacement over the point's height), `force_kn` (the
    curve) and `result` (per direction the peak force kN, the drift at the peak %, the
    ultimate drift %, the initial stiffness kN/mm and the envelope's robust readings; the
    mechanism, the wall's vertical modulus MPa, the largest block excursion mm). `solver="limit"`: `result` holds the peak force by limit analysis and
    its mechanism. Raises `InputError` for a bad parameter or layout, `SolverError` for a
    solver that does not run it (nscd) or a run that fails.
    """
    return dict(_native._in_plane(_layout_of(layout), solver, params or None))


def compression(layout: Any, solver: Any = None, **params: Any) -> Dict[str, Any]:
    """The vertical compression test of `layout`: the loading beam's vertical force cycled
    between the stress `sigma0_mpa` (MPa, on the wall's top, the beam's weight part of it)
    and `unload_to_mpa` (default: the beam's own weight), `cycles` times (default 3), then
    optionally raised to `raise_to_mpa` (`CompressionParams` keys: `points_per_branch`,
    `beam_rotation`, `shear_span_m`). By the penalty DEM (the only method that runs it): a
    dict with the arrays `stress_mpa`, `shortening_mm` and `force_kn` (the force-shortening
    curve) and `result` (`wall_vertical_modulus_mpa`, the secant of the first loading
    branch, the database's Epc; `loading_secants_mpa` and `residual_settlements_mm` per
    cycle; `strength_bracket_mpa` of the raise). Raises `InputError` for a bad parameter or
    layout, `SolverError` for a solver that does not run it (nscd, limit) or a run that fails.
    """
    return dict(_native._compression(_layout_of(layout), solver, params or None))


def supports(protocol: str, solver: str) -> Tuple[bool, str]:
    """Whether the solver kind `solver` (`penalty`, `implicit`, `accelerated`,
    `relaxation`, `nscd`, `limit`) runs `protocol` (`tilt`, `tilt_by_hand`, `lateral`,
    `pushover`, `shake`, `in_plane`, `compression`): the library's one compatibility table, which studies,
    the command line and these functions all ask (`tilt`, `lateral`, `pushover` and
    `in_plane` run every solver it admits; `tilt_by_hand` is `tilt` with `by_hand`). Returns
    `(runs, reason)`, the reason a refusal gives (empty when it runs). Raises `InputError`
    for an unknown name.
    """
    return _native._supports(protocol, solver)


def pushover(layout: Any, solver: Any = None, **params: Any) -> PushoverResult:
    """Pushes the static out-of-plane pressure of `lateral` (`LateralParams` keys, e.g.
    `pressure_base_pa`, `pressure_top_pa`, `pushover_resolution`: the final bracket's
    width relative to λ, 0.02 with a penalty method and 0.01 with `"nscd"` when not given) to collapse. `solver` as in `lateral`: a penalty method (the
    default: the joints keep their Kn, Ks, friction, cohesion and tensile strength; the
    histories hold every increment), `"nscd"` (the rigid pushover: λ bisected to 1 % by
    non-smooth contact dynamics of rigid blocks, or to `pushover_resolution`) or `"limit"` (limit analysis: λ stable and
    unstable both its load multiplier); the last two have no histories. Raises
    `InputError` for a bad key or value, `SolverError` if the layout does not stand.
    """
    raw = _native._pushover(_layout_of(layout), solver, params or None)
    r = raw["result"]
    return PushoverResult(
        lambda_stable=r["lambda_stable"],
        lambda_unstable=r["lambda_unstable"],
        collapse_reason=r["collapse_reason"],
        mechanism=Mechanism._from(r["mechanism"]) if r.get("mechanism") else None,
        monitors=list(r["monitors"]),
        load_multiplier=raw["load_multiplier"],
        stable=raw["stable"],
        displacement_m=raw["displacement_m"],
        weight_n=r["weight_n"],
        steps=r["steps"],
        dt_s=r["dt_s"],
        wall_time_s=r["wall_time_s"],
        _raw=r,
    )


_TEXT_SUMMARY_COLUMNS = {"group", "sweep", "displacement_measure"}
_COUNT_SUMMARY_COLUMNS = {"point", "realizations", "failed", "stood"}


def _polars():
    try:
        import polars
    except ImportError as e:  # pragma: no cover - polars is a dependency
        raise ImportError("drystone.run_study returns polars DataFrames: pip install polars") from e
    return polars


def _frame(raw: Dict[str, Any]):
    pl = _polars()
    kinds = {"u64": pl.UInt64, "f64": pl.Float64, "str": pl.Utf8, "list[f64]": pl.List(pl.Float64)}
    schema = {n: kinds[t] for n, t in zip(raw["names"], raw["dtypes"])}
    return pl.DataFrame({n: raw["columns"][n] for n in raw["names"]}, schema=schema)


def _read_summary(path: Path):
    """`summary.csv` with its numbers as Float64 (NaN where a statistic has no value)."""
    pl = _polars()
    header = path.read_text(encoding="utf-8").split("\n", 1)[0].split(",")
    schema = {}
    for c in header:
        if c in _TEXT_SUMMARY_COLUMNS:
            schema[c] = pl.Utf8
        elif c in _COUNT_SUMMARY_COLUMNS or c.endswith("_n"):
            schema[c] = pl.UInt64
        else:
            schema[c] = pl.Float64
    return pl.read_csv(path, schema=schema)


@dataclass
class StudyResult:
    """A study's run: `realizations` (a polars DataFrame with the columns of
    `realizations.csv`, one row per realization in item order; the per-increment series
    `tilt_deg` and `disp_top_*_cm` as lists of floats), `summary` (the statistics of
    `summary.csv` per group and sweep point; None for a shard), `comparison` (the
    measured-against-simulated text `drystone run` prints; None for a shard), `out` (the
    run directory), `resumed` (rows taken from the journal of an earlier run).
    """

    name: str
    seed: int
    realizations_per_group: int
    out: Path
    realizations: Any
    summary: Any
    comparison: Optional[str]
    resumed: int

    def to_pandas(self):
        """The realizations as a pandas DataFrame (needs pandas and pyarrow)."""
        try:
            import pandas  # noqa: F401
        except ImportError as e:
            raise ImportError("StudyResult.to_pandas needs pandas: pip install pandas pyarrow") from e
        return self.realizations.to_pandas()

    def means(self, column: str = "collapse_angle_deg") -> Dict[str, float]:
        """The mean of a statistic of `summary` per group at the first sweep point, e.g.
        `means()` gives the mean collapse angle (degrees) of each group."""
        if self.summary is None:
            raise DrystoneError("a shard has no summary: merge the shards first")
        rows = self.summary.filter(self.summary["point"] == 0)
        return dict(zip(rows["group"].to_list(), rows[f"{column}_mean"].to_list()))


def _progress_callback(progress: Any) -> Optional[Callable[[int, int, Dict[str, Any]], None]]:
    if progress is None or progress is False:
        return None
    if progress is True:
        try:
            from tqdm.auto import tqdm
        except ImportError as e:
            raise ImportError("progress=True uses tqdm: pip install tqdm, or pass a callable") from e
        bar: Dict[str, Any] = {}

        def report(done: int, total: int, row: Dict[str, Any]) -> None:
            if "bar" not in bar:
                bar["bar"] = tqdm(total=total, unit="realization")
            bar["bar"].update(1)
            if done >= total:
                bar["bar"].close()

        return report
    if hasattr(progress, "update") and not callable(progress):
        return lambda done, total, row: progress.update(1)
    if hasattr(progress, "update") and hasattr(progress, "total"):
        return lambda done, total, row: progress.update(1)
    if callable(progress):
        return progress
    raise TypeError("progress: expected None, True (tqdm), a tqdm bar or a callable(done, total, row)")


def run_study(
    study: Union[PathLike, Study],
    realizations: Optional[int] = None,
    out: Optional[PathLike] = None,
    threads: Optional[int] = None,
    progress: Any = None,
    shard: Optional[str] = None,
    resume: bool = False,
    force: bool = False,
) -> StudyResult:
    """Runs a study file as `drystone run STUDY [--realizations N] [--out DIR]` does: the
    same rows bit for bit, the same run directory (`out`, default `out/<name>`: journal,
    `realizations.csv`/`.parquet`, `summary.csv`, `report.md`, plots, manifest).

    `threads`: worker threads (default: one per core; the results do not depend on it).
    `progress`: True for a tqdm bar, a tqdm bar, or a callable `progress(done, total, row)`
    called after each realization (`row`: index, group, realization, status,
    collapse_angle_deg). `shard`: `"K/N"`. `resume`: continue the journal of an interrupted
    run; `force`: replace a journal that cannot be continued.

    The GIL is released while it runs. Ctrl-C (or an exception of `progress`) stops it
    after the realizations running finish: no new one starts, every finished one is in the
    journal, and `resume=True` continues from there.
    """
    if isinstance(study, Study):
        path = study.path
        if realizations is None:
            realizations = study.realizations
    else:
        path = os.fspath(study)
    raw = _native._run_study(
        os.fspath(path),
        realizations,
        None if out is None else os.fspath(out),
        threads,
        shard,
        resume,
        force,
        _progress_callback(progress),
    )
    out_dir = Path(raw["out"])
    summary = _read_summary(out_dir / "summary.csv") if raw["complete"] else None
    return StudyResult(
        name=raw["name"],
        seed=raw["seed"],
        realizations_per_group=raw["realizations"],
        out=out_dir,
        realizations=_frame(raw),
        summary=summary,
        comparison=raw["text"],
        resumed=raw["resumed"],
    )


@dataclass(frozen=True)
class Discrepancy:
    """The verdict of a discrepancy analysis (`drystone discrepancy --json`): `verdict`
    (`explained`, `no_effect` or `unexplained`), `cause` (the named effect, e.g.
    `kn_scale`, or None), `parameters` (the cause's fitted parameters, in their units),
    `tie` (candidates the data cannot separate from the cause), `candidates` (every
    candidate, best first, with its scores), `weights` (the pseudo-BMA+ weight of the
    baseline and of every candidate, heaviest first), `shared` (the models that share 90 %
    of that weight). `to_dict()` gives the whole object, with the stacking weights, the
    weights' intervals and the identifiability of the leading models.
    """

    verdict: str
    cause: Optional[str]
    parameters: Dict[str, float]
    tie: List[str]
    candidates: List[Dict[str, Any]]
    weights: Dict[str, float]
    shared: List[str]
    _raw: Dict[str, Any] = field(repr=False, compare=False)

    def to_dict(self) -> Dict[str, Any]:
        """The whole verdict object, as `drystone discrepancy --json` prints it."""
        return dict(self._raw)


def discrepancy(
    study: Union[PathLike, Study],
    realizations: Optional[int] = None,
    out: Optional[PathLike] = None,
    threads: Optional[int] = None,
    **settings: Any,
) -> Discrepancy:
    """Compares a study with its measured data and names the physical effect that explains
    the misfit, as `drystone discrepancy` does. `settings`: keys of the study's
    `[discrepancy]` table put over it (e.g. `effects=["kn_scale"]`, `null_replicates=50`,
    `confirm=False`); `realizations` as `--realizations`. With `out`, the report (and the
    extended study when a cause is named) is written there. The GIL is released while it
    runs (minutes at the defaults).
    """
    path = study.path if isinstance(study, Study) else os.fspath(study)
    raw = _native._discrepancy(
        os.fspath(path), settings or None, realizations, None if out is None else os.fspath(out), threads
    )
    cause = raw.get("cause")
    params = {}
    if cause:
        params = {k: v for k, v in (cause.get("parameters") or {}).items()} if isinstance(cause.get("parameters"), dict) else {}
    return Discrepancy(
        verdict=raw["verdict"],
        cause=cause["name"] if cause else None,
        parameters=params,
        tie=list(raw.get("tie") or []),
        candidates=list(raw.get("candidates") or []),
        weights={m["name"]: m["pseudo_bma"] for m in (raw.get("weights") or {}).get("models", [])},
        shared=list((raw.get("weights") or {}).get("shared") or []),
        _raw=raw,
    )


@dataclass(frozen=True)
class Effect:
    """A named extension of the model (`effects::EffectDef`): `name`, `description`,
    `source` (its literature), `parameters` (each a dict: `name`, `unit`, `min`, `max`,
    `scale` linear or log, `neutral`: the value that leaves the model unchanged), `stages`
    (where it enters the model: `layout`, `joint_law`, `restraints`), `steps` (its
    primitives as the effect file writes them)."""

    name: str
    description: str
    source: str
    parameters: List[Dict[str, Any]]
    stages: List[str]
    steps: List[Any]


def effects(study: Optional[Union[PathLike, Study]] = None) -> List[Effect]:
    """The effect library: the built-ins, then a study's effect files when `study` is
    given, each with its parameters."""
    path = None
    if study is not None:
        path = os.fspath(study.path if isinstance(study, Study) else study)
    return [
        Effect(
            name=d["name"],
            description=d.get("description", ""),
            source=d.get("source", ""),
            parameters=list(d.get("parameters", [])),
            stages=list(d.get("stages", [])),
            steps=list(d.get("steps", [])),
        )
        for d in _native._effects(path)
    ]
