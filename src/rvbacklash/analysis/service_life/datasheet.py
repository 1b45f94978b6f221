"""The service-life datasheet of a design (docs/service-life.md): the nominal unit's trajectory,
its contacts' wear rates at the start, its worn flank, and the production run (``production``)."""

from __future__ import annotations

import math
from typing import Callable

import numpy as np

from rvbacklash.analysis.service_life.production import production_life
from rvbacklash.analysis.service_life.rates import WearIncrement
from rvbacklash.analysis.service_life.results import ContactWearRate, FlankProfile, ServiceLifeResult
from rvbacklash.analysis.service_life.ripple import worn_ripple
from rvbacklash.analysis.service_life.stepping import DEFAULT_ANGLES, DEFAULT_STEP_FRACTION, check_hours, \
    nominal_trajectory
from rvbacklash.design.duty_cycle import DutyCycle
from rvbacklash.errors import InputError
from rvbacklash.models.elastic import elastic_model
from rvbacklash.problem import Problem

UNIT_WEAR = ("own", "nominal")  # the production run's units: their own wear, or the nominal unit's

SLIDING = {
    "cycloid flanks": "relative to the pins the disc turns about the pitch point P: |v| = |omega_disc| |P P_c|; "
                      "the flank takes (1 - pin_rolling_fraction) of it",
    "pins (flank side)": "the same sliding as the flank; spread round the pin when it turns, else at the normal's "
                         "direction",
    "pin seats": "the pin's surface turning in its groove: pin_rolling_fraction of the flank's relative sliding",
    "crank needle bearings": "needle_slip_fraction of the needles' rolling distance, pi d_m (1 - gamma^2) / 2 per "
                             "revolution of the rings (z_p per output revolution); clearance growth 2 w_i + 2 w_o + "
                             "4 w_r",
}


def _rates(rate: WearIncrement, geo) -> tuple[ContactWearRate, ...]:
    def row(name: str, values: np.ndarray, k: float) -> ContactWearRate:
        v = np.asarray(values, float).ravel() * 1e3
        pos = v[v > 0.0]
        return ContactWearRate(name, float(v.max(initial=0.0)), float(pos.mean()) if pos.size else 0.0, k,
                               SLIDING[name])

    pins = rate.pin_um[:, None] + rate.pin_local_um
    return (row("cycloid flanks", rate.flank_um, geo.k_flank), row("pins (flank side)", pins, geo.k_flank),
            row("pin seats", rate.seat_um, geo.k_seat),
            ContactWearRate("crank needle bearings", rate.clearance_max_um * 1e3, rate.clearance_um * 1e3,
                            geo.k_needle, SLIDING["crank needle bearings"] + " (rates: clearance growth, largest "
                                                                             "and mean bearing)"))


def service_life(problem: Problem, cycle: DutyCycle, hours, *, samples: int = 0, seed: int = 0,
                 spec_lost_motion_arcmin: float = 1.5, angles: int = DEFAULT_ANGLES,
                 step_fraction: float = DEFAULT_STEP_FRACTION, unit_wear: str = "own", sensitivity_samples: int = 0,
                 progress: Callable[[str, float], None] | None = None) -> ServiceLifeResult:
    """The ServiceLifeResult of a design under a duty cycle at ``hours`` (module docstring);
    ``samples`` units of the production run (0: none), each with its own wear (``unit_wear`` "own") or
    the nominal unit's ("nominal"; production.py). ``sensitivity_samples`` N > 0 (a power of two): the
    Sobol indices of the units' accuracy life, censored at the last hour, along the same trajectory
    (``sensitivity``; N (D + 2) units, seed ``seed``). ``progress(stage, share)``: stages "nominal",
    "units", "sensitivity"."""
    targets = check_hours(hours)
    if sensitivity_samples:
        from rvbacklash.analysis.sensitivity_global import check_samples

        try:
            check_samples(sensitivity_samples)
        except InputError as e:
            raise e.renamed("sensitivity_samples") from None
        if targets[-1] <= 0.0:
            raise InputError("hours", list(hours), "the accuracy life's Sobol indices need a last hour > 0")
        if unit_wear != "own":
            raise InputError("unit_wear", unit_wear, "the accuracy life's Sobol indices read each unit's own wear; "
                                                     "allowed with sensitivity: own")
    if not (isinstance(spec_lost_motion_arcmin, (int, float)) and math.isfinite(spec_lost_motion_arcmin)
            and spec_lost_motion_arcmin > 0.0):
        raise InputError("spec_lost_motion_arcmin", spec_lost_motion_arcmin, "allowed: a number > 0 [arcmin]")
    if not (isinstance(samples, int) and samples >= 0):
        raise InputError("samples", samples, "allowed: 0 (the nominal unit only) or a number of units >= 1")
    if unit_wear not in UNIT_WEAR:
        raise InputError("unit_wear", unit_wear, f"allowed: {', '.join(UNIT_WEAR)}")
    model = elastic_model(problem)
    tr = nominal_trajectory(problem, cycle, targets, angles=angles, step_fraction=step_fraction, model=model,
                            progress=(lambda s: progress("nominal", s)) if progress else None)
    points = tuple(p for p in tr.points if p.hours in targets)
    production = None
    if samples and not tr.partial:
        production = production_life(problem, tr, [p.hours for p in points], samples=samples, seed=seed,
                                     spec_lost_motion_arcmin=spec_lost_motion_arcmin, model=model,
                                     own_wear=unit_wear == "own", progress=(lambda n: progress("units", n / samples)) if progress else None)
    geo = tr.geometry
    profile = FlankProfile(tr.hours[-1], tuple(float(v) for v in np.degrees(geo.phase_rad)),
                           tuple(tuple(float(v) for v in d) for d in tr.wear[-1].flank_um))
    w = geo.inputs
    inputs = {**w.model_dump(), "k_flank_mm3_per_nm": geo.k_flank, "k_seat_mm3_per_nm": geo.k_seat,
              "k_needle_mm3_per_nm": geo.k_needle, "reference_clearance_um": tr.reference_clearance_um}
    te = tuple(worn_ripple(problem, h, w, geo) for h, w in zip(tr.hours, tr.wear) if h in targets)
    sobol = None
    if sensitivity_samples and not tr.partial and not (production is not None and production.partial):
        from rvbacklash.analysis.sensitivity_global import global_sensitivity
        from rvbacklash.analysis.service_life.sensitivity import accuracy_life_streams

        streams = accuracy_life_streams(problem, tr, spec_lost_motion_arcmin, model)
        runs = sensitivity_samples * (sum(streams.random) + 2)
        sobol = global_sensitivity(problem, model=streams, output="accuracy_life", samples=sensitivity_samples,
                                   seed=seed, progress=(lambda k: progress("sensitivity", k / runs)) if progress
                                   else None)
    partial = tr.partial or (production is not None and production.partial) or (sobol is not None and sobol.partial)
    return ServiceLifeResult(problem.design.name, cycle.source, cycle.mean_speed_rpm, angles, step_fraction,
                             len(tr.hours) - 1, inputs, points, tr.points, _rates(tr.initial_rate, geo), profile,
                             production, partial, te, sobol)
