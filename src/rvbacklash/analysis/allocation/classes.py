"""Allocation of grades *and* classes (issue 39; docs/selective-assembly.md): the cheapest combination
of the part groups' grades and the number of pin and needle-roller diameter classes that meets the
yield target, when selective assembly is a lever beside the grades.

For each selection of a menu (random assembly first; then pins and rollers in classes), the
Monte-Carlo allocation (``search``) finds the cheapest grades whose units, assembled with that
selection, meet the target (common random numbers: every candidate the same units). The total cost
per reducer built of an option is

    C = C_grades + [selection] (m + c_k (K_p - 1) + c_k (K_r - 1))
        + s (r_p - 1) C_pins + s (r_r - 1) C_rollers,

m the measuring cost per unit, c_k the cost of a class kept beyond the first (per part kind), K the
class counts, r the part sets bought per unit built (the classes' demand against the parts' law:
analysis.selection.run.surplus), s the share of a left-over set's price that is lost and C_pins,
C_rollers the cost of the part groups holding the pins' diameter and the crank bearings' clearance at
the chosen grades ([costs.selection], design.costs.selection_prices). The search within an option
minimises C_grades (its selection's fixed cost is the same for every candidate); the surplus term is
charged on the design it chose (r moves little between neighbouring grades). The cheapest total wins.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Callable

from rvbacklash.analysis.allocation.results import AllocationResult
from rvbacklash.analysis.allocation.search import DEFAULT_MC_SAMPLES, SEARCH_STREAM, allocate_monte_carlo, \
    evaluate_candidate
from rvbacklash.analysis.allocation.specs import extra_specs
from rvbacklash.analysis.selection.classes import ClassSet, Selection, make_selection
from rvbacklash.analysis.statistics import Proportion
from rvbacklash.design.costs import selection_prices
from rvbacklash.errors import InputError
from rvbacklash.problem import Problem
from rvbacklash.results import KEY, Result

# the menu of ``allocate --select-classes``: random assembly, then pins, rollers and both in classes 2 um wide
DEFAULT_MENU = ((1, 1), (3, 1), (5, 1), (1, 3), (3, 3), (5, 3))
MENU_WIDTH_UM = 2.0
PIN_FACTOR, ROLLER_FACTOR = "pin_radius", "crank_bearing_clearance"


@dataclass(frozen=True, repr=False)
class ClassOption(Result):
    """One selection of the menu and the cheapest grades that meet the target with it (``grades``
    None: none found), with its cost per reducer built split into its terms."""

    selection: str
    pin_classes: int
    roller_classes: int
    feasible: bool
    grades: dict | None
    yield_: Proportion | None = field(metadata={KEY: "yield"})
    grades_cost: float | None
    selection_cost: float  # measuring and classes
    surplus_cost: float | None
    total_cost: float | None
    pin_sets_per_unit: float | None
    roller_sets_per_unit: float | None
    chosen: bool = False
    note: str = ""


@dataclass(frozen=True, repr=False)
class ClassAllocationResult(Result):
    """The cheapest combination of grades and classes (module docstring): every option of the menu,
    the chosen one's allocation, and whether selection let coarser grades pass."""

    design_name: str
    model: str
    spec_arcmin: float
    yield_target: float
    unit: str
    measuring_cost_per_unit: float
    class_cost: float
    surplus_cost_share: float
    options: tuple[ClassOption, ...]
    chosen: str | None  # the selection of the cheapest option
    coarser_grades: dict  # group -> (grade at random assembly, grade chosen) where the chosen one is coarser
    allocation: AllocationResult | None  # the chosen option's
    random_allocation: AllocationResult | None  # random assembly's

    def rows(self) -> list[dict]:
        return [{k: v for k, v in o.to_dict().items() if k != "grades"} | {
            f"grade_{g}": v for g, v in (o.grades or {}).items()} for o in self.options]

    def summary(self) -> list[str]:
        lines = [f"{self.design_name}, {self.model} model: cheapest grades and classes for yield >= "
                 f"{self.yield_target:g} at {self.spec_arcmin:g} arcmin"]
        for o in self.options:
            cost = f"{o.total_cost:.2f} {self.unit}" if o.total_cost is not None else "no design meets the target"
            lines.append(f"{'*' if o.chosen else ' '} {o.selection}: {cost}")
        if self.coarser_grades:
            lines.append("selection lets coarser grades pass: " + ", ".join(
                f"{g} {a} -> {b}" for g, (a, b) in self.coarser_grades.items()))
        return lines


def menu_selection(pins: int, rollers: int, width_um: float = MENU_WIDTH_UM) -> Selection | None:
    """The option (pin classes, roller classes) of the menu; (1, 1): random assembly (None)."""
    if pins == 1 and rollers == 1:
        return None
    return make_selection(pins=ClassSet(pins, width_um) if pins > 1 else None,
                          rollers=ClassSet(rollers, width_um) if rollers > 1 else None)


def _group_cost(result: AllocationResult, factor: str) -> float:
    return sum(g.cost_after for g in result.groups if factor in g.factors)


def allocate_grades_and_classes(problem: Problem, *, model: str, spec_arcmin: float, yield_target: float,
                                menu=DEFAULT_MENU, width_um: float = MENU_WIDTH_UM,
                                spec_rigidity_nm_per_arcmin: float | None = None, spec_preload_um: float | None = None,
                                spec_te_arcsec: float | None = None, samples: int = DEFAULT_MC_SAMPLES,
                                seed: int = 0, workers: int | None = None,
                                progress: Callable[[int], None] | None = None) -> ClassAllocationResult:
    """The cheapest grades and classes (module docstring) over ``menu``: (pin classes, roller classes)
    pairs of classes ``width_um`` wide [um of diameter]."""
    if model not in ("contact", "elastic", "transmission"):
        raise InputError("model", model, "allowed with selection: contact, elastic, transmission (a Monte-Carlo "
                                         "model: the linear one draws no parts)")
    if not menu or any(not (isinstance(p, int) and isinstance(r, int) and p >= 1 and r >= 1) for p, r in menu):
        raise InputError("menu", menu, "allowed: (pin classes, roller classes) pairs of whole numbers >= 1")
    if spec_te_arcsec is not None and model == "contact":
        model = "transmission"
    prices = selection_prices(problem.design.costs)
    specs = extra_specs(spec_rigidity_nm_per_arcmin, spec_preload_um, spec_te_arcsec, None, None) or None
    kw = dict(model=model, spec_arcmin=spec_arcmin, yield_target=yield_target,
              spec_rigidity_nm_per_arcmin=spec_rigidity_nm_per_arcmin, spec_preload_um=spec_preload_um,
              spec_te_arcsec=spec_te_arcsec, samples=samples, seed=seed, workers=workers, progress=progress)
    found: list[tuple[ClassOption, AllocationResult | None]] = []
    for pins, rollers in dict.fromkeys(tuple(m) for m in menu):
        sel = menu_selection(pins, rollers, width_um)
        fixed = 0.0 if sel is None else prices.measuring_cost_per_unit + prices.class_cost * (pins - 1 + rollers - 1)
        name = "random assembly" if sel is None else ",".join(
            f"{part}={k}x{width_um:g}um" for part, k in (("pins", pins), ("rollers", rollers)) if k > 1)
        try:
            res = allocate_monte_carlo(problem, selection=sel, **kw)
        except InputError as e:
            if e.field != "yield_target":
                raise
            found.append((ClassOption(name, pins, rollers, False, None, None, None, fixed, None, None, None, None,
                                      note=e.allowed.split(";")[0]), None))
            continue
        rp = rr = 1.0
        if sel is not None:  # the chosen design's part sets per unit built (the search's own run, again)
            ev = evaluate_candidate((res.design, model, int(samples), int(seed), (SEARCH_STREAM,), float(spec_arcmin),
                                     specs, workers or 1, sel))
            rp, rr = ev.pin_sets_per_unit, ev.roller_sets_per_unit
        surplus = prices.surplus_cost_share * ((rp - 1.0) * _group_cost(res, PIN_FACTOR)
                                               + (rr - 1.0) * _group_cost(res, ROLLER_FACTOR))
        total = res.cost + fixed + surplus
        found.append((ClassOption(name, pins, rollers, not res.partial, dict(res.grades), res.yield_, res.cost, fixed,
                                  surplus, total, rp, rr), res))
        if res.partial:
            break
    feasible = [(o.total_cost, i) for i, (o, _) in enumerate(found) if o.feasible and math.isfinite(o.total_cost)]
    best = min(feasible)[1] if feasible else None
    options = tuple(o if i != best else replace(o, chosen=True) for i, (o, _) in enumerate(found))
    random = next((r for o, r in found if o.pin_classes == 1 and o.roller_classes == 1), None)
    chosen = found[best][1] if best is not None else None
    coarser = {}
    if chosen is not None and random is not None:
        coarser = {g: (random.grades[g], v) for g, v in chosen.grades.items() if v > random.grades.get(g, v)}
    unit = (chosen or random).unit if (chosen or random) is not None else "relative"
    return ClassAllocationResult(problem.name, model, float(spec_arcmin), float(yield_target), unit,
                                 prices.measuring_cost_per_unit, prices.class_cost, prices.surplus_cost_share,
                                 options, options[best].selection if best is not None else None, coarser, chosen,
                                 random)
