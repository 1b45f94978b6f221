"""The thermal balance and what temperature does to the clearances (docs/efficiency.md; issue 40
items 4-5): the steady case temperature of a duty cycle, the time to reach it, the allowable duty
at the case limit; the parts' differential thermal expansion at a temperature, as changes of the
clearances the contact and elastic models read, and the nominal unit's lost motion and backlash
there.

*Heat balance.* The case is one lumped body at the oil's temperature (the oil, the parts and the
case alike: a small, full reducer): losses P(T) (the cycle's time-weighted mean of
``elements.element_losses`` at each step's torque and speed, the viscosity at T) = heat given off
Q(T) (``friction.housing_heat_flow_w``: convection, radiation, the mounting's conduction). P falls
and Q rises with T: one root. The time constant tau = C / (dQ/dT - dP/dT) at the root (the
linearised lumped body, ``friction.lumped_time_constant_s``). The allowable duty at the case limit:
the share of time f the cycle may run (idle, without losses, the rest) for the case to stay at the
limit: f = Q(T_lim) / P(T_lim) (>= 1: the cycle may run continuously).

*Expansion.* From the reference temperature (ISO 1: 20 degC) every part grows by its own
coefficient (``[thermal]``): the disc's profile is generated with r_p, r_rp and e, and grows with the
disc; the pin circle grows with the housing, the pins with theirs. Against the disc, the pin circle's
growth is a moving-distance modification of r_p (alpha_d - alpha_h) dT (positive: less clearance),
the pins' an equidistance modification r_rp (alpha_d - alpha_p) dT (positive: more clearance), the
pins in their housing holes' diametral clearance 2 r_rp (alpha_h - alpha_p) dT and the crank needle
bearings' clearance (alpha_d D_bore - alpha_c d_e - 2 alpha_n D_w) dT. Equal coefficients leave
every clearance as it was (to rounding: the clearances themselves scale by 1 + alpha dT; tested).
Not followed: the eccentricity's and the crank circle's mismatch (they would move the cranks'
phases against the disc's bores), the involute stage's centre distance, the bearings' preloads, the
rigidity and TE at temperature.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from rvbacklash.design.duty_cycle import DutyCycle
from rvbacklash.design.lubrication import ThermalInputs, housing_envelope
from rvbacklash.models import friction as fr
from rvbacklash.problem import Problem
from rvbacklash.results import Result

TEMPERATURE_TOLERANCE_K = 1e-6
HIGHEST_C = 400.0  # a steady temperature above this is reported as such (no root below)


@dataclass(frozen=True, repr=False)
class ClearanceChange(Result):
    """The clearances the models read, changed by the parts' expansion at a temperature [um]."""

    temperature_c: float
    moving_distance_modification_um: float  # added to the design's (positive: less clearance)
    equidistance_modification_um: float  # added to the design's (positive: more clearance)
    pin_hole_clearance_um: float  # added to the zone mean (diametral)
    crank_bearing_clearance_um: float  # added to the zone mean


def clearance_change(problem: Problem, thermal: ThermalInputs, temperature_c: float) -> ClearanceChange:
    """The ClearanceChange at a temperature (module docstring, "Expansion")."""
    d = problem.design
    s2 = d.second_stage
    dt = temperature_c - thermal.reference_temperature_c
    a_h, a_p, a_d = thermal.housing_expansion_per_k, thermal.pin_expansion_per_k, thermal.disc_expansion_per_k
    a_c, a_n = thermal.crank_expansion_per_k, thermal.needle_expansion_per_k
    moving = fr.thermal_growth_um(s2.pin_circle_radius_mm, a_d - a_h, dt)
    equidistance = fr.thermal_growth_um(s2.pin_radius_mm, a_d - a_p, dt)
    pin_hole = fr.thermal_growth_um(2.0 * s2.pin_radius_mm, a_h - a_p, dt)
    crank = 0.0
    e = d.elastic
    if e is not None:
        d_e = d.crank_stage.bearing_bore_mm
        d_w = e.crank_bearing_roller_diameter_mm
        crank = (fr.thermal_growth_um(d_e + 2.0 * d_w, a_d, dt) - fr.thermal_growth_um(d_e, a_c, dt)
                 - fr.thermal_growth_um(2.0 * d_w, a_n, dt))
    # the designed modifications themselves grow with the disc (equal coefficients: a uniform scaling)
    moving += s2.moving_distance_modification_um * a_d * dt
    equidistance += s2.equidistance_modification_um * a_d * dt
    return ClearanceChange(float(temperature_c), moving, equidistance, pin_hole, crank)


@dataclass(frozen=True, repr=False)
class PrecisionAtTemperature(Result):
    """The nominal unit's lost motion and backlash at a temperature (elastic model)."""

    temperature_c: float
    lost_motion_arcmin: float
    backlash_arcmin: float
    clearance: ClearanceChange


def precision_at_temperature(problem: Problem, model, thermal: ThermalInputs, temperature_c: float
                             ) -> PrecisionAtTemperature:
    """Lost motion and backlash of the nominal unit with its clearances at a temperature (its loop by the
    elastic model: ``PreparedUnit.figures``)."""
    from rvbacklash.factors.catalog import FACTOR_KEYS
    from rvbacklash.models.elastic import other_stages_nominal
    from rvbacklash.models.elastic.chain import BACKLASH, LOST_MOTION
    from rvbacklash.models.elastic.unit import PreparedUnit, unit_from_realization
    from rvbacklash.models.unit_errors import Realization

    c = clearance_change(problem, thermal, temperature_c)
    s2 = problem.design.second_stage
    pin_hole = float(problem.means_um[FACTOR_KEYS.index("pin_hole_clearance")]) + c.pin_hole_clearance_um
    r = Realization.nominal(problem.cycloid, s2.equidistance_modification_um + c.equidistance_modification_um,
                            s2.moving_distance_modification_um + c.moving_distance_modification_um, pin_hole, 0.0)
    inv, clr = other_stages_nominal(problem)
    unit = unit_from_realization(problem, r, inv, clr + c.crank_bearing_clearance_um)
    fig = PreparedUnit(model, unit).figures()
    return PrecisionAtTemperature(float(temperature_c), float(fig[LOST_MOTION]), float(fig[BACKLASH]), c)


@dataclass(frozen=True, repr=False)
class ThermalResult(Result):
    """A duty cycle's thermal balance (module docstring)."""

    duty_cycle: str
    ambient_c: float
    case_limit_c: float
    housing_diameter_mm: float
    housing_length_mm: float
    housing_area_m2: float
    heat_capacity_j_k: float
    steady_temperature_c: float
    loss_at_steady_w: float  # the cycle's mean loss at the steady temperature
    heat_conductance_w_k: float  # dQ/dT - dP/dT at the steady temperature
    time_constant_min: float
    allowable_duty_at_limit: float  # share of time the cycle may run for the case to stay at the limit (>= 1: always)
    loss_at_limit_w: float
    heat_at_limit_w: float
    precision: tuple[PrecisionAtTemperature, ...]  # at the reference temperature, the case limit, the steady one
    coefficients: dict

    def summary(self) -> list[str]:
        return [f"steady case temperature {self.steady_temperature_c:.1f} degC ({self.loss_at_steady_w:.1f} W), "
                f"time constant {self.time_constant_min:.0f} min",
                f"allowable duty at {self.case_limit_c:g} degC: {self.allowable_duty_at_limit:.0%}"]


def cycle_loss_w(lm, duty: DutyCycle, temperature_c: float) -> float:
    """The duty cycle's time-weighted mean power loss at an oil temperature [W] (a hold: none)."""
    total = 0.0
    for s in duty.steps:
        if s.output_speed_rpm > 0.0:
            total += s.time_share * lm.point(abs(s.output_torque_nm), s.output_speed_rpm, temperature_c).total_loss_w
    return total


def thermal_balance(lm, duty: DutyCycle, thermal: ThermalInputs | None = None) -> ThermalResult:
    """The ThermalResult of a duty cycle for a LossModel's unit (module docstring)."""
    from scipy.optimize import brentq

    problem = lm.problem
    th = thermal or problem.design.thermal
    s2 = problem.design.second_stage
    diameter, length, area, mass = housing_envelope(th, s2.pin_circle_radius_mm, s2.pin_radius_mm)
    cap = mass * th.specific_heat_j_kgk

    def heat(t: float) -> float:
        return fr.housing_heat_flow_w(t, th.ambient_c, area, th.convection_w_m2k, th.emissivity,
                                      th.flange_conductance_w_k)

    def gap(t: float) -> float:
        return heat(t) - cycle_loss_w(lm, duty, t)

    lo = th.ambient_c
    if gap(lo) >= 0.0:
        t_ss = lo  # no losses: the case stays at the ambient
    elif gap(HIGHEST_C) < 0.0:
        t_ss = math.inf
    else:
        t_ss = float(brentq(gap, lo, HIGHEST_C, xtol=TEMPERATURE_TOLERANCE_K))
    if math.isfinite(t_ss):
        h = 0.05
        g_th = (gap(t_ss + h) - gap(t_ss - h)) / (2.0 * h) if t_ss > lo else (gap(lo + h) - gap(lo)) / h
        tau = fr.lumped_time_constant_s(cap, g_th) / 60.0
        loss_ss = cycle_loss_w(lm, duty, t_ss)
    else:
        g_th, tau, loss_ss = math.nan, math.inf, math.nan
    loss_lim = cycle_loss_w(lm, duty, th.case_limit_c)
    heat_lim = heat(th.case_limit_c)
    duty_ok = heat_lim / loss_lim if loss_lim > 0.0 else math.inf
    temps = [th.reference_temperature_c, th.case_limit_c] + ([t_ss] if math.isfinite(t_ss) else [])
    precision = tuple(precision_at_temperature(problem, lm.model, th, t) for t in temps)
    coeffs = {"convection_w_m2k": th.convection_w_m2k, "emissivity": th.emissivity,
              "flange_conductance_w_k": th.flange_conductance_w_k, "specific_heat_j_kgk": th.specific_heat_j_kgk,
              "mass_kg": mass}
    return ThermalResult(duty.source, th.ambient_c, th.case_limit_c, diameter, length, area, cap, t_ss, loss_ss,
                         g_th, tau, duty_ok, loss_lim, heat_lim, precision, coeffs)


def with_equal_expansion(thermal: ThermalInputs, alpha_per_k: float) -> ThermalInputs:
    """The thermal inputs with every part's coefficient equal (the no-change check)."""
    return replace_model(thermal, housing_expansion_per_k=alpha_per_k, pin_expansion_per_k=alpha_per_k,
                         disc_expansion_per_k=alpha_per_k, crank_expansion_per_k=alpha_per_k,
                         needle_expansion_per_k=alpha_per_k, carrier_expansion_per_k=alpha_per_k)


def replace_model(m, **kw):
    return m.model_copy(update=kw)


__all__ = ["ClearanceChange", "clearance_change", "PrecisionAtTemperature", "precision_at_temperature",
           "ThermalResult", "thermal_balance", "cycle_loss_w", "with_equal_expansion"]
