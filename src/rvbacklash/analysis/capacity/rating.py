"""The capacity and life datasheet of a design's nominal unit (``rvbacklash capacity``;
docs/capacity.md): every bearing's load, rating and L10 at the stated rated torque and the rated
output speed, the reducer's life, the derived rated torque beside the stated one, the momentary
maximum torque with its limiting element, the allowable acceleration torque, the main bearings'
moment rigidity and allowable moment, and a duty cycle's life.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from rvbacklash.analysis.capacity.duty import DutyCycleLife, duty_cycle_life
from rvbacklash.analysis.capacity.life import BearingLife, bearing_speed_rpm
from rvbacklash.analysis.capacity.main_bearings import MainBearingRating, main_bearing_rating
from rvbacklash.analysis.capacity.revolution import DEFAULT_ANGLES, RevolutionLoads
from rvbacklash.analysis.capacity.unit import StaticLimit, UnitCapacity
from rvbacklash.design.duty_cycle import DutyCycle
from rvbacklash.design.structure import has_main_bearings
from rvbacklash.errors import InputError
from rvbacklash.models.elastic import elastic_model, nominal_realization, other_stages_nominal
from rvbacklash.problem import Problem
from rvbacklash.results import EXPORT, Result

LIFE_METHODS = ("iso16281", "iso281")


@dataclass(frozen=True, repr=False)
class StaticLimitRow(Result):
    """An element's static load against its limit at a torque (ratio 1: the limit)."""

    element: str
    value: float
    limit: float
    ratio: float
    criterion: str


@dataclass(frozen=True, repr=False)
class CapacityResult(Result):
    """A design's capacity and life figures (module docstring), for its nominal unit."""

    design_name: str
    unit: str
    life_method: str
    crank_angles: int
    rated_life_h: float
    rated_output_speed_rpm: float
    bearing_speed_rpm: float  # the crank bearings' speed at the rated output speed (z_p times it)
    stated_rated_torque_nm: float  # [elastic] rated_torque_nm
    bearings: tuple[BearingLife, ...]  # at the stated rated torque and the rated output speed
    reducer_life_h: float  # the system of the bearings at the stated rated torque and rated speed
    weakest_bearing: str
    weakest_bearing_life_h: float
    derived_rated_torque_nm: float  # the reducer's L10 = rated life at the rated output speed
    life_at_derived_rated_torque_h: float  # equals rated_life_h (the consistency of the root)
    derived_rated_torque_by_method_nm: dict[str, float]  # iso16281 and iso281 side by side
    momentary_maximum_torque_nm: float
    limiting_element: str
    static_limits_at_momentary: tuple[StaticLimitRow, ...]
    static_limits_at_rated: tuple[StaticLimitRow, ...]
    allowable_acceleration_torque_nm: float
    acceleration_rule: str
    max_pin_force_n: float  # at the stated rated torque, over the revolution
    max_pin_stress_mpa: float
    needle_load_range_n: tuple[float, float]  # the crank needle bearings' smallest and largest load over the revolution
    crank_torque_share_range: tuple[float, float]
    main_bearings: MainBearingRating | None
    duty_cycle: DutyCycleLife | None
    loads: RevolutionLoads = field(metadata={EXPORT: True})

    def summary(self) -> list[str]:
        return [f"{self.design_name}: reducer L10 {self.reducer_life_h:.4g} h at {self.stated_rated_torque_nm:g} N m, "
                f"{self.rated_output_speed_rpm:g} r/min",
                f"derived rated torque {self.derived_rated_torque_nm:.4g} N m (stated {self.stated_rated_torque_nm:g})",
                f"momentary maximum {self.momentary_maximum_torque_nm:.4g} N m ({self.limiting_element})"]

    def rows(self) -> list[dict]:
        """One row per bearing (its ratings, loads and lives)."""
        return [b.to_dict() for b in self.bearings]


def _rows(limits: list[StaticLimit]) -> tuple[StaticLimitRow, ...]:
    return tuple(StaticLimitRow(s.element, s.value, s.limit, s.ratio, s.criterion) for s in limits)


def capacity_rating(problem: Problem, *, angles: int = DEFAULT_ANGLES, duty_cycle: DutyCycle | None = None,
                    life_method: str | None = None) -> CapacityResult:
    """The CapacityResult of a prepared design's nominal unit (module docstring). ``angles``: crank
    angles per revolution; ``life_method``: overrides [capacity] life_method."""
    if life_method is not None and life_method not in LIFE_METHODS:
        raise InputError("life_method", life_method, f"allowed: {', '.join(LIFE_METHODS)}")
    model = elastic_model(problem)
    if model.structure is None:
        raise InputError("structure", None, "the capacity ratings need the design's [structure] table (the "
                                            "crankshafts and their support bearings; docs/capacity.md)")
    inv, clr = other_stages_nominal(problem)
    unit = UnitCapacity(problem, model, nominal_realization(problem), inv, clr, angles, life_method)
    cap = problem.design.capacity
    t_r, n0 = unit.rated_torque_nm, cap.rated_output_speed_rpm
    lives = unit.lives(t_r, n0)
    life = unit.life_h(t_r, n0)
    weakest = min(lives, key=lambda b: b.l10_h)
    by_method = {m: unit.rated_torque(method=m) for m in LIFE_METHODS}
    t0 = by_method[unit.method]
    t_max, limiting, at_max = unit.momentary_maximum()
    t_acc = cap.acceleration_torque_fraction * t_max
    rule = (f"{cap.acceleration_torque_fraction:g} x the momentary maximum torque (the RV-E catalogues' 2.5 T0 / 5 T0: "
            f"a static safety of {1 / cap.acceleration_torque_fraction:g} against the first static limit)")
    loads = unit.loads(t_r)
    main = None
    if has_main_bearings(model.structure):
        main = main_bearing_rating(model.structure, cap.rated_life_h, n0, cap.main_bearing_static_safety)
    duty = None
    if duty_cycle is not None:
        duty = duty_cycle_life(unit, duty_cycle, t0, t_acc, t_max, main.allowable_moment_nm if main else None)
    shares = loads.crank_torque_shares
    needle = loads.crank_bearing_load_magnitude_n
    return CapacityResult(
        problem.design.name, "nominal", unit.method, int(angles), cap.rated_life_h, n0, bearing_speed_rpm(model, n0), t_r,
        tuple(lives), life, weakest.name, weakest.l10_h, t0, unit.life_h(t0, n0), by_method, t_max, limiting,
        _rows(at_max), _rows(unit.static_limits(t_r)), t_acc, rule, float(loads.pin_force_n.max()),
        float(loads.pin_stress_mpa.max()), (float(needle.min()), float(needle.max())),
        (float(shares.min()), float(shares.max())), main, duty, loads)
