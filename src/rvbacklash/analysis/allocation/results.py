"""The typed results of a tolerance allocation: the groups' grades before and after, the points of
the cost-yield front, the uniform-grade baseline, the binding constraint, and AllocationResult
that holds them (``to_dict``, ``rows``/``to_frame``, ``summary``).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Mapping

from rvbacklash.analysis.statistics import Proportion
from rvbacklash.design.schema import Design
from rvbacklash.results import EXPORT, Result


@dataclass(frozen=True, repr=False)
class GroupGrade(Result):
    """A part group before and after the allocation."""

    group: str
    grade_table: str
    factors: tuple[str, ...]
    grade_before: int | None  # None: the group's factors had different grades
    grade_after: int
    cost_before: float | None
    cost_after: float
    grade_min: int
    grade_max: int
    description: str

    def summary(self) -> list[str]:
        before = "mixed" if self.grade_before is None else str(self.grade_before)
        return [f"{self.group}: grade {before} -> {self.grade_after}, cost {self.cost_after:.4g}"]


@dataclass(frozen=True, repr=False)
class FrontPoint(Result):
    """A design on the cost-yield plane."""

    cost: float
    yield_: Proportion = field(metadata={"key": "yield"})
    grades: Mapping[str, int]
    kind: str  # "optimum" (min cost at a yield target), "uniform", "candidate" (Monte-Carlo search)
    target: float | None  # the yield target it was the optimum for
    chosen: bool = False

    def row(self) -> dict:
        y = self.yield_
        return {"cost": self.cost, "yield": y.fraction, "yield_ci95_low": y.ci95_low, "yield_ci95_high": y.ci95_high,
                "kind": self.kind, "target": self.target, "chosen": self.chosen,
                **{f"grade.{k}": v for k, v in self.grades.items()}}


@dataclass(frozen=True, repr=False)
class Baseline(Result):
    """The cheapest uniform grade (every group alike) that meets the spec."""

    grade: int | None  # None: no uniform grade meets it
    cost: float | None
    yield_: Proportion | None = field(metadata={"key": "yield"})


@dataclass(frozen=True, repr=False)
class Binding(Result):
    """The constraint that decides the allocation and its slack; groups at their finest grade."""

    constraint: str
    value: float  # yield of the chosen design (point estimate)
    ci95_low: float  # lower end of its interval (= value when exact)
    target: float
    slack: float  # ci95_low - target
    at_finest: tuple[str, ...]  # groups at their finest allowed grade (bounds that bind)


@dataclass(frozen=True, repr=False)
class AllocationResult(Result):
    """The cheapest grades that meet the spec at the target yield, against the uniform-grade
    baseline, with the cost-yield Pareto front. ``rows()`` / ``to_frame()``: the grade table;
    ``front_rows()``: the front; ``design``: the chosen design (``--write-design``)."""

    design_name: str
    model: str
    method: str
    optimality: str
    output: str  # the output whose upper limit is spec_arcmin (backlash; lost_motion for the elastic model)
    spec_arcmin: float
    spec_rigidity_nm_per_arcmin: float | None
    spec_preload_um: float | None  # upper limit of the cycloid stage's preload (contact, elastic)
    spec_te_arcsec: float | None  # upper limit of the TE peak-to-peak (transmission model)
    yield_target: float
    unit: str
    cost: float
    cost_before: float | None
    yield_: Proportion = field(metadata={"key": "yield"})
    yield_before: Proportion | None
    yields: Mapping[str, Proportion]  # per output with a spec
    grades: Mapping[str, int]  # group -> grade after
    groups: tuple[GroupGrade, ...]
    binding: Binding
    baseline: Baseline
    saving: float | None  # baseline.cost - cost
    saving_fraction: float | None
    front: tuple[FrontPoint, ...]  # non-dominated designs, cheapest first
    uniform: tuple[FrontPoint, ...]  # every uniform grade
    samples: int | None  # per candidate (Monte-Carlo); None: exact
    seed: int | None
    evaluations: int  # candidates evaluated (exact yields, or Monte-Carlo runs)
    verification: Proportion | None  # yield of the chosen design on an independent stream
    elapsed_s: float
    partial: bool
    notes: tuple[str, ...]
    spec_life_h: float | None = None  # lower limit of the reducer's L10 at the rated torque and speed (elastic)
    spec_rated_torque_nm: float | None = None  # lower limit of the derived rated torque (elastic)
    design: Design | None = field(default=None, metadata={EXPORT: False})
    # the hours of ``duty_cycle`` a unit's lost motion must stay within spec_arcmin (elastic model, each unit's
    # own wear: docs/service-life.md); None: no accuracy-life spec
    spec_accuracy_life_h: float | None = None
    duty_cycle: str | None = None
    _frame_index = "group"

    def rows(self) -> list[dict]:
        return [g.to_dict() for g in self.groups]

    def front_rows(self) -> list[dict]:
        return [p.row() for p in self.front]

    def summary(self) -> list[str]:
        y = self.yield_
        what = f"{self.output} <= {self.spec_arcmin:g} arcmin" if self.spec_accuracy_life_h is None else \
            f"lost motion <= {self.spec_arcmin:g} arcmin for {self.spec_accuracy_life_h:g} h of {self.duty_cycle}"
        head = (f"{self.design_name}, {self.model} model: P({what}) >= "
                f"{self.yield_target:g}" + ("  [PARTIAL: interrupted]" if self.partial else ""))
        lines = [head, f"cost {self.cost:.4g} {self.unit}, yield {y.fraction:.6f}"
                       + (f" [{y.ci95_low:.6f}, {y.ci95_high:.6f}]" if y.ci95_low != y.ci95_high else " (exact)")]
        if self.baseline.cost is not None:
            lines.append(f"baseline: uniform grade {self.baseline.grade}, cost {self.baseline.cost:.4g} "
                         f"(saving {self.saving:.4g}, {self.saving_fraction:.1%})")
        return lines + [line for g in self.groups for line in g.summary()]
