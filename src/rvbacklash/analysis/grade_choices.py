"""What a tolerance allocation can choose on a prepared design: for each part group of the cost
model (``rvbacklash.design.costs``), the grades it may take, the cost of each grade and the
tolerance zones its factors get; and a candidate (one grade per group) as zones, as a Problem
and as a Design that ``simulate`` re-runs to the same numbers.

A factor's zone depends on its own grade only (``standards.factor_tolerances``), so the zones
of every factor at every grade are resolved once (one ``prepare`` per grade) and a candidate is
assembled from them without touching the standards again.
"""

from __future__ import annotations

import dataclasses
import math
from collections import Counter
from dataclasses import dataclass
from typing import Sequence

import numpy as np

from rvbacklash.analysis.scenarios import apply_overrides
from rvbacklash.design.costs import NOMINAL_FACTORS, PartGroup, cost_unit, part_groups, reciprocal_power_cost
from rvbacklash.design.loading import design_from_dict
from rvbacklash.design.schema import Design
from rvbacklash.errors import InputError
from rvbacklash.factors.catalog import CATALOG, FACTOR_KEYS, factor_by_key
from rvbacklash.factors.distributions import ResolvedZone, is_normal
from rvbacklash.problem import Problem, prepare
from rvbacklash.standards.factor_tolerances import graded_zone

STAGES = ("involute", "cycloid", "crank")
_INDEX = {k: i for i, k in enumerate(FACTOR_KEYS)}


def graded_factors(design: Design) -> tuple[str, ...]:
    """Keys of the factors whose zone comes from a grade (neither an explicit zone nor a designed
    modification's nominal value), in catalog order."""
    out = []
    for f in CATALOG:
        zone = getattr(design.factors, f.key)
        if f.key in NOMINAL_FACTORS or (zone is not None and zone.has_zone):
            continue
        if design.grades is not None and design.grades.grade_for(f) is not None:
            out.append(f.key)
    return tuple(out)


@dataclass(frozen=True, eq=False)
class GroupChoice:
    """One part group on one design: its candidate grades (finest first) and their costs."""

    group: PartGroup
    factors: tuple[int, ...]  # catalog indices of the group's factors whose zone comes from a grade
    grades: tuple[int, ...]
    costs: tuple[float, ...]
    tolerances_um: tuple[float | None, ...]  # t(g) of the tolerance factor (None: cost tabulated)
    current_grade: int | None  # the design's grade of the group (None: its factors differ)
    current_cost: float | None

    @property
    def name(self) -> str:
        return self.group.name

    def cost_of(self, grade: int) -> float:
        return self.costs[self.grades.index(grade)]


@dataclass(frozen=True, eq=False)
class GradeChoices:
    """The part groups of a design with their options; candidates are tuples of grades, one per
    group in ``groups`` order."""

    problem: Problem
    groups: tuple[GroupChoice, ...]
    unit: str
    notes: tuple[str, ...]
    zones_at: dict  # grade -> tuple of 21 ResolvedZone at that grade (valid for the groups' factors)
    means_at: dict  # grade -> (21,) means [um]
    sigmas_at: dict  # grade -> (21,) sigmas [um]

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(g.name for g in self.groups)

    @property
    def current(self) -> tuple[int | None, ...]:
        return tuple(g.current_grade for g in self.groups)

    def check(self, grades: Sequence[int]) -> tuple[int, ...]:
        grades = tuple(int(g) for g in grades)
        if len(grades) != len(self.groups):
            raise ValueError(f"{len(grades)} grades for {len(self.groups)} groups")
        for g, c in zip(grades, self.groups):
            if g not in c.grades:
                raise ValueError(f"grade {g} is not a candidate of group {c.name} ({c.grades})")
        return grades

    def cost(self, grades: Sequence[int]) -> float:
        return float(sum(c.cost_of(g) for c, g in zip(self.groups, self.check(grades))))

    def moments(self, grades: Sequence[int]) -> tuple[tuple[ResolvedZone, ...], np.ndarray, np.ndarray]:
        """(zones, means [um], sigmas [um]) of every factor for a candidate."""
        p = self.problem
        zones = list(p.zones)
        means, sigmas = p.means_um.copy(), p.sigmas_um.copy()
        for c, g in zip(self.groups, self.check(grades)):
            for i in c.factors:
                zones[i] = self.zones_at[g][i]
                means[i] = self.means_at[g][i]
                sigmas[i] = self.sigmas_at[g][i]
        return tuple(zones), means, sigmas

    def candidate_problem(self, grades: Sequence[int]) -> Problem:
        """The base Problem with the candidate's zones (same geometry, correlation, coefficients)."""
        zones, means, sigmas = self.moments(grades)
        return dataclasses.replace(self.problem, zones=zones, means_um=means, sigmas_um=sigmas)

    def all_normal(self) -> bool:
        """Every random factor is normal at every candidate grade (closed-form exact distribution)."""
        p = self.problem
        fixed = [i for c in self.groups for i in c.factors]
        if any(p.sigmas_um[i] > 0 and not is_normal(z) for i, z in enumerate(p.zones) if i not in fixed):
            return False
        return all(self.sigmas_at[g][i] == 0 or is_normal(self.zones_at[g][i])
                   for c in self.groups for g in c.grades for i in c.factors)

    def factor_grades(self, grades: Sequence[int]) -> dict[str, int]:
        """Grade of every graded factor for a candidate (factors of no group keep the design's)."""
        design = self.problem.design
        out = {k: design.grades.grade_for(factor_by_key(k))[0] for k in graded_factors(design)}
        for c, g in zip(self.groups, self.check(grades)):
            for i in c.factors:
                out[FACTOR_KEYS[i]] = g
        return out

    def design(self, grades: Sequence[int], description: str | None = None) -> Design:
        """The design with the candidate's grades: each stage takes the grade most of its graded
        factors have, the others are set per factor (grades.factors); explicit zones are kept."""
        base = self.problem.design
        data = base.model_dump(exclude_none=True)
        if description is not None:
            data["description"] = description
        fg = self.factor_grades(grades)
        table = data.setdefault("grades", {})
        stage_of = {f.key: f.stage.label for f in CATALOG}
        per_factor = {k: v for k, v in table.get("factors", {}).items() if k not in fg}
        for stage in STAGES:
            keys = [k for k in fg if stage_of[k] == stage]
            if not keys:
                continue
            table[stage] = Counter(fg[k] for k in keys).most_common(1)[0][0]
            per_factor.update({k: fg[k] for k in keys if fg[k] != table[stage]})
        if per_factor:
            table["factors"] = {k: per_factor[k] for k in FACTOR_KEYS if k in per_factor}
        else:
            table.pop("factors", None)
        return design_from_dict(data)


def _width(group: PartGroup, grade: int, design: Design) -> float:
    f = factor_by_key(group.tolerance_factor)
    where = f"costs.groups.{group.name}"
    z = graded_zone(f, grade, design, design.grades.edition, where)
    w = float(z.upper_um - z.lower_um)
    if not w > 0:
        raise InputError(where + ".tolerance_factor", group.tolerance_factor,
                         f"its zone at grade {grade} has no width; allowed: a factor whose tolerance grows with the "
                         f"grade")
    return w


def group_cost(group: PartGroup, grade: int, design: Design) -> tuple[float, float | None]:
    """(cost, t(g) [um] or None when tabulated) of making ``group`` to ``grade`` on ``design``."""
    tab = group.tabulated_cost(grade)
    if tab is not None:
        return tab, None
    if group.cost_by_grade is not None:
        raise InputError(f"costs.groups.{group.name}.cost_by_grade", grade, "no cost given for this grade")
    t = _width(group, grade, design)
    try:
        t_ref = _width(group, group.reference_grade, design)
    except InputError as e:
        raise InputError(f"costs.groups.{group.name}.reference_grade", group.reference_grade, e.allowed) from None
    return reciprocal_power_cost(t, t_ref, group.fixed_cost, group.precision_cost, group.exponent), t


def _prepare_at(design: Design, keys: Sequence[str], grade: int) -> Problem | None:
    try:
        return prepare(apply_overrides(design, {k: grade for k in keys}))
    except InputError:
        return None


def grade_choices(problem: Problem) -> GradeChoices:
    """The allocation options of a prepared design, with the design's [costs] (or the defaults)."""
    design = problem.design
    graded = graded_factors(design)
    if not graded:
        raise InputError("design", problem.name, "no factor takes its tolerance from a grade, so there is nothing to "
                                                 "allocate; allowed: a design with a [grades] table (e.g. rv80e)")
    notes: list[str] = []
    groups = part_groups(design.costs)
    active = []
    for g in groups:
        idx = tuple(_INDEX[k] for k in g.factors if k in graded)
        if not idx:
            notes.append(f"group {g.name}: every factor has an explicit zone; not allocated")
            continue
        active.append((g, idx))
    lone = [k for k in graded if not any(_INDEX[k] in idx for _, idx in active)]
    if lone:
        notes.append(f"factors in no part group keep the design's grade: {', '.join(lone)}")
    keys = [FACTOR_KEYS[i] for _, idx in active for i in idx]
    wanted = sorted({gr for g, _ in active for gr in g.candidate_grades})
    zones_at, means_at, sigmas_at = {}, {}, {}
    usable: dict[str, set[int]] = {g.name: set() for g, _ in active}
    for grade in wanted:
        p = _prepare_at(design, keys, grade)
        if p is not None:
            zones_at[grade], means_at[grade], sigmas_at[grade] = list(p.zones), p.means_um.copy(), p.sigmas_um.copy()
            for g, _ in active:
                usable[g.name].add(grade)
            continue
        # some factor has no tolerance at this grade (outside a standard's scope): group by group
        zones_at[grade] = list(problem.zones)
        means_at[grade], sigmas_at[grade] = problem.means_um.copy(), problem.sigmas_um.copy()
        for g, idx in active:
            if grade not in g.candidate_grades:
                continue
            q = _prepare_at(design, [FACTOR_KEYS[i] for i in idx], grade)
            if q is None:
                notes.append(f"group {g.name}: grade {grade} dropped (outside the scope of its standard for this "
                             f"design)")
                continue
            usable[g.name].add(grade)
            for i in idx:
                zones_at[grade][i], means_at[grade][i], sigmas_at[grade][i] = q.zones[i], q.means_um[i], q.sigmas_um[i]
    choices = []
    for g, idx in active:
        grades = tuple(gr for gr in g.candidate_grades if gr in usable[g.name])
        if not grades:
            raise InputError(f"costs.groups.{g.name}", f"grades {g.grade_min}-{g.grade_max}",
                             "none of them gives tolerances for this design; allowed: other grade_min/grade_max")
        costs, tols = zip(*(group_cost(g, gr, design) for gr in grades))
        current = {design.grades.grade_for(factor_by_key(FACTOR_KEYS[i]))[0] for i in idx}
        cur = current.pop() if len(current) == 1 else None
        cur_cost = None
        if cur is not None:
            try:
                cur_cost = costs[grades.index(cur)] if cur in grades else group_cost(g, cur, design)[0]
            except InputError:
                cur_cost = None
        choices.append(GroupChoice(g, idx, grades, tuple(float(c) for c in costs), tols, cur, cur_cost))
    for grade in zones_at:
        zones_at[grade] = tuple(zones_at[grade])
    return GradeChoices(problem, tuple(choices), cost_unit(design.costs), tuple(notes), zones_at, means_at, sigmas_at)


def moments_arcmin(problem: Problem, means: np.ndarray, sigmas: np.ndarray) -> tuple[float, float]:
    """Mean and sigma of the linear model's output [arcmin] for given factor moments [um]:
    mu = S . m, sigma = sqrt(v^T R v), v = S sigma (Eq. (2), statistical stack-up)."""
    s = problem.sensitivities_arcmin_per_um
    v = s * sigmas
    return float(s @ means), math.sqrt(max(float(v @ problem.correlation @ v), 0.0))
