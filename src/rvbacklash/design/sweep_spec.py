"""The sweep input (``SWEEP.toml``): a base design, the design fields to vary by their dotted
path, how to choose the points (a grid, or a Latin-hypercube / Sobol sample of scipy.stats.qmc),
the model, the samples per point, the seed and the specs (docs/sweeps.md).

Validated like designs (pydantic v2, strict, unknown keys refused): every problem becomes one
``InputError`` naming the field (``parameters[1].path``), the value and what is allowed. Every
point's design is validated as a whole ``Design`` before anything runs (``point_designs``).

Running the points is the analysis layer's job (``rvbacklash.analysis.sweep``).
"""

from __future__ import annotations

import copy
import itertools
import math
import re
import tomllib
import types
import typing
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any, Literal, Union

from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator, model_validator

from rvbacklash.design.loading import (_allowed_range, _submodel, available_examples, design_from_dict,
                                       read_design_text)
from rvbacklash.design.schema import Design
from rvbacklash.errors import InputError
from rvbacklash.factors.catalog import CATALOG
from rvbacklash.paths import is_file

SAMPLINGS = ("grid", "latin-hypercube", "sobol")
MAX_POINTS = 100_000  # a sweep larger than this is a typing error more often than a plan
MAX_PARAMETERS = 12
# spawn key of the generator of a Latin-hypercube / Sobol design of points: (DESIGN_STREAM,) of
# the sweep seed, apart from every point's Monte-Carlo streams (point, block)
DESIGN_STREAM = 2**32 - 1

_SWEEPS_DIR = "sweeps"  # inside the rvbacklash.examples package
_EXAMPLES_PACKAGE = "rvbacklash.examples"


class _FieldError(ValueError):
    """A rule over several fields that names the one at fault (relative to where it is raised)."""

    def __init__(self, field: str, value: Any = None, allowed: str = "", *, has_value: bool = True):
        self.field, self.value, self.allowed, self.has_value = field, value, allowed, has_value
        super().__init__(allowed)


def _problem(field: str, allowed: str) -> _FieldError:
    return _FieldError(field, allowed=allowed, has_value=False)


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False, strict=True)


Scalar = Union[bool, int, float, str]


# --- where a dotted path leads in the design ---------------------------------------------------

@dataclass(frozen=True)
class Leaf:
    """The design field a dotted path names: its kind ("int", "float", "str", "bool") and, for a
    choice among fixed strings, the allowed ones."""

    path: str
    kind: str
    choices: tuple[str, ...] = ()

    @property
    def numeric(self) -> bool:
        return self.kind in ("int", "float")


def _members(ann: Any) -> tuple:
    if typing.get_origin(ann) in (Union, types.UnionType):
        return tuple(a for a in typing.get_args(ann) if a is not type(None))
    return (ann,)


def _leaf_kind(ann: Any) -> tuple[str, tuple[str, ...]] | None:
    members = _members(ann)
    if any(typing.get_origin(m) is Literal for m in members):
        choices = tuple(str(c) for m in members if typing.get_origin(m) is Literal for c in typing.get_args(m))
        return "str", choices
    for kind, cls in (("bool", bool), ("int", int), ("float", float), ("str", str)):
        if cls in members:
            return kind, ()
    return None


def resolve_path(path: str) -> Leaf:
    """The design field at ``path`` (e.g. ``second_stage.equidistance_modification_um``,
    ``grades.cycloid``, ``factors.pin_hole_clearance.upper_um``); ValueError saying what is
    allowed where the path goes wrong."""
    parts = path.split(".")
    if not path or any(not p for p in parts):
        raise ValueError("allowed: a dotted path to a design field, e.g. second_stage.equidistance_modification_um")
    model: type[BaseModel] = Design
    for i, part in enumerate(parts):
        here = ".".join(parts[:i]) or "the design"
        if part not in model.model_fields:
            raise ValueError(f"unknown field {part!r} in {here}; allowed: {', '.join(model.model_fields)}")
        ann = model.model_fields[part].annotation
        rest = parts[i + 1:]
        sub = _submodel(model, (part,))
        if sub is not None:
            if not rest:
                raise ValueError(f"{'.'.join(parts[:i + 1])} is a table; allowed: one of its fields: "
                                 f"{', '.join(sub.model_fields)}")
            model = sub
            continue
        members = _members(ann)
        mapping = next((m for m in members if typing.get_origin(m) is dict), None)
        if mapping is not None:  # grades.factors.<factor key>
            keys = [f.key for f in CATALOG]
            if len(rest) != 1 or rest[0] not in keys:
                raise ValueError(f"{'.'.join(parts[:i + 1])} needs one factor key after it; allowed: "
                                 f"{', '.join(keys)}")
            kind = _leaf_kind(typing.get_args(mapping)[1])
            return Leaf(path, *kind)  # type: ignore[misc]
        kind = _leaf_kind(ann)
        if kind is None:
            raise ValueError(f"{'.'.join(parts[:i + 1])} is not a single value (a list or a matrix); allowed: "
                             f"a field holding one number, integer, string or boolean")
        if rest:
            raise ValueError(f"{'.'.join(parts[:i + 1])} is a value, it has no field {rest[0]!r}")
        return Leaf(path, *kind)
    raise ValueError("allowed: a dotted path to a design field")  # pragma: no cover - loop always returns


def coerce_value(leaf: Leaf, value: Any) -> Scalar:
    """``value`` in the field's own type (an integer field takes whole numbers only; a float field
    takes any number, stored as float); ValueError otherwise."""
    if leaf.kind == "bool":
        if not isinstance(value, bool):
            raise ValueError(f"allowed: true or false for {leaf.path}")
        return value
    if leaf.kind == "str":
        if not isinstance(value, str):
            raise ValueError(f"allowed: a string for {leaf.path}")
        if leaf.choices and value not in leaf.choices:
            raise ValueError(f"allowed for {leaf.path}: {', '.join(leaf.choices)}")
        return value
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ValueError(f"allowed: a finite number for {leaf.path}")
    if leaf.kind == "int":
        if value != int(value):
            raise ValueError(f"allowed: whole numbers for the integer field {leaf.path}")
        return int(value)
    return float(value)


# --- the schema --------------------------------------------------------------------------------

class Parameter(_Strict):
    """One design field to vary, by its dotted path, with one way of choosing its values:
    ``values`` (explicit; with a sampled design: choices drawn evenly), ``start``/``stop``/``count``
    (evenly spaced, both ends included; grid only) or ``low``/``high`` (bounds of a Latin-hypercube
    or Sobol sample; an integer field takes every whole number from low to high)."""

    path: str = Field(min_length=1, max_length=300,
                      description="dotted path of a design field, e.g. second_stage.equidistance_modification_um")
    values: list[Scalar] | None = Field(None, min_length=1, max_length=MAX_POINTS,
                                        description="explicit values (grid) or choices (sampled designs)")
    start: float | None = Field(None, description="first value of an evenly spaced range (grid)")
    stop: float | None = Field(None, description="last value of an evenly spaced range (grid), included")
    count: int | None = Field(None, ge=2, le=MAX_POINTS, description="number of values of the range, >= 2")
    low: float | None = Field(None, description="lower bound of a sampled design (latin-hypercube, sobol)")
    high: float | None = Field(None, description="upper bound of a sampled design (latin-hypercube, sobol)")
    label: str = Field("", max_length=100, description="short name for tables and figures; default: the path")

    @field_validator("path")
    @classmethod
    def _known_path(cls, path: str) -> str:
        resolve_path(path)
        return path

    @model_validator(mode="after")
    def _one_way(self) -> "Parameter":
        leaf = resolve_path(self.path)
        ranged = [n for n in ("start", "stop", "count") if getattr(self, n) is not None]
        bounded = [n for n in ("low", "high") if getattr(self, n) is not None]
        ways = (self.values is not None) + bool(ranged) + bool(bounded)
        if ways != 1:
            raise _problem("", "give exactly one of: values = [...]; start, stop and count; low and high")
        if ranged and len(ranged) != 3:
            raise _problem("", "a range needs start, stop and count")
        if bounded and len(bounded) != 2:
            raise _problem("", "a sampled parameter needs low and high")
        if (ranged or bounded) and not leaf.numeric:
            raise _FieldError("path", self.path, f"holds a {leaf.kind}; allowed for it: values = [...]")
        if self.values is not None:
            coerced = []
            for k, v in enumerate(self.values):
                try:
                    coerced.append(coerce_value(leaf, v))
                except ValueError as e:
                    raise _FieldError(f"values[{k}]", v, str(e)) from None
            if len(set(coerced)) != len(coerced):
                raise _FieldError("values", self.values, "a value is listed twice; allowed: distinct values")
        if ranged:
            if self.start == self.stop:
                raise _FieldError("stop", self.stop, f"equals start; allowed: stop != start = {self.start}")
            if leaf.kind == "int" and any(v != int(v) for v in self.range_values()):
                raise _FieldError("count", self.count, f"gives values between whole numbers; allowed: whole "
                                                       f"numbers for the integer field {self.path}")
        if bounded:
            if not self.low < self.high:  # type: ignore[operator]
                raise _FieldError("high", self.high, f"allowed: high > low = {self.low}")
            for name in ("low", "high"):
                v = getattr(self, name)
                if leaf.kind == "int" and v != int(v):
                    raise _FieldError(name, v, f"allowed: a whole number for the integer field {self.path}")
        return self

    @property
    def leaf(self) -> Leaf:
        return resolve_path(self.path)

    @property
    def name(self) -> str:
        return self.label or self.path

    def range_values(self) -> list[float]:
        """start + i (stop - start) / (count - 1), i = 0 .. count - 1, rounded to 12 decimals
        (so that 0.1 steps print as 0.3, not 0.30000000000000004)."""
        n = int(self.count)  # type: ignore[arg-type]
        step = (self.stop - self.start) / (n - 1)  # type: ignore[operator]
        return [round(self.start + i * step, 12) for i in range(n)]  # type: ignore[operator]

    def grid_values(self) -> list[Scalar]:
        leaf = self.leaf
        raw = self.values if self.values is not None else self.range_values()
        return [coerce_value(leaf, v) for v in raw]

    def from_unit(self, u: float) -> Scalar:
        """The value at u in [0, 1) of a sampled design: a choice among ``values`` (each with
        probability 1/k), a whole number low .. high, or low + u (high - low)."""
        leaf = self.leaf
        if self.values is not None:
            k = len(self.values)
            return coerce_value(leaf, self.values[min(int(u * k), k - 1)])
        lo, hi = float(self.low), float(self.high)  # type: ignore[arg-type]
        if leaf.kind == "int":
            n = int(hi) - int(lo) + 1
            return int(lo) + min(int(u * n), n - 1)
        return lo + u * (hi - lo)


class SweepSpec(_Strict):
    """A design sweep: the base design, the fields to vary, how to choose the points, and one
    Monte-Carlo run per point (model, samples, seed, specs)."""

    name: str = Field("", max_length=200, pattern=r"^$|^[A-Za-z0-9][A-Za-z0-9._-]*$",
                      description="name of the sweep (letters, digits, . _ -; it names the default --out "
                                  "directory); default: the file name without .toml")
    description: str = Field("", max_length=5000)
    design: str = Field(min_length=1, max_length=1000,
                        description="base design: a TOML path relative to the sweep file, or a built-in example")
    model: str = Field("linear", min_length=1, max_length=100,
                       description="model of every point: a name of analysis.simulation.MODELS (linear, contact, ...)")
    method: str = Field("default", description="sampling method of every point: default | box-muller | sobol")
    samples: int = Field(ge=1, le=10**9, description="Monte-Carlo samples per point")
    seed: int = Field(0, ge=0, le=2**63 - 1, description="seed of the sweep; point i draws from its stream (i,)")
    spec_arcmin: float | None = Field(None, gt=0, description="upper limit of the model's primary output [arcmin]")
    specs: dict[str, float] = Field(default_factory=dict,
                                    description="limits of outputs by name (e.g. backlash = 1.0, preload = 10.0)")
    life: bool = Field(False, description="elastic model: each point's life outputs as columns (life, "
                                          "weakest_bearing_life, rated_torque, max_pin_stress; docs/capacity.md); "
                                          "implied by a spec on one of them (specs.life = 6000.0)")
    quantiles: list[float] = Field(default_factory=list, max_length=20,
                                   description="extra quantiles per point, besides 0.00135, 0.5, 0.99865")
    sampling: Literal["grid", "latin-hypercube", "sobol"] = Field(
        "grid", description="grid: every combination of the parameters' values; latin-hypercube / sobol: "
                            "`points` points of a scipy.stats.qmc sample over the parameters' bounds")
    points: int | None = Field(None, ge=1, le=MAX_POINTS,
                               description="points of a latin-hypercube or sobol design (sobol: a power of 2)")
    parameters: list[Parameter] = Field(min_length=1, max_length=MAX_PARAMETERS,
                                        description="the design fields to vary")

    @field_validator("specs")
    @classmethod
    def _limits(cls, specs: dict[str, float]) -> dict[str, float]:
        for name, v in specs.items():
            if not math.isfinite(v) or v < 0 or (v == 0 and name != "preload"):
                raise _FieldError(name, v, "allowed: a finite limit > 0 (preload: >= 0) in the output's unit")
        return specs

    @field_validator("quantiles")
    @classmethod
    def _probabilities(cls, qs: list[float]) -> list[float]:
        for p in qs:
            if not 0 < p < 1:
                raise _FieldError("", p, "allowed: probabilities 0 < p < 1")
        return qs

    @model_validator(mode="after")
    def _consistent(self) -> "SweepSpec":
        paths = [p.path for p in self.parameters]
        for i, p in enumerate(paths):
            if p in paths[:i]:
                raise _FieldError(f"parameters[{i}].path", p, "is varied twice; allowed: each path once")
        labels = [p.name for p in self.parameters]
        for i, lab in enumerate(labels):
            if lab in labels[:i]:
                raise _FieldError(f"parameters[{i}].label", lab, "is another parameter's name; allowed: distinct "
                                                                 "labels")
        if self.sampling == "grid":
            if self.points is not None:
                raise _FieldError("points", self.points, "applies to sampling = latin-hypercube or sobol; a grid "
                                                         "has the product of the parameters' value counts")
            for i, p in enumerate(self.parameters):
                if p.low is not None:
                    raise _FieldError(f"parameters[{i}].low", p.low, "low/high are for sampling = latin-hypercube "
                                                                     "or sobol; allowed on a grid: values, or start, "
                                                                     "stop and count")
            n = math.prod(len(p.values) if p.values is not None else int(p.count)  # type: ignore[arg-type]
                          for p in self.parameters)
            if n > MAX_POINTS:
                raise _FieldError("parameters", n, f"points of the grid; allowed: at most {MAX_POINTS}")
        else:
            if self.points is None:
                raise _problem("points", f"missing: sampling = {self.sampling!r} needs points = N")
            if self.sampling == "sobol" and self.points & (self.points - 1):
                raise _FieldError("points", self.points, "allowed: a power of 2 for sampling = sobol (its balance "
                                                         "properties hold for 2^m points)")
            for i, p in enumerate(self.parameters):
                if p.count is not None:
                    raise _FieldError(f"parameters[{i}].count", p.count, f"start/stop/count make a grid; allowed "
                                                                         f"with sampling = {self.sampling}: low and "
                                                                         f"high, or values (choices)")
        return self

    @property
    def paths(self) -> tuple[str, ...]:
        return tuple(p.path for p in self.parameters)

    def point_count(self) -> int:
        if self.sampling == "grid":
            return math.prod(len(p.grid_values()) for p in self.parameters)
        return int(self.points)  # type: ignore[arg-type]


# --- points --------------------------------------------------------------------------------------

def sweep_points(spec: SweepSpec) -> list[tuple[Scalar, ...]]:
    """The parameter values of every point, in point order.

    grid: every combination, the first parameter varying slowest (row-major). latin-hypercube /
    sobol: ``spec.points`` points of a scrambled scipy.stats.qmc sample in [0, 1)^d drawn from
    ``SeedSequence(seed, spawn_key=(DESIGN_STREAM,))``, mapped to each parameter's bounds or choices.
    """
    if spec.sampling == "grid":
        return list(itertools.product(*(p.grid_values() for p in spec.parameters)))
    import numpy as np
    from scipy.stats import qmc

    d = len(spec.parameters)
    rng = np.random.default_rng(np.random.SeedSequence(spec.seed, spawn_key=(DESIGN_STREAM,)))
    cls = qmc.LatinHypercube if spec.sampling == "latin-hypercube" else qmc.Sobol
    try:
        sampler = cls(d, rng=rng)
    except TypeError:  # scipy < 1.15 calls it seed
        sampler = cls(d, seed=rng)
    n = int(spec.points)  # type: ignore[arg-type]
    u = sampler.random_base2(n.bit_length() - 1) if spec.sampling == "sobol" else sampler.random(n)
    return [tuple(p.from_unit(float(u[i, j])) for j, p in enumerate(spec.parameters)) for i in range(n)]


def with_values(data: dict, paths: tuple[str, ...], values: tuple[Scalar, ...]) -> dict:
    """A copy of a design's data (the parsed TOML) with each dotted path set to its value
    (tables created where missing)."""
    out = copy.deepcopy(data)
    for path, value in zip(paths, values):
        *heads, last = path.split(".")
        node = out
        for h in heads:
            nxt = node.get(h)
            if not isinstance(nxt, dict):
                nxt = {}
                node[h] = nxt
            node = nxt
        node[last] = value
    return out


def point_label(paths: tuple[str, ...], values: tuple[Scalar, ...]) -> str:
    return ", ".join(f"{p} = {v!r}" for p, v in zip(paths, values))


def point_designs(base: dict, spec: SweepSpec, points: list[tuple[Scalar, ...]]) -> list[Design]:
    """Every point's validated Design; the first invalid point raises one InputError naming the
    point, its values and what is wrong (the field and what is allowed)."""
    paths = spec.paths
    designs = []
    for i, values in enumerate(points):
        try:
            designs.append(design_from_dict(with_values(base, paths, values)))
        except InputError as e:
            which = next((f"parameters[{k}] " for k, p in enumerate(paths) if p == e.field), "")
            where = f"point {i} ({point_label(paths, values)}): {which}{e.field}"
            raise InputError(where, e.value, e.allowed) if e.has_value else InputError(where, allowed=e.allowed)
    return designs


# --- loading ---------------------------------------------------------------------------------------

@dataclass(frozen=True)
class SweepSource:
    """A validated sweep with where it came from: its text, its origin (a path or
    ``example:<name>``), the directory its base design path is relative to (None: the current
    directory for a sweep given as an object; an example's base is a built-in example), and
    the base design (parsed TOML data, origin, text)."""

    spec: SweepSpec
    origin: str
    text: str | None
    base_data: dict
    base_origin: str
    base_text: str


def available_sweeps() -> tuple[str, ...]:
    """Names of the built-in example sweeps (``modifications-sweep``, ...)."""
    d = resources.files(_EXAMPLES_PACKAGE).joinpath(_SWEEPS_DIR)
    if not d.is_dir():
        return ()
    return tuple(sorted(p.name.removesuffix(".toml") for p in d.iterdir() if p.name.endswith(".toml")))


def sweep_example_text(name: str) -> str:
    """The TOML text of a built-in example sweep."""
    if name not in available_sweeps():
        raise InputError("sweep", name, f"allowed: a built-in example sweep ({', '.join(available_sweeps())})")
    return resources.files(_EXAMPLES_PACKAGE).joinpath(_SWEEPS_DIR, f"{name}.toml").read_text(encoding="utf-8")


def sweep_description(name: str) -> str:
    return sweep_from_toml(sweep_example_text(name), name).description


_INDEX = re.compile(r"\.(\d+)(?=\.|$)")


def _field_name(loc: tuple) -> str:
    return _INDEX.sub(r"[\1]", ".".join(str(p) for p in loc))


def sweep_validation_error(err: ValidationError) -> InputError:
    """The first validation problem of a sweep as an InputError: field (``parameters[1].path``),
    value, what is allowed."""
    errors = sorted(err.errors(include_url=False), key=lambda e: e["type"] != "extra_forbidden")
    first = errors[0]
    loc = tuple(first["loc"])
    field = _field_name(loc) or "sweep"
    n = len(errors) - 1
    more = f" (and {n} more problem{'s' if n > 1 else ''})" if n else ""
    names = tuple(p for p in loc if isinstance(p, str))
    holder = _submodel(SweepSpec, names[:-1]) if names else None
    info = holder.model_fields.get(names[-1]) if holder is not None and names else None
    kind = first["type"]
    exc = (first.get("ctx") or {}).get("error")
    if isinstance(exc, _FieldError):
        name = _field_name(loc + ((exc.field,) if exc.field else ())) or "sweep"
        return InputError(name, exc.value, exc.allowed + more) if exc.has_value else \
            InputError(name, allowed=exc.allowed + more)
    if kind == "missing":
        return InputError(field, allowed="missing required field; " + (_allowed_range(info) or "required") + more)
    if kind == "extra_forbidden":
        allowed = f"unknown field; allowed fields here: {', '.join(holder.model_fields) if holder else 'none'}{more}"
        return InputError(field, first.get("input"), allowed)
    msg = first["msg"].removeprefix("Value error, ")
    value = first.get("input")
    if isinstance(value, dict):  # a rule over several fields: the message names them
        return InputError(field, allowed=msg + more)
    rng = _allowed_range(info) if info is not None and kind != "value_error" else ""
    return InputError(field, value, msg + (f"; {rng}" if rng else "") + more)


def sweep_from_dict(data: dict) -> SweepSpec:
    try:
        return SweepSpec.model_validate(data)
    except ValidationError as e:
        raise sweep_validation_error(e) from None


def sweep_from_toml(text: str, origin: str = "<string>") -> SweepSpec:
    try:
        data = tomllib.loads(text.removeprefix("\ufeff"))
    except tomllib.TOMLDecodeError as e:
        raise InputError(origin, allowed=f"malformed TOML: {e}") from None
    spec = sweep_from_dict(data)
    if not spec.name:
        stem = Path(origin.removeprefix("example:")).name.removesuffix(".toml")
        spec = spec.model_copy(update={"name": stem or "sweep"})
    return spec


def read_sweep_text(source: str | Path) -> tuple[str, str, Path | None]:
    """(TOML text, origin, directory of relative paths) of a sweep file or example sweep name."""
    path = Path(source)
    if is_file("sweep", source):
        try:
            return path.read_text(encoding="utf-8-sig"), str(path), path.resolve().parent
        except (OSError, UnicodeDecodeError) as e:
            raise InputError("sweep", str(source), f"cannot read file ({e})") from None
    if str(source) in available_sweeps():
        return sweep_example_text(str(source)), f"example:{source}", None
    raise InputError("sweep", str(source), f"allowed: a path to an existing SWEEP.toml file or a built-in example "
                                           f"sweep ({', '.join(available_sweeps())})")


def base_design(spec: SweepSpec, relative_to: Path | None) -> tuple[dict, str, str]:
    """(parsed TOML data, origin, text) of the sweep's base design: a TOML path relative to
    ``relative_to`` (the sweep file's directory; the current one when None), else a built-in
    example name. The base design itself must be valid."""
    path = (relative_to / spec.design) if relative_to is not None else Path(spec.design)
    if path.is_file():
        text, origin = read_design_text(path)
    elif spec.design in available_examples():
        text, origin = read_design_text(spec.design)
    else:
        where = f" (relative to {relative_to})" if relative_to is not None else ""
        raise InputError("design", spec.design, f"allowed: a design TOML file{where} or a built-in example "
                                                f"({', '.join(available_examples())})")
    try:
        data = tomllib.loads(text.removeprefix("\ufeff"))
    except tomllib.TOMLDecodeError as e:
        raise InputError(f"design {origin}", allowed=f"malformed TOML: {e}") from None
    try:
        design_from_dict(data)
    except InputError as e:
        where = f"design {origin}: {e.field}"
        raise (InputError(where, e.value, e.allowed) if e.has_value else InputError(where, allowed=e.allowed)) from None
    return data, origin, text


def load_sweep_source(source: str | Path | SweepSpec) -> SweepSource:
    """A validated sweep and its base design from a SWEEP.toml path, an example sweep name or a
    SweepSpec (its design path then relative to the current directory)."""
    if isinstance(source, SweepSpec):
        spec = source if source.name else source.model_copy(update={"name": "sweep"})
        origin, text, rel = "<object>", None, None
    elif isinstance(source, (str, Path)):
        text, origin, rel = read_sweep_text(source)
        spec = sweep_from_toml(text, origin)
    else:
        raise InputError("sweep", type(source).__name__, "allowed: a path to a SWEEP.toml file, an example sweep "
                                                         "name or a SweepSpec")
    data, base_origin, base_text = base_design(spec, rel)
    return SweepSource(spec, origin, text, data, base_origin, base_text)
