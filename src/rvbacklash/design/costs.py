"""The cost model of tolerance allocation, as data: part groups (which catalog factors one
manufacturing decision sets together, and which grade table drives them) and the relative cost
of making each group to a precision grade.

Defaults: ``design/data/cost_tolerance.toml`` (its comments give the form, the sources and the
assumptions). A design's ``[costs]`` table (``Costs``) overrides them, validated like the rest of
the design::

    [costs]
    unit = "EUR"
    [costs.groups.pins]                   # change a default group
    fixed_cost = 3.0
    precision_cost = 6.0
    [costs.groups.cycloid_discs]
    cost_by_grade = { 4 = 31.0, 5 = 22.0, 6 = 17.0 }   # quotes instead of the formula
    [costs.groups.pin_fit]                # a new group (its factors leave the group they were in)
    factors = ["pin_hole_clearance"]
    fixed_cost = 1.0
    precision_cost = 2.0

Cost of group at grade g (``reciprocal_power_cost``): C(g) = A + B (t_ref / t(g))^k, with t(g)
the zone width of the group's ``tolerance_factor`` at grade g from the standards; the tolerance
itself is evaluated where the standards are known (``rvbacklash.analysis.grade_choices``).
"""

from __future__ import annotations

import functools
import math
import re
import tomllib
from dataclasses import dataclass
from importlib import resources
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, model_validator

from rvbacklash.design.bounds import bounds_text
from rvbacklash.factors.catalog import CATALOG, FACTOR_KEYS

DATA_FILE = "data/cost_tolerance.toml"
GRADE_TABLES = ("involute", "cycloid", "crank")
# The designed modifications are nominal values, not graded parts (= design.schema.OPTIONAL_FACTORS;
# not imported from there: schema imports this module).
NOMINAL_FACTORS = frozenset({"equidistance_modification", "moving_distance_modification"})
_NAME = re.compile(r"^[a-z][a-z0-9_]{0,63}$")
_STAGE_OF = {f.key: f.stage.label for f in CATALOG}


# --- the formula ---------------------------------------------------------------------------------

def reciprocal_power_cost(tolerance_um: float, reference_tolerance_um: float, fixed_cost: float,
                          precision_cost: float, exponent: float) -> float:
    """Relative cost of making a part to tolerance t: C = A + B (t_ref / t)^k.

    The reciprocal-power cost-tolerance curve C = A + B'/t^k (Sutherland; k = 1 the reciprocal
    curve, k = 2 Spotts'), as collected by Chase et al., Manufacturing Review 3(1) (1990) 49-59
    and the ADCATS reports, written about a reference tolerance: B' = B t_ref^k, so that B is the
    precision cost at the reference tolerance.
    Parameters: tolerance_um t > 0 [um], reference_tolerance_um t_ref > 0 [um], fixed_cost A >= 0
    and precision_cost B >= 0 [cost units], exponent k > 0 [-]. Returns [cost units]. Valid over
    the tolerances a process holds; outside them real costs jump (a process change), which a
    ``cost_by_grade`` table expresses.
    """
    if not (tolerance_um > 0 and reference_tolerance_um > 0):
        raise ValueError(f"tolerances must be > 0 um; got t = {tolerance_um}, t_ref = {reference_tolerance_um}")
    return fixed_cost + precision_cost * (reference_tolerance_um / tolerance_um) ** exponent


# --- resolved part groups ------------------------------------------------------------------------

@dataclass(frozen=True)
class PartGroup:
    """One part group of the cost model, complete (defaults merged with the design's [costs])."""

    name: str
    description: str
    grade_table: str  # involute | cycloid | crank
    factors: tuple[str, ...]  # catalog keys
    tolerance_factor: str  # its zone width at a grade is t(g)
    fixed_cost: float  # A
    precision_cost: float  # B
    exponent: float  # k
    reference_grade: int
    grade_min: int
    grade_max: int
    cost_by_grade: tuple[tuple[int, float], ...] | None  # (grade, cost): replaces the formula
    origin: str  # "default", "default, changed by [costs]" or "[costs]"

    @property
    def candidate_grades(self) -> tuple[int, ...]:
        """Grades the search may choose, finest first."""
        if self.cost_by_grade is not None:
            return tuple(g for g, _ in self.cost_by_grade if self.grade_min <= g <= self.grade_max)
        return tuple(range(self.grade_min, self.grade_max + 1))

    def tabulated_cost(self, grade: int) -> float | None:
        """The cost given for ``grade`` in ``cost_by_grade`` (None: the formula applies)."""
        if self.cost_by_grade is None:
            return None
        return dict(self.cost_by_grade).get(grade)


# --- the [costs] table -------------------------------------------------------------------------------

class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False, strict=True)


class GroupCost(_Strict):
    """Cost model of one part group; every field optional: those given replace the default
    group's (a new group needs ``factors`` and either the coefficients or ``cost_by_grade``)."""

    description: str | None = Field(None, max_length=500, description="what the group is")
    grade_table: Literal[GRADE_TABLES] | None = Field(  # type: ignore[valid-type]
        None, description="grade table that turns the grade into zones: involute, cycloid or crank; "
                          "default: the stage of the factors")
    factors: list[str] | None = Field(None, min_length=1, description="catalog factor keys of the group")
    tolerance_factor: str | None = Field(None, description="factor whose zone width at a grade is t(g); "
                                                           "default: the first factor")
    fixed_cost: float | None = Field(None, ge=0, le=1e12, description="A: cost independent of the tolerance")
    precision_cost: float | None = Field(None, ge=0, le=1e12, description="B: cost of precision at the "
                                                                           "reference grade")
    exponent: float | None = Field(None, gt=0, le=10, description="k of C = A + B (t_ref/t)^k [-]")
    reference_grade: int | None = Field(None, ge=0, le=12, description="grade at which t = t_ref")
    grade_min: int | None = Field(None, ge=0, le=12, description="finest grade the search may choose")
    grade_max: int | None = Field(None, ge=0, le=12, description="coarsest grade the search may choose")
    cost_by_grade: dict[str, float] | None = Field(
        None, description="cost at each grade, e.g. { 4 = 31.0, 5 = 22.0 }: replaces the formula; the "
                          "search chooses among these grades")


class SelectionCost(_Strict):
    """What selective assembly costs per reducer built (``[costs.selection]``; docs/selective-assembly.md):
    the measuring of the discs and the housing, each class kept (per part kind, beyond the first),
    and the share of a left-over part set's price that is lost. Fields left out take the defaults of
    design/data/cost_tolerance.toml ([selection]: assumptions, in the groups' relative units)."""

    measuring_cost_per_unit: float | None = Field(None, ge=0, le=1e12, description="measuring one unit's discs and "
                                                                                   "housing [cost units]")
    class_cost: float | None = Field(None, ge=0, le=1e12, description="each class kept beyond the first, per part "
                                                                      "kind, per unit built [cost units]")
    surplus_cost_share: float | None = Field(None, ge=0, le=1, description="share of a left-over part set's cost "
                                                                           "that is lost (0: used later; 1: scrapped)")


class Costs(_Strict):
    """The design's ``[costs]`` table: overrides of the default cost model."""

    unit: str | None = Field(None, max_length=100, description="unit of the costs (default: relative)")
    only_listed_groups: bool = Field(False, description="true: the groups listed here are the only part groups")
    groups: dict[str, GroupCost] = Field(default_factory=dict, description="part groups by name")
    selection: SelectionCost | None = Field(None, description="the cost of selective assembly (allocate "
                                                              "--select-classes)")

    @model_validator(mode="before")
    @classmethod
    def _groups_one_by_one(cls, data):
        """Each group validated on its own, so that an error names the group, the field and what is
        allowed (a dict of models is opaque to the design loader's messages)."""
        groups = data.get("groups") if isinstance(data, dict) else None
        if isinstance(groups, dict):
            for name, body in groups.items():
                if isinstance(body, dict):
                    _check_group_fields(str(name), body)
        return data

    @model_validator(mode="after")
    def _complete(self) -> "Costs":
        part_groups(self)  # every merged group complete and consistent, or a ValueError naming it
        return self


def _check_group_fields(name: str, body: dict) -> None:
    from pydantic import ValidationError

    known = GroupCost.model_fields
    for key in body:
        if key not in known:
            raise ValueError(f"groups.{name}.{key}: unknown field; allowed fields: {', '.join(known)}")
    try:
        GroupCost.model_validate(body)
    except ValidationError as e:
        first = e.errors(include_url=False)[0]
        loc = ".".join(str(p) for p in first["loc"])
        field = first["loc"][0] if first["loc"] else None
        info = known.get(field) if isinstance(field, str) else None
        bounds = bounds_text(info) if info is not None else ""
        allowed = "; allowed: " + " ".join(p for p in (bounds, f"({info.description})" if info and info.description
                                                        else "") if p) if info is not None else ""
        raise ValueError(f"groups.{name}.{loc} = {first.get('input')!r}: {first['msg']}{allowed}") from None


# --- defaults and merging ----------------------------------------------------------------------------

@functools.lru_cache(maxsize=1)
def default_cost_data() -> dict:
    """The parsed default data file (design/data/cost_tolerance.toml)."""
    text = resources.files("rvbacklash.design").joinpath(DATA_FILE).read_text(encoding="utf-8")
    return tomllib.loads(text)


@dataclass(frozen=True)
class SelectionPrices:
    """The cost of selective assembly, complete (defaults merged with ``[costs.selection]``)."""

    measuring_cost_per_unit: float
    class_cost: float
    surplus_cost_share: float


def selection_prices(costs: Costs | None) -> SelectionPrices:
    """The design's selection costs: ``[costs.selection]`` over the data file's [selection]."""
    base = dict(default_cost_data()["selection"])
    if costs is not None and costs.selection is not None:
        base.update(costs.selection.model_dump(exclude_none=True))
    return SelectionPrices(float(base["measuring_cost_per_unit"]), float(base["class_cost"]),
                           float(base["surplus_cost_share"]))


def cost_unit(costs: Costs | None) -> str:
    return (costs.unit if costs is not None and costs.unit else None) or str(default_cost_data()["unit"])


def _grade_table(cost_by_grade: dict[str, float], where: str) -> tuple[tuple[int, float], ...]:
    out = []
    for key, value in cost_by_grade.items():
        if not re.fullmatch(r"\d{1,2}", key) or not 0 <= int(key) <= 12:
            raise ValueError(f"{where}.cost_by_grade: grade {key!r}; allowed: grades 0 to 12")
        if not (math.isfinite(value) and value >= 0):
            raise ValueError(f"{where}.cost_by_grade.{key} = {value}; allowed: a finite cost >= 0")
        out.append((int(key), float(value)))
    if not out:
        raise ValueError(f"{where}.cost_by_grade is empty; allowed: at least one grade = cost")
    return tuple(sorted(out))


def _merge(name: str, base: dict, override: GroupCost | None, data: dict, origin: str) -> PartGroup:
    where = f"groups.{name}"
    fields = dict(base)
    if override is not None:
        fields.update({k: v for k, v in override.model_dump(exclude_none=True).items()})
    factors = fields.get("factors")
    if not factors:
        raise ValueError(f"{where}: a new group needs factors = [...]; allowed keys: {', '.join(FACTOR_KEYS)}")
    for key in factors:
        if key not in FACTOR_KEYS:
            raise ValueError(f"{where}.factors: unknown factor {key!r}; allowed: {', '.join(FACTOR_KEYS)}")
        if key in NOMINAL_FACTORS:
            raise ValueError(f"{where}.factors: {key} is a designed modification (a nominal value), not a graded "
                             f"part; allowed: its error {key}_error")
    if len(set(factors)) != len(factors):
        raise ValueError(f"{where}.factors: a factor is listed twice")
    stages = sorted({_STAGE_OF[k] for k in factors})
    table = fields.get("grade_table") or stages[0]
    if len(stages) > 1 or stages[0] != table:
        raise ValueError(f"{where}: grade_table {table!r} but factors of stage(s) {', '.join(stages)}; allowed: "
                         f"factors whose zones one grade table gives (one stage)")
    tol = fields.get("tolerance_factor") or factors[0]
    if tol not in factors:
        raise ValueError(f"{where}.tolerance_factor = {tol!r}; allowed: one of the group's factors "
                         f"({', '.join(factors)})")
    by_grade = fields.get("cost_by_grade")
    table_costs = _grade_table(by_grade, where) if by_grade is not None else None
    if table_costs is None and (fields.get("fixed_cost") is None or fields.get("precision_cost") is None):
        raise ValueError(f"{where}: no cost; allowed: fixed_cost and precision_cost (and exponent), or "
                         f"cost_by_grade")
    lo = int(fields.get("grade_min", data["grade_min"] if table_costs is None else min(g for g, _ in table_costs)))
    hi = int(fields.get("grade_max", data["grade_max"] if table_costs is None else max(g for g, _ in table_costs)))
    if lo > hi:
        raise ValueError(f"{where}: grade_min = {lo} > grade_max = {hi}; allowed: grade_min <= grade_max")
    if table_costs is not None and not any(lo <= g <= hi for g, _ in table_costs):
        raise ValueError(f"{where}: no grade of cost_by_grade lies in [grade_min, grade_max] = [{lo}, {hi}]")
    return PartGroup(
        name=name, description=str(fields.get("description", "")), grade_table=table, factors=tuple(factors),
        tolerance_factor=tol, fixed_cost=float(fields.get("fixed_cost", 0.0)),
        precision_cost=float(fields.get("precision_cost", 0.0)), exponent=float(fields.get("exponent", 1.0)),
        reference_grade=int(fields.get("reference_grade", data["reference_grade"])), grade_min=lo, grade_max=hi,
        cost_by_grade=table_costs, origin=origin)


def part_groups(costs: Costs | None = None) -> tuple[PartGroup, ...]:
    """The part groups of the cost model: the defaults, changed, extended or replaced by a design's
    [costs] table. A factor named by a group of [costs] leaves the default group it was in; a
    default group left without factors is dropped. ValueError names the offending group."""
    data = default_cost_data()
    defaults: dict[str, dict] = {k: dict(v) for k, v in data["groups"].items()}
    overrides = dict(costs.groups) if costs is not None else {}
    only = costs is not None and costs.only_listed_groups
    for name in overrides:
        if not _NAME.match(name):
            raise ValueError(f"groups: name {name!r}; allowed: lower-case letters, digits and _ (a-z first)")
    # factors claimed by the [costs] table leave the default groups that are not themselves overridden
    claimed = {k: n for n, o in overrides.items() if o.factors for k in o.factors}
    out: list[PartGroup] = []
    names = list(overrides) if only else list(defaults) + [n for n in overrides if n not in defaults]
    for name in names:
        base = defaults.get(name, {})
        override = overrides.get(name)
        if base and (override is None or override.factors is None):
            base = dict(base, factors=[k for k in base["factors"] if claimed.get(k, name) == name])
            if not base["factors"]:
                if override is None:
                    continue
                raise ValueError(f"groups.{name}: every factor of the group is claimed by other groups; allowed: "
                                 f"give its factors, or drop it")
            if base.get("tolerance_factor") not in base["factors"]:
                base["tolerance_factor"] = base["factors"][0]
        origin = "default" if override is None else ("[costs]" if name not in defaults
                                                     else "default, changed by [costs]")
        out.append(_merge(name, base, override, data, origin))
    seen: dict[str, str] = {}
    for g in out:
        for key in g.factors:
            if key in seen:
                raise ValueError(f"groups: factor {key!r} is in groups {seen[key]!r} and {g.name!r}; allowed: each "
                                 f"factor in one group")
            seen[key] = g.name
    if not out:
        raise ValueError("groups: no part group left; allowed: at least one group")
    return tuple(out)
