"""The nominal unit through its service life (docs/service-life.md): time steps in which the wear
grows at the rates of the current, worn geometry, re-solved at every step.

Each step: the worn unit is prepared at K crank angles (``worn.WornAngles``), its loads solved at
every duty-cycle step's torque (``analysis.capacity.revolution_loads``), every contact's wear rate
per hour of the cycle summed over the cycle's steps (their time shares and speeds,
``rates.wear_per_revolution``); the step's length is bounded so that no contact wears more than
``step_fraction`` of the reference clearance (the nominal clearances in series at a pin: the flank's
equidistance modification, half the pin-hole clearance, half the crank bearings' clearance; at
least 1 um) and so that it ends on each requested hour. The wear coefficient's running-in multiplier
is integrated exactly over a step (``models.wear.running_in_hours``); the loads are explicit (the
rates of the step's start), which the step bound keeps small (tested: halving the steps moves the
6000 h lost motion by < 1 %).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from rvbacklash.analysis.capacity.revolution import load_geometry, needle_rollers, revolution_loads
from rvbacklash.analysis.service_life.rates import (WearGeometry, WearIncrement, wear_geometry,
                                                    wear_per_revolution)
from rvbacklash.analysis.service_life.results import LifePoint
from rvbacklash.analysis.service_life.worn import WornAngles, worn_model, worn_unit
from rvbacklash.design.duty_cycle import DutyCycle
from rvbacklash.design.wear import WearInputs
from rvbacklash.errors import InputError
from rvbacklash.factors.catalog import FACTOR_KEYS
from rvbacklash.interrupt import mark_progress, stop_requested
from rvbacklash.models import wear as wr
from rvbacklash.models.elastic import (BACKLASH, LOST_MOTION, RIGIDITY, ElasticModel, PreparedUnit, elastic_model,
                                       nominal_realization, other_stages_nominal)
from rvbacklash.models.unit_errors import Realization
from rvbacklash.problem import Problem

DEFAULT_ANGLES = 12  # crank angles per revolution of each step's loads
DEFAULT_STEP_FRACTION = 0.1  # the largest wear depth per step, as a share of the reference clearance
MAX_STEPS = 10_000
MAX_HOURS = 1e6


@dataclass(frozen=True, eq=False)
class Trajectory:
    """The nominal unit's path: its state and figures at every step's start (the last: the last hour)."""

    hours: tuple[float, ...]
    wear: tuple[WearIncrement, ...]  # accumulated at each time
    points: tuple[LifePoint, ...]
    initial_rate: WearIncrement  # per hour of the cycle at 0 h, steady coefficient
    geometry: WearGeometry
    reference_clearance_um: float
    partial: bool


def reference_clearance_um(problem: Problem) -> float:
    """The nominal clearances in series at a pin [um] (module docstring), at least 1 um."""
    s2 = problem.design.second_stage
    pin_hole = float(problem.means_um[FACTOR_KEYS.index("pin_hole_clearance")])
    _, crank = other_stages_nominal(problem)
    return max(1.0, s2.equidistance_modification_um + 0.5 * pin_hole + 0.5 * max(crank, 0.0))


def check_hours(hours) -> tuple[float, ...]:
    values = sorted({float(h) for h in hours})
    if not values or not all(math.isfinite(h) and 0.0 <= h <= MAX_HOURS for h in values):
        raise InputError("hours", list(hours), f"allowed: one or more numbers of hours from 0 to {MAX_HOURS:g}")
    return tuple(values)


def hourly_wear(angles: WornAngles, cycle: DutyCycle, geo: WearGeometry, load_geo, needles) -> tuple[WearIncrement,
                                                                                                      float]:
    """(every contact's wear per hour of the cycle with the steady coefficients, the largest pin
    pressure over the cycle's steps [MPa]) of a prepared (worn) unit."""
    total = WearIncrement.zero(geo.discs)
    stress = 0.0
    per_torque: dict[float, tuple[WearIncrement, float]] = {}
    for step in cycle.steps:
        if step.output_speed_rpm <= 0.0 or step.time_share <= 0.0:
            continue
        t = float(step.output_torque_nm)
        if t not in per_torque:
            loads = revolution_loads(angles, t, load_geo, needles)
            per_torque[t] = (wear_per_revolution(loads, geo), float(loads.pin_stress_mpa.max()))
        inc, s = per_torque[t]
        total = total.plus(inc.scaled(60.0 * step.output_speed_rpm * step.time_share))
        stress = max(stress, s)
    return total, stress


def nominal_trajectory(problem: Problem, cycle: DutyCycle, hours, *, angles: int = DEFAULT_ANGLES,
                       step_fraction: float = DEFAULT_STEP_FRACTION, wear: WearInputs | None = None,
                       realization: Realization | None = None, model: ElasticModel | None = None,
                       progress: Callable[[float], None] | None = None) -> Trajectory:
    """The nominal unit (or ``realization``, read with the tooth- and pin-averaged wear of its own
    loads) stepped to the last of ``hours`` (module docstring). ``wear``: the [wear] inputs (None:
    the design's); ``progress`` receives the share of the hours done."""
    targets = check_hours(hours)
    if not (isinstance(step_fraction, (int, float)) and 0.0 < step_fraction <= 1.0):
        raise InputError("step_fraction", step_fraction, "allowed: a number in (0, 1]")
    if problem.design.elastic is None:
        raise InputError("elastic", None, "the service life needs the design's [elastic] table (docs/elastic.md)")
    model = model or elastic_model(problem)
    geo = wear_geometry(problem, model, wear)
    inputs = geo.inputs
    needles = needle_rollers(model)
    inv, clr = other_stages_nominal(problem)
    r = realization if realization is not None else nominal_realization(problem)
    c_ref = reference_clearance_um(problem)
    bound = step_fraction * c_ref
    t, state = 0.0, WearIncrement.zero(geo.discs)
    times, states, points = [], [], []
    initial = None
    partial = False
    last = targets[-1]
    with stop_requested() as stop:
        while True:
            worn = WornAngles(problem, model, r, inv, clr, state, geo, angles)
            figures = PreparedUnit(worn.model, worn_unit(problem, r, inv, clr, state, geo)).figures()
            rate, stress = hourly_wear(worn, cycle, geo, load_geometry(problem, worn.model), needles)
            if initial is None:
                initial = rate
            times.append(t)
            states.append(state)
            points.append(_point(t, figures, state, stress))
            if progress is not None:
                progress(t / last if last > 0 else 1.0)
            mark_progress()
            if t >= last:
                break
            if stop.is_set() or len(times) >= MAX_STEPS:
                partial = True
                break
            nxt = next(h for h in targets if h > t)
            largest = rate.largest_depth_um()
            multiplier = 1.0 + (inputs.running_in_factor - 1.0) * math.exp(-t / inputs.running_in_hours)
            dt = bound / (largest * multiplier) if largest > 0.0 else math.inf
            end = nxt if t + dt >= nxt * (1.0 - 1e-12) else t + dt
            equivalent = wr.running_in_hours(t, end, inputs.running_in_factor, inputs.running_in_hours)
            state = state.plus(rate.scaled(equivalent))
            t = end
    return Trajectory(tuple(times), tuple(states), tuple(points), initial, geo, c_ref, partial)


def _point(t: float, figures: np.ndarray, state: WearIncrement, stress: float) -> LifePoint:
    return LifePoint(float(t), float(figures[LOST_MOTION]), float(figures[BACKLASH]), float(figures[RIGIDITY]),
                     float(state.flank_um.max(initial=0.0)),
                     float((state.pin_um[:, None] + state.pin_local_um + state.seat_um).max(initial=0.0)),
                     float(state.clearance_um), stress)
