"""Calibration of the wear coefficients from a unit measured over time (docs/service-life.md): the
lost motion read at 0 h and after t h of a known duty cycle (twice or more: e.g. from the
``bench`` command's loops) scales every contact's wear coefficient by one factor s (k = s k_design),
fitted with a 95 % interval.

The model's growth of lost motion dLM(t; s) = LM(t; s) - LM(0) (the nominal unit stepped through the
cycle, ``stepping.nominal_trajectory``) is computed at a grid of s (SCALE_GRID, geometric) and
interpolated in ln s (monotone cubic); the measured growths d_i = LM_i - LM_0 are fitted by least
squares: the deviance -2 ln L = sum_i (d_i - dLM(t_i; s))^2 / (2 sigma^2) (each growth is the
difference of two readings of repeatability sigma); the 95 % interval is where the deviance exceeds
its minimum by at most chi^2_1(0.95) = 3.84 (the profile likelihood's region for one parameter). The
unit's own errors move its lost motion at 0 h; its growth is read as the nominal unit's (the
production run's shortcut).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rvbacklash.analysis.service_life.stepping import nominal_trajectory
from rvbacklash.design.duty_cycle import DutyCycle
from rvbacklash.design.wear import WearInputs
from rvbacklash.errors import InputError
from rvbacklash.models.elastic import elastic_model
from rvbacklash.problem import Problem
from rvbacklash.results import Result

SCALE_GRID = np.geomspace(1.0 / 16.0, 16.0, 9)  # s: the design's coefficients times 1/16 ... 16
CHI2_95 = 3.841458820694124  # chi^2 with one degree of freedom, 95 %


@dataclass(frozen=True, repr=False)
class WearCalibration(Result):
    """The wear coefficients' common scale fitted to a unit's lost motion over time."""

    scale: float  # s: k = s k_design
    scale_ci95_low: float  # 0 / inf: the interval reaches the grid's end (the data do not bound it)
    scale_ci95_high: float
    k_flank_mm3_per_nm: float
    k_seat_mm3_per_nm: float
    k_needle_mm3_per_nm: float
    measured_hours: tuple[float, ...]
    measured_growth_arcmin: tuple[float, ...]
    fitted_growth_arcmin: tuple[float, ...]
    sigma_arcmin: float

    def summary(self) -> list[str]:
        return [f"wear coefficients x {self.scale:.3g} [{self.scale_ci95_low:.3g}, {self.scale_ci95_high:.3g}] (95 %)",
                f"k_flank {self.k_flank_mm3_per_nm:.3g} mm^3/(N m)"]


def scaled_inputs(inputs: WearInputs, scale: float) -> WearInputs:
    """The [wear] inputs with every coefficient times ``scale``."""
    return inputs.model_copy(update={f"{c}_wear_coefficient": getattr(inputs, f"{c}_wear_coefficient") * scale
                                     for c in ("flank", "seat", "needle")})


def growth_curves(problem: Problem, cycle: DutyCycle, hours, scales=SCALE_GRID, step_fraction: float = 0.1,
                  angles: int = 12) -> np.ndarray:
    """(len(scales), len(hours)): the nominal unit's lost-motion growth [arcmin] at ``hours`` with the
    coefficients scaled by each s."""
    model = elastic_model(problem)
    base = problem.design.wear
    out = np.empty((len(scales), len(hours)))
    for i, s in enumerate(scales):
        tr = nominal_trajectory(problem, cycle, [0.0, *hours], angles=angles, step_fraction=step_fraction,
                                wear=scaled_inputs(base, float(s)), model=model)
        lm = {p.hours: p.lost_motion_arcmin for p in tr.points}
        out[i] = [lm[float(h)] - lm[0.0] for h in hours]
    return out


def calibrate_wear(problem: Problem, cycle: DutyCycle, measurements, *, sigma_arcmin: float = 0.01,
                   step_fraction: float = 0.1, angles: int = 12) -> WearCalibration:
    """Fit the wear coefficients' scale s to ``measurements``: (hours, lost motion [arcmin]) pairs of one
    unit under ``cycle``, the first at 0 h (module docstring); ``sigma_arcmin``: the repeatability of
    one reading."""
    from scipy.interpolate import PchipInterpolator

    pairs = sorted((float(h), float(v)) for h, v in measurements)
    if len(pairs) < 2 or pairs[0][0] != 0.0 or any(not (math.isfinite(h) and math.isfinite(v)) for h, v in pairs):
        raise InputError("measurements", list(measurements), "allowed: two or more (hours, lost motion [arcmin]) "
                                                              "pairs of finite numbers, the first at 0 h")
    if not (math.isfinite(sigma_arcmin) and sigma_arcmin > 0.0):
        raise InputError("sigma_arcmin", sigma_arcmin, "allowed: a number > 0")
    hours = [h for h, _ in pairs[1:]]
    measured = np.array([v - pairs[0][1] for _, v in pairs[1:]])
    curves = growth_curves(problem, cycle, hours, step_fraction=step_fraction, angles=angles)
    log_s = np.log(SCALE_GRID)
    fine = np.linspace(log_s[0], log_s[-1], 4001)
    model = np.stack([PchipInterpolator(log_s, curves[:, j])(fine) for j in range(len(hours))], axis=1)
    deviance = ((measured[None, :] - model) ** 2).sum(axis=1) / (2.0 * sigma_arcmin ** 2)
    best = int(np.argmin(deviance))
    inside = np.nonzero(deviance - deviance[best] <= CHI2_95)[0]
    lo = 0.0 if inside[0] == 0 else float(np.exp(fine[inside[0]]))
    hi = math.inf if inside[-1] == fine.size - 1 else float(np.exp(fine[inside[-1]]))
    s = float(np.exp(fine[best]))
    w = scaled_inputs(problem.design.wear, s)
    from rvbacklash.models.wear import dimensional_wear_coefficient as k_of

    return WearCalibration(s, lo, hi, k_of(w.flank_wear_coefficient, w.hardness_hv),
                           k_of(w.seat_wear_coefficient, w.hardness_hv), k_of(w.needle_wear_coefficient, w.hardness_hv),
                           tuple(hours), tuple(float(v) for v in measured), tuple(float(v) for v in model[best]),
                           float(sigma_arcmin))
