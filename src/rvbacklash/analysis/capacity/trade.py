"""The trade made visible (docs/capacity.md, "The trade: lost motion against life"): the nominal
unit's lost motion (the hysteresis loop) beside its life and derived rated torque (the capacity
computation), for the design as given and for what-ifs of it — a crank-bearing clearance or
preload, an equidistance modification, any design edit.

A what-if is a set of design edits (dotted paths of the design file and their values, as a sweep's
parameters and the workbench's edits name them); each one is prepared as its own design, and its
point computed as the design's own: the loop by ``hysteresis.hysteresis``, the lives and the rated
torque by ``UnitCapacity`` at ``angles`` crank angles.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Iterable, Mapping

from rvbacklash.analysis.capacity.revolution import DEFAULT_ANGLES
from rvbacklash.analysis.capacity.unit import UnitCapacity
from rvbacklash.design.loading import design_from_dict
from rvbacklash.design.sweep_spec import with_values
from rvbacklash.errors import InputError
from rvbacklash.factors.catalog import FACTOR_KEYS
from rvbacklash.models.elastic import elastic_model, nominal_realization, other_stages_nominal
from rvbacklash.problem import Problem, prepare
from rvbacklash.results import Result

CLEARANCE = "factors.crank_bearing_clearance"
MODIFICATION = "second_stage.equidistance_modification_um"
# the what-ifs of docs/capacity.md's table: the crank needle bearings' radial clearance (negative: a
# preload) and the cycloid's equidistance modification [um]; one equal to the design's own is left out
CLEARANCES_UM = (-4.0, 0.0, 10.0, 20.0)
MODIFICATIONS_UM = (0.0, 2.0, 10.0)
MAX_WHAT_IFS = 32


@dataclass(frozen=True)
class WhatIf:
    """A named what-if: design edits by dotted path (``{"second_stage.equidistance_modification_um": 2.0}``)."""

    name: str
    edits: Mapping[str, float | int | str | bool]
    family: str = "edit"  # clearance | modification | edit: the figure joins a family's points


def clearance_what_if(clearance_um: float) -> WhatIf:
    """The crank needle bearings' radial clearance fixed at a value [um] (negative: a preload): the
    factor's zone read as a fixed value, which the nominal unit takes as its clearance."""
    c = float(clearance_um)
    name = f"crank bearings preloaded {-c:g} um" if c < 0 else (
        "crank bearings line to line" if c == 0 else f"crank-bearing clearance {c:g} um")
    return WhatIf(name, {f"{CLEARANCE}.distribution": "fixed", f"{CLEARANCE}.value_um": c,
                         f"{CLEARANCE}.lower_um": c, f"{CLEARANCE}.upper_um": c}, "clearance")


def modification_what_if(modification_um: float) -> WhatIf:
    """The cycloid's equidistance modification set to a value [um]."""
    return WhatIf(f"equidistance modification {float(modification_um):g} um", {MODIFICATION: float(modification_um)},
                  "modification")


def default_what_ifs(problem: Problem) -> list[WhatIf]:
    """The what-ifs of docs/capacity.md's table (CLEARANCES_UM, MODIFICATIONS_UM), less those equal
    to the design's own clearance (its zone mean) or modification."""
    own_clearance = float(problem.means_um[FACTOR_KEYS.index("crank_bearing_clearance")])
    own_modification = float(problem.design.second_stage.equidistance_modification_um)
    return ([clearance_what_if(c) for c in CLEARANCES_UM if abs(c - own_clearance) > 1e-9]
            + [modification_what_if(m) for m in MODIFICATIONS_UM if abs(m - own_modification) > 1e-9])


@dataclass(frozen=True, repr=False)
class TradePoint(Result):
    """One design's (or what-if's) nominal unit: its lost motion beside its life."""

    name: str
    family: str  # design | clearance | modification | edit
    edits: dict
    crank_clearance_um: float  # the nominal unit's (negative: a preload)
    equidistance_modification_um: float
    lost_motion_arcmin: float
    backlash_arcmin: float
    torsional_rigidity_nm_per_arcmin: float
    reducer_life_h: float  # at the stated rated torque and the rated output speed
    weakest_bearing: str
    weakest_bearing_life_h: float
    derived_rated_torque_nm: float  # the reducer's L10 = the rated life at the rated output speed
    max_pin_force_n: float  # over the revolution, at the stated rated torque
    max_pin_stress_mpa: float


@dataclass(frozen=True, repr=False)
class CapacityTrade(Result):
    """Lost motion against life of a design and its what-ifs (module docstring); ``points[0]`` is the
    design as given."""

    design_name: str
    life_method: str
    crank_angles: int
    stated_rated_torque_nm: float
    rated_life_h: float
    rated_output_speed_rpm: float
    points: tuple[TradePoint, ...]
    partial: bool = False

    @property
    def design(self) -> TradePoint:
        return self.points[0]

    def summary(self) -> list[str]:
        d = self.design
        return [f"{self.design_name}: {len(self.points)} points; the design: lost motion "
                f"{d.lost_motion_arcmin:.4g} arcmin, "
                f"L10 {d.reducer_life_h:.4g} h at {self.stated_rated_torque_nm:g} N m, "
                f"derived rated torque {d.derived_rated_torque_nm:.4g} N m"]

    def rows(self) -> list[dict]:
        """One row per point (its edits as text)."""
        out = []
        for p in self.points:
            row = p.to_dict()
            row["edits"] = "; ".join(f"{k} = {v}" for k, v in p.edits.items())
            out.append(row)
        return out


def _edited(problem: Problem, what_if: WhatIf) -> Problem:
    if not what_if.edits:
        return problem
    data = problem.design.model_dump(exclude_none=True)
    if CLEARANCE + ".distribution" in what_if.edits:  # a fixed clearance replaces the factor's whole zone
        data.get("factors", {}).pop("crank_bearing_clearance", None)
    paths = tuple(what_if.edits)
    try:
        design = design_from_dict(with_values(data, paths, tuple(what_if.edits[p] for p in paths)))
    except InputError as e:
        raise InputError(f"what_if '{what_if.name}'", e.value, f"{e.field}: {e.allowed}") from None
    return prepare(design)


def trade_point(problem: Problem, what_if: WhatIf | None = None, *, angles: int = DEFAULT_ANGLES,
                life_method: str | None = None) -> TradePoint:
    """The TradePoint of a design (``what_if`` None) or of a what-if of it (module docstring)."""
    from rvbacklash.analysis.hysteresis import hysteresis

    what_if = what_if or WhatIf("the design", {}, "design")
    p = _edited(problem, what_if)
    model = elastic_model(p)
    if model.structure is None:
        raise InputError("structure", None, "the capacity ratings need the design's [structure] table (the "
                                            "crankshafts and their support bearings; docs/capacity.md)")
    loop = hysteresis(p)
    inv, clr = other_stages_nominal(p)
    unit = UnitCapacity(p, model, nominal_realization(p), inv, clr, angles, life_method)
    n0 = p.design.capacity.rated_output_speed_rpm
    t_r = unit.rated_torque_nm
    lives = unit.lives(t_r, n0)
    weakest = min(lives, key=lambda b: b.l10_h)
    loads = unit.loads(t_r)
    return TradePoint(what_if.name, what_if.family, dict(what_if.edits), clr,
                      float(p.design.second_stage.equidistance_modification_um), loop.lost_motion_arcmin,
                      loop.backlash_arcmin, loop.torsional_rigidity_nm_per_arcmin, unit.life_h(t_r, n0), weakest.name,
                      weakest.l10_h, unit.rated_torque(), float(loads.pin_force_n.max()),
                      float(loads.pin_stress_mpa.max()))


def capacity_trade(problem: Problem, what_ifs: Iterable[WhatIf] | None = None, *, angles: int = DEFAULT_ANGLES,
                   life_method: str | None = None, progress: Callable[[int], None] | None = None) -> CapacityTrade:
    """The design's TradePoint and its what-ifs' (``what_ifs``; None: ``default_what_ifs``, () : the
    design alone). ``progress(done)``: points finished. A Ctrl-C (or a stop) ends it with the points
    done, marked partial."""
    from rvbacklash.interrupt import check_abandoned, stop_requested

    todo = default_what_ifs(problem) if what_ifs is None else list(what_ifs)
    if len(todo) > MAX_WHAT_IFS:
        raise InputError("what_ifs", len(todo), f"allowed: at most {MAX_WHAT_IFS} what-ifs")
    for w in todo:
        if not isinstance(w, WhatIf) or not w.edits:
            raise InputError("what_ifs", getattr(w, "name", w), "allowed: WhatIf items with at least one edit")
    cap = problem.design.capacity
    points: list[TradePoint] = []
    partial = False
    with stop_requested() as stop:
        for w in [None, *todo]:
            if stop.is_set():  # a Ctrl-C between points: the points done, marked partial
                partial = True
                break
            check_abandoned()  # the workbench's cancel: nobody wants the rest
            points.append(trade_point(problem, w, angles=angles, life_method=life_method))
            if progress is not None:
                progress(len(points))
    if not points:
        raise InputError("what_ifs", None, "interrupted before the design's own point was computed")
    method = life_method or cap.life_method
    return CapacityTrade(problem.design.name, method, int(angles), float(elastic_model(problem).chain.rated_torque_nm),
                         float(cap.rated_life_h), float(cap.rated_output_speed_rpm), tuple(points), partial)

