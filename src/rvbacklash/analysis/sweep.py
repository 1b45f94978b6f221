"""Design sweeps: one Monte-Carlo run per point of a grid or a sampled design of points, on an
executor (in process, a local cluster, a Dask cluster), with results written point by point and
a resume that skips the finished points (docs/sweeps.md).

    plan = plan_sweep("my-sweep.toml")        # validates the sweep and every point's design
    result = run_sweep(plan, out="my-sweep", scheduler="local")
    result.to_frame()                          # one row per point

Determinism: point i runs ``simulate(..., seed=spec.seed, stream=(i,))``, so block b of it draws
from ``SeedSequence(seed, spawn_key=(i, b))``: its numbers depend on the sweep's seed and the
point's index only, never on the scheduler, the worker, the order or a resume.

A row holds the point's index and parameter values, then every output's figures named
``<output>_<statistic>`` (``backlash_mean``, ``backlash_q99865``, ``backlash_q99865_ci95_low``,
``backlash_yield``, ...), the joint yield when there are several specs, and the model's own
figures (``preload_fraction``). A quantile's tag is the digits of its probability after "0.",
at least two: q00135, q50, q99865.
"""

from __future__ import annotations

import contextlib
import csv
import hashlib
import io
import json
import math
import os
import shutil
import stat
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Iterable, Mapping

from rvbacklash._version import SCHEMA_VERSION
from rvbacklash.analysis.executor import Executor, check_scheduler, check_workers, cores, dask_available, executor
from rvbacklash.analysis.simulation import LIFE_OUTPUTS, MODELS, _elastic_life, check_run_parameters, simulate
from rvbacklash.atomic import atomic_write
from rvbacklash.design.schema import Design
from rvbacklash.design.sweep_spec import (Scalar, SweepSource, SweepSpec, load_sweep_source, point_designs,
                                          sweep_points)
from rvbacklash.errors import InputError
from rvbacklash.interrupt import stop_requested
from rvbacklash.paths import is_dir, path_stat
from rvbacklash.problem import prepare
from rvbacklash.results import Result, plain

INLINE_MAX_POINTS = 4  # default scheduler: inline up to this many points to run, a local cluster above
RESULTS_FLUSH_S = 1.0  # the combined results files are rewritten at most this often while running
STATE_FILE = "sweep.json"
LOCK_FILE = ".lock"
POINTS_DIR = "points"
RESULTS_PARQUET = "results.parquet"
RESULTS_CSV = "results.csv"
OWNED = (STATE_FILE, RESULTS_PARQUET, RESULTS_CSV, "sweep.toml", "plot.svg", "sweep.html")


# --- the plan ----------------------------------------------------------------------------------

@dataclass(frozen=True)
class OutputInfo:
    name: str
    unit: str
    upper_limit: bool


@dataclass(frozen=True, eq=False)
class SweepPlan:
    """A validated sweep, ready to run: its points, every point's Design, the model's outputs,
    the effective specs and the fingerprint that identifies its results."""

    spec: SweepSpec
    origin: str
    text: str | None
    base_origin: str
    base_name: str
    points: tuple[tuple[Scalar, ...], ...]
    designs: tuple[Design, ...]
    outputs: tuple[OutputInfo, ...]
    limits: dict[str, float]  # output name -> spec limit (its side is the output's)
    fingerprint: str

    @property
    def parameters(self) -> tuple[str, ...]:
        return self.spec.paths

    @property
    def labels(self) -> tuple[str, ...]:
        return tuple(p.name for p in self.spec.parameters)

    def __len__(self) -> int:
        return len(self.points)


def wants_life(spec: SweepSpec) -> bool:
    """Whether a sweep's points carry the elastic model's life outputs (``life``, or a spec on one)."""
    return bool(spec.life or any(k in LIFE_OUTPUTS for k in spec.specs))


def _fingerprint(spec: SweepSpec, base_data: dict) -> str:
    """sha256 of what decides the rows: the sweep without its name and description, the base
    design's data (not its path or comments) and the package version."""
    from rvbacklash._version import __version__

    # life false is left out: the fingerprints of sweeps written before the field existed stay theirs
    left_out = {"name", "description"} | ({"life"} if not spec.life else set())
    doc = {"sweep": spec.model_dump(mode="json", exclude=left_out),
           "design": base_data,
           "version": __version__}
    return hashlib.sha256(json.dumps(doc, sort_keys=True, default=str).encode("utf-8")).hexdigest()


def plan_sweep(sweep: str | Path | SweepSpec) -> SweepPlan:
    """Validate a sweep (a SWEEP.toml path, a built-in example sweep, or a SweepSpec whose design
    path is relative to the current directory) and every point's design, before anything runs."""
    src: SweepSource = load_sweep_source(sweep)
    spec = src.spec
    if spec.model not in MODELS:
        raise InputError("model", spec.model, f"allowed: {', '.join(MODELS)}")
    if spec.method == "exact":
        raise InputError("method", spec.method, "allowed: default, box-muller, sobol (a sweep samples every point)")
    check_run_parameters(spec.samples, spec.seed, spec.method, spec.spec_arcmin, tuple(spec.quantiles), None)
    points = sweep_points(spec)
    designs = point_designs(src.base_data, spec, points)
    problems = [prepare(d) for d in designs]  # zones from grades etc.: every point must prepare
    life = wants_life(spec)
    if life and spec.model != "elastic":
        name = "life" if spec.life else "specs." + next(k for k in spec.specs if k in LIFE_OUTPUTS)
        raise InputError(name, spec.life if spec.life else spec.specs[name.removeprefix("specs.")],
                         "allowed with model 'elastic' only (the life outputs come from its load solution)")
    source = (_elastic_life if life else MODELS[spec.model])(problems[0], spec.method, spec.seed, (0,))
    outputs = tuple(OutputInfo(o.name, o.unit, o.upper_limit) for o in source.outputs)
    names = [o.name for o in outputs]
    for name, value in spec.specs.items():
        if name not in names:
            raise InputError(f"specs.{name}", value, f"not an output of the {spec.model} model; allowed outputs: "
                                                     f"{', '.join(names)}")
    if spec.spec_arcmin is not None and names[0] in spec.specs:
        raise InputError("spec_arcmin", spec.spec_arcmin, f"is the limit of {names[0]}, which specs.{names[0]} sets "
                                                          f"too; allowed: one of them")
    limits = dict(spec.specs)
    if spec.spec_arcmin is not None:
        limits = {names[0]: spec.spec_arcmin, **limits}
    return SweepPlan(spec, src.origin, src.text, src.base_origin, designs[0].name, tuple(points), tuple(designs),
                     outputs, limits, _fingerprint(spec, src.base_data))


# --- one point ---------------------------------------------------------------------------------

@dataclass(frozen=True)
class PointTask:
    """Everything a worker needs to run one point (picklable, small)."""

    index: int
    values: tuple[Scalar, ...]
    paths: tuple[str, ...]
    design: Design
    model: str
    method: str
    samples: int
    seed: int
    spec_arcmin: float | None
    specs: dict[str, float]
    quantiles: tuple[float, ...]
    threads: int | None  # threads of the point's own simulation (None: all cores)
    life: bool = False  # the elastic model's life outputs (SweepSpec.life)


@dataclass(frozen=True)
class PointOutcome:
    row: dict
    partial: bool
    elapsed_s: float


def quantile_tag(p: float) -> str:
    """'q99865' for 0.99865, 'q50' for 0.5, 'q00135' for 0.00135: the digits after '0.', at least two."""
    digits = format(p, ".12f").rstrip("0").partition(".")[2]
    return "q" + digits.ljust(2, "0")


def result_figures(result) -> dict:
    """Every figure of a SimulationResult as flat columns (names in the module docstring)."""
    row: dict[str, Any] = {"samples": result.samples_done}
    for name, o in result.outputs.items():
        p = f"{name}_"
        row.update({p + "samples": o.samples, p + "mean": o.mean, p + "mean_ci95_low": o.mean_ci95_low,
                    p + "mean_ci95_high": o.mean_ci95_high, p + "sigma": o.sigma, p + "min": o.min, p + "max": o.max})
        for q in o.quantiles:
            t = p + quantile_tag(q.probability)
            row.update({t: q.value, t + "_ci95_low": q.ci95_low, t + "_ci95_high": q.ci95_high,
                        t + "_bounded": q.bounded})
        if o.spec_limit is not None:
            y = o.yield_
            row.update({p + "yield": y.fraction if y else None, p + "yield_ci95_low": y.ci95_low if y else None,
                        p + "yield_ci95_high": y.ci95_high if y else None, p + "ppm_out": o.ppm_out,
                        p + "cp": o.cp, p + "cpk": o.cpk})
        row[p + "negative_fraction"] = o.negative_fraction
    if result.joint_yield is not None:
        y = result.joint_yield
        row.update({"joint_yield": y.fraction, "joint_yield_ci95_low": y.ci95_low,
                    "joint_yield_ci95_high": y.ci95_high})
    if result.preload_fraction is not None:
        row["preload_fraction"] = result.preload_fraction
    row["linear_mean_arcmin"] = result.linear_reference.mean_arcmin
    row["linear_sigma_arcmin"] = result.linear_reference.sigma_arcmin
    if result.warnings:  # e.g. a lost motion read in friction's stick band at this point
        row["warnings"] = "; ".join(result.warnings)
    return plain(row)


def evaluate_point(task: PointTask) -> PointOutcome:
    """Run one point: prepare its design, simulate with the point's stream (index,), one row."""
    t0 = time.perf_counter()
    result = simulate(prepare(task.design), samples=task.samples, seed=task.seed, method=task.method,
                      spec_arcmin=task.spec_arcmin, specs=task.specs or None, quantiles=task.quantiles,
                      workers=task.threads, model=task.model, stream=(task.index,), life=task.life)
    row = {"point": task.index, **dict(zip(task.paths, task.values)), **result_figures(result)}
    return PointOutcome(row, result.partial, time.perf_counter() - t0)


def point_tasks(plan: SweepPlan, indices: Iterable[int], threads: int | None) -> list[PointTask]:
    s = plan.spec
    return [PointTask(i, plan.points[i], plan.parameters, plan.designs[i], s.model, s.method, s.samples, s.seed,
                      s.spec_arcmin, dict(s.specs), tuple(s.quantiles), threads, wants_life(s)) for i in indices]


# --- files -------------------------------------------------------------------------------------

def _atomic_write(path: Path, content: bytes) -> None:
    atomic_write("out", path, content)


def _column_types(rows: list[dict], columns: list[str]) -> dict[str, str]:
    """int / float / str / bool per column from its values (None ignored; int and float -> float)."""
    kinds: dict[str, str] = {}
    for c in columns:
        seen = {type(r.get(c)) for r in rows} - {type(None)}
        if seen == {bool}:
            kinds[c] = "bool"
        elif seen and seen <= {int}:
            kinds[c] = "int"
        elif seen and seen <= {int, float}:
            kinds[c] = "float"
        elif seen:
            kinds[c] = "str"
        else:
            kinds[c] = "float"
    return kinds


def columns_of(rows: list[dict]) -> list[str]:
    return list(dict.fromkeys(k for r in rows for k in r))


def render_parquet(rows: list[dict]) -> bytes:
    import pyarrow as pa
    import pyarrow.parquet as pq

    cols = columns_of(rows)
    kinds = _column_types(rows, cols)
    types = {"int": pa.int64(), "float": pa.float64(), "str": pa.string(), "bool": pa.bool_()}
    arrays = []
    for c in cols:
        values = [r.get(c) for r in rows]
        if kinds[c] == "float":
            values = [None if v is None else float(v) for v in values]
        arrays.append(pa.array(values, type=types[kinds[c]]))
    table = pa.table(arrays, names=cols)
    sink = pa.BufferOutputStream()
    pq.write_table(table, sink)
    return sink.getvalue().to_pybytes()


def render_rows_csv(rows: list[dict]) -> bytes:
    buf = io.StringIO()
    cols = columns_of(rows)
    w = csv.DictWriter(buf, fieldnames=cols, lineterminator="\n")
    w.writeheader()
    for r in rows:
        w.writerow({c: ("" if r.get(c) is None else repr(r[c]) if isinstance(r.get(c), float) else r[c])
                    for c in cols})
    return buf.getvalue().encode("utf-8")


class SweepStore:
    """The results directory of a sweep:

    - ``sweep.json``: fingerprint, the sweep, its state (running | partial | complete);
    - ``points/<index>.json``: one finished point (its row), written atomically when it finishes;
    - ``results.parquet``, ``results.csv``: every finished point, by index, rewritten as points
      finish (at most once a second) and at the end;
    - ``sweep.toml``: a copy of the sweep file.

    A directory holding the same sweep (same fingerprint) is resumed: its finished points are not
    run again. A different sweep, or a directory of other files, is refused unless ``force``;
    ``force`` removes this store's own files (never others) and starts over.
    """

    def __init__(self, root: Path, plan: SweepPlan, force: bool = False):
        self.root = root
        self.plan = plan
        self.points_dir = root / POINTS_DIR
        self.rows: dict[int, dict] = {}
        self._last_flush = 0.0
        self._dirty = False
        self._open(force)

    @staticmethod
    def check_out(out: Path) -> None:
        found = path_stat("out", out)
        if found is not None and not stat.S_ISDIR(found.st_mode):
            raise InputError("out", str(out), "is not a directory; allowed: a new or existing directory")
        parent = out.parent if str(out.parent) else Path(".")
        if found is None and not is_dir("out", parent):
            raise InputError("out", str(out), f"its parent directory {str(parent)!r} does not exist")

    def _open(self, force: bool) -> None:
        self.check_out(self.root)
        # a directory this store creates (or finds empty) is removed again if the sweep never finishes a point
        self.created = not self.root.exists() or not any(self.root.iterdir())
        state_path = self.root / STATE_FILE
        state = None
        if state_path.is_file():
            try:
                state = json.loads(state_path.read_text(encoding="utf-8"))
            except (OSError, ValueError):
                state = None
        if self.root.is_dir() and any(p.name != LOCK_FILE for p in self.root.iterdir()) and not force:
            if state is None:
                raise InputError("out", str(self.root), "exists and holds no sweep (no readable sweep.json); allowed: "
                                                        "a new or empty directory, a sweep's directory, or --force")
            if state.get("fingerprint") != self.plan.fingerprint:
                raise InputError("out", str(self.root), f"holds the results of a different sweep "
                                                        f"({state.get('name')!r}, fingerprint "
                                                        f"{str(state.get('fingerprint'))[:12]}, this one "
                                                        f"{self.plan.fingerprint[:12]}); allowed: a new directory, the "
                                                        f"same sweep to resume, or --force to start over")
        try:
            self.root.mkdir(exist_ok=True)
        except OSError as e:
            raise InputError("out", str(self.root), f"cannot create ({e.strerror or e})") from None
        if not os.access(self.root, os.W_OK):
            raise InputError("out", str(self.root), "is not writable")
        self._lock()
        try:
            if force:
                self._clear()
            self.points_dir.mkdir(exist_ok=True)
        except OSError as e:
            self.close()
            raise InputError("out", str(self.root), f"cannot write ({e.strerror or e})") from None
        self.rows = read_points(self.points_dir, self.plan)
        self.write_state("running")
        if self.plan.text is not None:
            _atomic_write(self.root / "sweep.toml", self.plan.text.encode("utf-8"))

    def _lock(self) -> None:
        """One sweep at a time per directory: an advisory lock on DIR/.lock while it runs."""
        try:
            import fcntl
        except ImportError:  # pragma: no cover - not POSIX
            return
        self._lock_file = open(self.root / LOCK_FILE, "a")
        try:
            fcntl.flock(self._lock_file.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            self._lock_file.close()
            self._lock_file = None
            raise InputError("out", str(self.root), "is in use by another running sweep; allowed: another "
                                                    "directory, or wait for it to finish") from None

    def close(self) -> None:
        if getattr(self, "_lock_file", None) is not None:
            self._lock_file.close()  # releases the lock
            self._lock_file = None

    def discard_if_unused(self) -> None:
        """Remove the directory again when this store created it and no point finished (e.g. the
        scheduler could not be reached): a sweep that never started leaves nothing behind."""
        if not self.created or self.rows or any(self.points_dir.glob("*.json")):
            return
        self.close()
        with contextlib.suppress(OSError):
            shutil.rmtree(self.root)

    def _clear(self) -> None:
        for name in OWNED:
            p = self.root / name
            if p.is_file() or p.is_symlink():
                p.unlink()
        if self.points_dir.is_dir():
            shutil.rmtree(self.points_dir)

    def write_state(self, status: str, **extra: Any) -> None:
        p = self.plan
        state = {"schema_version": SCHEMA_VERSION, "name": p.spec.name, "fingerprint": p.fingerprint, "status": status, "points_total": len(p),
                 "points_done": len(self.rows), "parameters": list(p.parameters), "labels": list(p.labels),
                 "outputs": [o.__dict__ for o in p.outputs], "limits": p.limits, "design": p.base_name,
                 "design_source": p.base_origin, "sweep_source": p.origin,
                 "spec": p.spec.model_dump(mode="json"), "version": _version(), **extra}
        _atomic_write(self.root / STATE_FILE, (json.dumps(plain(state), indent=2) + "\n").encode("utf-8"))

    def add(self, outcome: PointOutcome) -> None:
        i = outcome.row["point"]
        doc = {"row": outcome.row, "elapsed_s": outcome.elapsed_s}
        _atomic_write(self.points_dir / point_file(i), (json.dumps(doc) + "\n").encode("utf-8"))
        self.rows[i] = outcome.row
        self._dirty = True
        if time.monotonic() - self._last_flush >= RESULTS_FLUSH_S:
            self.flush()

    def flush(self) -> None:
        rows = [self.rows[i] for i in sorted(self.rows)]
        if rows:
            _atomic_write(self.root / RESULTS_PARQUET, render_parquet(rows))
            _atomic_write(self.root / RESULTS_CSV, render_rows_csv(rows))
        self._last_flush = time.monotonic()
        self._dirty = False


def _version() -> str:
    from rvbacklash._version import __version__

    return __version__


def point_file(i: int) -> str:
    return f"{i:06d}.json"


def read_points(points_dir: Path, plan: SweepPlan | None = None) -> dict[int, dict]:
    """The finished points of a results directory, by index. With a plan, a point whose index or
    parameter values do not match it is ignored (it is run again)."""
    rows: dict[int, dict] = {}
    if not points_dir.is_dir():
        return rows
    for f in sorted(points_dir.glob("*.json")):
        try:
            row = json.loads(f.read_text(encoding="utf-8"))["row"]
            i = int(row["point"])
        except (OSError, ValueError, KeyError, TypeError):
            continue
        if f.name != point_file(i):
            continue
        if plan is not None:
            if not 0 <= i < len(plan) or any(row.get(p) != v for p, v in zip(plan.parameters, plan.points[i])):
                continue
        rows[i] = row
    return rows


# --- the result --------------------------------------------------------------------------------

@dataclass(frozen=True, repr=False)
class SweepResult(Result):
    """The rows of a sweep (one per finished point, by index) and what they came from.

    ``partial``: some points did not run (Ctrl-C); run the sweep again with the same ``out`` to
    finish it. ``skipped``: points found finished in ``out`` and not run again."""

    name: str
    description: str
    design_name: str
    model: str
    method: str
    samples: int  # per point
    seed: int
    sampling: str
    parameters: tuple[str, ...]  # dotted paths, the row's columns
    labels: tuple[str, ...]  # short names of the parameters for figures
    outputs: tuple[str, ...]
    output_units: dict[str, str]
    output_upper: dict[str, bool]
    limits: dict[str, float]
    fingerprint: str
    points_total: int
    table: tuple[dict, ...] = field(metadata={"key": "rows"})
    partial: bool
    skipped: int
    scheduler: str
    workers: int | None
    elapsed_s: float
    out: str | None

    _frame_index = "point"

    @property
    def points_done(self) -> int:
        return len(self.table)

    def rows(self) -> list[dict]:
        return [dict(r) for r in self.table]

    def column(self, name: str) -> list:
        return [r.get(name) for r in self.table]

    @property
    def columns(self) -> list[str]:
        return columns_of(list(self.table))

    def figure_columns(self) -> list[str]:
        """The columns that are figures of the points (not the index or the parameters)."""
        return [c for c in self.columns if c not in ("point", "warnings") and c not in self.parameters]

    def default_figure(self) -> str:
        """What a picture shows unless told: the joint yield, else the primary output's yield,
        else its 99.865 % quantile."""
        cols = self.columns
        primary = self.outputs[0] if self.outputs else "backlash"
        for c in ("joint_yield", f"{primary}_yield", f"{primary}_q99865", f"{primary}_mean"):
            if c in cols:
                return c
        return self.figure_columns()[0] if self.figure_columns() else "point"

    def maximise(self, figure: str) -> bool:
        """Whether a larger value of ``figure`` is better: yields and capabilities are; the
        statistics of an output with an upper spec (lost motion) are not, of a lower one (rigidity) are."""
        base = figure.removesuffix("_ci95_low").removesuffix("_ci95_high")
        if base.endswith(("yield", "_cp", "_cpk")):
            return True
        for o in sorted(self.outputs, key=len, reverse=True):
            if base.startswith(o + "_"):
                return not self.output_upper.get(o, True)
        return False

    def best(self, figure: str | None = None) -> dict | None:
        """The row with the best value of ``figure`` (default: ``default_figure()``); ties: lowest index."""
        figure = figure or self.default_figure()
        rows = [r for r in self.table if isinstance(r.get(figure), (int, float)) and not isinstance(r.get(figure), bool)
                and math.isfinite(r[figure])]
        if not rows:
            return None
        sign = -1.0 if self.maximise(figure) else 1.0
        return min(rows, key=lambda r: (sign * r[figure], r["point"]))

    def summary(self) -> list[str]:
        head = (f"sweep {self.name}: {self.design_name}, {self.model} model, {self.points_done} of {self.points_total} "
                f"points, {self.samples:,} samples each, seed {self.seed}" + ("  [PARTIAL]" if self.partial else ""))
        lines = [head]
        fig = self.default_figure()
        b = self.best(fig)
        if b is not None:
            where = ", ".join(f"{lab} = {b.get(p)!r}" for lab, p in zip(self.labels, self.parameters))
            lines.append(f"best {fig} = {b[fig]:.6g} at point {b['point']} ({where})")
        return lines


def sweep_result(plan_or_state: SweepPlan | dict, rows: Mapping[int, dict], *, partial: bool, skipped: int,
                 scheduler: str, workers: int | None, elapsed_s: float, out: str | None) -> SweepResult:
    if isinstance(plan_or_state, SweepPlan):
        p = plan_or_state
        s = p.spec
        meta = dict(name=s.name, description=s.description, design_name=p.base_name, model=s.model, method=s.method,
                    samples=s.samples, seed=s.seed, sampling=s.sampling, parameters=p.parameters, labels=p.labels,
                    outputs=tuple(o.name for o in p.outputs), output_units={o.name: o.unit for o in p.outputs},
                    output_upper={o.name: o.upper_limit for o in p.outputs}, limits=dict(p.limits),
                    fingerprint=p.fingerprint, points_total=len(p))
    else:
        st = plan_or_state
        s = st["spec"]
        meta = dict(name=st["name"], description=s.get("description", ""), design_name=st["design"],
                    model=s["model"], method=s["method"], samples=s["samples"], seed=s["seed"],
                    sampling=s["sampling"], parameters=tuple(st["parameters"]), labels=tuple(st["labels"]),
                    outputs=tuple(o["name"] for o in st["outputs"]),
                    output_units={o["name"]: o["unit"] for o in st["outputs"]},
                    output_upper={o["name"]: o["upper_limit"] for o in st["outputs"]}, limits=dict(st["limits"]),
                    fingerprint=st["fingerprint"], points_total=st["points_total"])
    table = tuple(rows[i] for i in sorted(rows))
    return SweepResult(**meta, table=table, partial=partial, skipped=skipped, scheduler=scheduler, workers=workers,
                       elapsed_s=elapsed_s, out=out)


def load_sweep(out: str | Path) -> SweepResult:
    """The results of a sweep directory (finished points only; ``partial`` unless complete)."""
    root = Path(out)
    try:
        state = json.loads((root / STATE_FILE).read_text(encoding="utf-8"))
        state["spec"], state["parameters"]  # noqa: B018 - the keys a result needs
    except (OSError, ValueError, KeyError, TypeError):
        raise InputError("out", str(out), "holds no sweep results (no readable sweep.json); allowed: the --out "
                                          "directory of a sweep") from None
    rows = read_points(root / POINTS_DIR)
    rows = {i: r for i, r in rows.items() if i < state["points_total"]}
    return sweep_result(state, rows, partial=len(rows) < state["points_total"], skipped=0,
                        scheduler=state.get("scheduler", ""), workers=state.get("workers"),
                        elapsed_s=float(state.get("elapsed_s", 0.0)), out=str(root))


# --- running -----------------------------------------------------------------------------------

def default_scheduler(points_to_run: int) -> str:
    """local when more than INLINE_MAX_POINTS points are to run, the machine has more than one
    core and dask is installed; inline otherwise."""
    return "local" if points_to_run > INLINE_MAX_POINTS and cores() > 1 and dask_available() else "inline"


def run_sweep(plan: SweepPlan, *, out: str | Path | None = None, scheduler: str | Executor | None = None,
              workers: int | None = None, force: bool = False,
              progress: Callable[[int, int], None] | None = None,
              stop: threading.Event | None = None) -> SweepResult:
    """Run the points of ``plan`` not yet finished in ``out`` and return every finished row.

    ``scheduler``: "inline", "local", an address (tcp://host:8786), an open Executor, or None
    for the default (``default_scheduler``). ``workers``: local cluster processes; inline, the
    threads of each point's simulation (None: all cores). ``out``: the results directory
    (``SweepStore``); None keeps the rows in memory only. ``progress(done, total)``: points
    finished (including those found in ``out``) of all the sweep's points. ``stop``: set it to
    stop submitting points; by default Ctrl-C sets it. Interrupted runs return ``partial=True``."""
    t0 = time.perf_counter()
    check_workers(workers)
    if scheduler is not None and not isinstance(scheduler, Executor):
        check_scheduler(scheduler)
        if scheduler != "inline" and scheduler != "local" and workers is not None:
            raise InputError("workers", workers, f"allowed only with scheduler inline or local; the cluster at "
                                                 f"{scheduler} has its own workers")
    store = None
    if out is not None:
        if not isinstance(out, (str, Path)) or not str(out):
            raise InputError("out", out, "allowed: a directory path")
        _need_pyarrow()
        store = SweepStore(Path(out), plan, force)
    try:
        return _run(plan, store, scheduler, workers, progress, stop, t0, out)
    except BaseException:  # a second Ctrl-C, or a failed point: what finished stays on disk, in the files too
        if store is not None:
            store.discard_if_unused()
            with contextlib.suppress(Exception):
                store.flush()
                store.write_state("partial", interrupted=True)
        raise
    finally:
        if store is not None:
            store.close()


def _run(plan: SweepPlan, store: SweepStore | None, scheduler, workers, progress, stop, t0: float,
         out) -> SweepResult:
    rows: dict[int, dict] = dict(store.rows) if store else {}
    skipped = len(rows)
    todo = [i for i in range(len(plan)) if i not in rows]
    if isinstance(scheduler, Executor):
        ex_name = scheduler.scheduler
    else:
        ex_name = default_scheduler(len(todo)) if scheduler is None else scheduler
    inline = ex_name == "inline"
    if progress is not None:
        progress(len(rows), len(plan))
    interrupted = False
    with stop_requested() if stop is None else _given(stop) as ev:
        if todo:
            ctx = _given(scheduler) if isinstance(scheduler, Executor) else \
                executor(ex_name, None if inline else workers)
            with ctx as ex:
                tasks = point_tasks(plan, todo, workers if ex.scheduler == "inline" else 1)
                for k, outcome in ex.map_unordered(evaluate_point, tasks, stop=ev):
                    # Ctrl-C inside the point's own run (inline): it stops after its blocks under way.
                    # If those were all of its samples the point is finished and kept like any other;
                    # else its part-run is not a point (a resume runs it again, the same numbers).
                    if outcome.partial:
                        ev.set()
                        continue
                    rows[todo[k]] = outcome.row
                    if store is not None:
                        store.add(outcome)
                    if progress is not None:
                        progress(len(rows), len(plan))
                interrupted = ev.is_set()
    partial = len(rows) < len(plan)
    # "interrupted": the stop left points to run. A Ctrl-C during the last point that still
    # finished it leaves a complete sweep, and the state must not say both (issue 36 item 14).
    interrupted = interrupted and partial
    elapsed = time.perf_counter() - t0
    used_workers = workers if not isinstance(scheduler, Executor) else scheduler.workers
    if store is not None:
        store.flush()
        store.write_state("partial" if partial else "complete", scheduler=ex_name, workers=used_workers,
                          elapsed_s=elapsed, interrupted=interrupted)
    return sweep_result(plan, rows, partial=partial, skipped=skipped, scheduler=ex_name, workers=used_workers,
                        elapsed_s=elapsed, out=str(out) if out is not None else None)


class _given:
    """A context manager that hands over an object it does not own."""

    def __init__(self, obj):
        self.obj = obj

    def __enter__(self):
        return self.obj

    def __exit__(self, *exc):
        return False


def _need_pyarrow() -> None:
    try:
        import pyarrow  # noqa: F401
    except ImportError:
        raise InputError("out", None, "writing the results (Parquet) needs pyarrow, an optional extra: "
                                      "pip install 'rvbacklash[sweep]'") from None
