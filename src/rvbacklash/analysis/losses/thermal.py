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
bearings' clearance (alpha_d D_bore - alpha_c d_e - 2 alpha_n D_w) dT, and (with [structure]) the
crank support bearings' radial clearance (alpha_carrier D_o - alpha_c d_i - 2 alpha_n D_w) dT, D_o and
d_i their outer and inner raceways (d_m +- D_w; the outer ring press-fitted follows the carrier's seat,
the rollers are the needles' steel): negative, a preload, when the steel journal and rollers outgrow
the iron carrier. Lengths are read in the disc's frame (over 1 + alpha_d dT, which leaves every angle as
it is): the disc's profile and its modifications stay as designed, only the other parts' growth against
the disc's is left, so equal coefficients change nothing (tested: clearances, lost motion, backlash,
rigidity and TE). Since heat40 also: the cranks' throw against the profile's eccentricity a (alpha_c -
alpha_d) dT (a crank eccentricity error), the carrier's crank circle against the discs' bores a0
(alpha_carrier - alpha_d) dT (every eccentric offset radially in its needle bearing: the tangential
clearance is the clearance circle's chord, ``friction.offset_clearance_um``), the involute stage's centre
distance a (alpha_carrier - alpha_gear) dT (its backlash by Eq. (1)'s transfer; an involute mesh's ratio,
so its TE, does not depend on it). These are a transformation of the unit (``unit_at_temperature``): the
nominal unit's lost motion, backlash, rigidity (the support bearings' preload, the crank bearings' load
zone) and TE at the temperature, and any unit's TE (``transmission_at_temperature``; the error-free
reference stays the design at the reference temperature). Not followed: the support pairs' axial
clearance along the crank's span (the arrangement, X or O, is not in the design: rv80e's 45 mm span and
1.5e-6 /K between crank and carrier give 2.7 um axially at 60 degC), the needle bearings' radial preload
once the crank circle has closed them (their dead band goes to 0, their stiffening is not followed), the
main bearings' preload, the parts' own errors scaling with them (um x 1e-3).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rvbacklash.design.duty_cycle import DutyCycle
from rvbacklash.design.lubrication import ThermalInputs, housing_envelope
from rvbacklash.models import friction as fr
from rvbacklash.models.unit_errors import Realization
from rvbacklash.problem import Problem
from rvbacklash.results import Result

TEMPERATURE_TOLERANCE_K = 1e-6
TE_POSITIONS_PER_PIN = 8  # the nominal unit's TE at a temperature on the production run's grid (8 z_p)
HIGHEST_C = 400.0  # a steady temperature above this is reported as such (no root below)


@dataclass(frozen=True, repr=False)
class ClearanceChange(Result):
    """The clearances the models read, changed by the parts' expansion at a temperature [um]."""

    temperature_c: float
    moving_distance_modification_um: float  # added to the design's (positive: less clearance)
    equidistance_modification_um: float  # added to the design's (positive: more clearance)
    pin_hole_clearance_um: float  # added to the zone mean (diametral)
    crank_bearing_clearance_um: float  # added to the zone mean
    support_bearing_clearance_um: float = 0.0  # added to the support bearings' (diametral; negative: a preload)
    crank_eccentricity_um: float = 0.0  # the cranks' throw against the profile's eccentricity (added to the error)
    crank_circle_um: float = 0.0  # the carrier's crank circle against the discs' bores (radial offset in each bore)
    centre_distance_um: float = 0.0  # the involute stage's centre distance against its gears (positive: apart)


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
    support = 0.0
    st = d.structure
    if st is not None:
        dm = st.support_bearing_pitch_diameter_mm or (
            0.5 * (st.crankshaft_diameter_mm + st.support_bearing_seat_diameter_mm)
            if st.support_bearing_seat_diameter_mm is not None else None)
        if dm is not None:
            d_w = st.support_bearing_roller_diameter_mm
            support = (fr.thermal_growth_um(dm + d_w, thermal.carrier_expansion_per_k, dt)
                       - fr.thermal_growth_um(dm - d_w, a_c, dt) - fr.thermal_growth_um(2.0 * d_w, a_n, dt))
    # Lengths are read in the disc's frame (every length over 1 + alpha_d dT; angles do not change with a
    # uniform scaling): the disc's profile, its modifications included, is as designed there, and only the
    # other parts' growth against the disc's is left. Equal coefficients: every change exactly 0.
    # The cranks' throw against the eccentricity the profile was generated with; the carrier's crank circle
    # against the discs' bores; the carrier's crank circle (the planets' axes) against the gears' own growth.
    geo = problem.geometry
    ecc = fr.thermal_growth_um(s2.eccentricity_mm, a_c - a_d, dt)
    circle = fr.thermal_growth_um(geo.crank_circle_radius_mm, thermal.carrier_expansion_per_k - a_d, dt)
    centre = fr.thermal_growth_um(geo.centre_distance_mm,
                                  thermal.carrier_expansion_per_k - thermal.gear_expansion_per_k, dt)
    return ClearanceChange(float(temperature_c), moving, equidistance, pin_hole, crank, support, ecc, circle, centre)


LOWEST_C, HIGHEST_INPUT_C = -40.0, 150.0  # a temperature a command accepts (as efficiency's)


def check_temperature(name: str, temperature_c) -> float:
    """A temperature [degC] as a command takes it, else the one-line error naming ``name``."""
    from rvbacklash.errors import InputError

    try:
        t = float(temperature_c)
    except (TypeError, ValueError):
        t = math.nan
    if isinstance(temperature_c, bool) or not (math.isfinite(t) and LOWEST_C <= t <= HIGHEST_INPUT_C):
        raise InputError(name, temperature_c, f"allowed: a temperature from {LOWEST_C:g} to {HIGHEST_INPUT_C:g} degC")
    return t


def unit_at_temperature(r: Realization, change: ClearanceChange) -> Realization:
    """A unit's cycloid-stage geometry at a temperature (module docstring, "Expansion"), in the disc's
    frame: its modifications, pin-hole clearances and crank eccentricity error changed by ``change``
    (the contact, elastic and transmission-error models read the result as they read any unit; the
    error-free reference stays the design at the reference temperature)."""
    return r.with_(moving_distance_um=np.asarray(r.moving_distance_um, float) + change.moving_distance_modification_um,
                   equidistance_um=np.asarray(r.equidistance_um, float) + change.equidistance_modification_um,
                   pin_clearance_um=np.asarray(r.pin_clearance_um, float) + change.pin_hole_clearance_um,
                   eccentricity_error_um=np.asarray(r.eccentricity_error_um, float) + change.crank_eccentricity_um)


def crank_clearance_at_temperature(clearance_um: float, change: ClearanceChange) -> float:
    """The crank needle bearings' clearance [um] at a temperature as the tangential dead band reads it: the
    bearing's own change, then the crank circle's offset across it (``friction.offset_clearance_um``: the
    carrier's crank circle against the discs' bores moves every eccentric radially in its bore, the same
    for all, so the disc stays centred and each bearing's tangential travel is the clearance circle's chord)."""
    return fr.offset_clearance_um(clearance_um + change.crank_bearing_clearance_um, change.crank_circle_um)


def other_stages_at_temperature(problem: Problem, change: ClearanceChange, crank_clearance_um: float
                                ) -> tuple[float, float]:
    """(involute stage's backlash change [arcmin], crank stage's change [arcmin]) at the output from the
    linear model's sensitivities (Eq. (1)): the centre distance's change (factor 2) and the crank
    bearings' clearance from ``crank_clearance_um`` to its value at the temperature (factor 20)."""
    from rvbacklash.factors.catalog import FACTOR_KEYS

    sens = problem.sensitivities_arcmin_per_um
    involute = float(sens[FACTOR_KEYS.index("centre_distance")]) * change.centre_distance_um
    crank = float(sens[FACTOR_KEYS.index("crank_bearing_clearance")]) * (
        crank_clearance_at_temperature(crank_clearance_um, change) - crank_clearance_um)
    return involute, crank


@dataclass(frozen=True, repr=False)
class PrecisionAtTemperature(Result):
    """The nominal unit's lost motion, backlash and rigidity at a temperature (elastic model)."""

    temperature_c: float
    lost_motion_arcmin: float
    backlash_arcmin: float
    clearance: ClearanceChange
    torsional_rigidity_nm_per_arcmin: float = float("nan")
    te_peak_to_peak_arcsec: float = float("nan")  # the nominal unit's TE there (against the reference's)
    crank_bearing_clearance_um: float = float("nan")  # the needle bearings' tangential clearance the loop reads


def precision_at_temperature(problem: Problem, model, thermal: ThermalInputs, temperature_c: float,
                             te_positions: int | None = None) -> PrecisionAtTemperature:
    """Lost motion, backlash and rigidity of the nominal unit with its clearances at a temperature (its loop
    by the elastic model: ``PreparedUnit.figures``; the support bearings' clearance change in its chain, the
    involute stage's backlash from its centre distance, the crank bearings' from the crank circle), and with
    ``te_positions`` its TE there (``transmission_at_temperature``, no shares)."""
    from dataclasses import replace
    from rvbacklash.factors.catalog import FACTOR_KEYS
    from rvbacklash.models.elastic import other_stages_nominal
    from rvbacklash.models.elastic.chain import BACKLASH, LOST_MOTION, RIGIDITY
    from rvbacklash.models.elastic.unit import PreparedUnit, unit_from_realization
    from rvbacklash.models.kinematics import perfect_unit
    from rvbacklash.units import ARCMIN_PER_RAD

    c = clearance_change(problem, thermal, temperature_c)
    s2 = problem.design.second_stage
    pin_hole = float(problem.means_um[FACTOR_KEYS.index("pin_hole_clearance")])
    r = unit_at_temperature(Realization.nominal(problem.cycloid, s2.equidistance_modification_um,
                                                s2.moving_distance_modification_um, pin_hole, 0.0), c)
    inv, clr = other_stages_nominal(problem)
    d_inv, _ = other_stages_at_temperature(problem, c, clr)
    clr_t = crank_clearance_at_temperature(clr, c)
    unit = unit_from_realization(problem, r, max(inv + d_inv / ARCMIN_PER_RAD, 0.0), clr_t)
    if c.support_bearing_clearance_um != 0.0 and model.chain.support_rollers > 0:
        model = replace(model, chain=model.chain._replace(
            support_clearance_um=model.chain.support_clearance_um + c.support_bearing_clearance_um))
    fig = PreparedUnit(model, unit).figures()
    te = float("nan")
    if te_positions:
        te = transmission_at_temperature(problem, perfect_unit(problem), c, te_positions, shares=False
                                         ).te_peak_to_peak_arcsec
    return PrecisionAtTemperature(float(temperature_c), float(fig[LOST_MOTION]), float(fig[BACKLASH]), c,
                                  float(fig[RIGIDITY]), te, float(clr_t))


def transmission_at_temperature(problem: Problem, r: Realization, change: ClearanceChange, positions: int,
                                load_direction: str = "ccw", shares: bool = True, label: str = "nominal",
                                other_stages_arcmin: float | None = None):
    """The transmission error of unit ``r`` with its parts at ``change``'s temperature
    (``analysis.transmission.transmission_error`` on ``unit_at_temperature``; TE against the error-free
    unit at the reference temperature, as the bench reads it against the ideal ratio): the cycloid stage's
    geometry from the expansion; the involute and crank stages' lost motion (``other_stages_arcmin``, or
    their linear means) changed by the centre distance and the crank bearings' clearance at the
    temperature. The involute stage's TE does not change with its centre distance (an involute mesh's
    ratio does not depend on it)."""
    from dataclasses import replace

    from rvbacklash.analysis.contact import linear_stage_means
    from rvbacklash.analysis.transmission import transmission_error

    clearance = r.crank_clearance_um if r.crank_clearance_um is not None else \
        float(problem.means_um[_factor("crank_bearing_clearance")])  # the unit's own (measured), else the zone's
    d_inv, d_crank = other_stages_at_temperature(problem, change, float(clearance))
    other = float(sum(linear_stage_means(problem)[0].values())) if other_stages_arcmin is None else \
        float(other_stages_arcmin)
    result = transmission_error(problem, unit_at_temperature(r, change), f"{label} at {change.temperature_c:g} degC",
                                positions, load_direction, shares,
                                other_stages_arcmin=max(other + d_inv + d_crank, 0.0))
    source = "linear means" if other_stages_arcmin is None else "given"
    return replace(result, temperature_c=float(change.temperature_c),
                   other_stages_from=f"{source}, at {change.temperature_c:g} degC")


def _factor(key: str) -> int:
    from rvbacklash.factors.catalog import FACTOR_KEYS

    return FACTOR_KEYS.index(key)


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
    te_positions = TE_POSITIONS_PER_PIN * problem.cycloid.zp  # the production run's grid (8 z_p)
    precision = tuple(precision_at_temperature(problem, lm.model, th, t, te_positions) for t in temps)
    coeffs = {"convection_w_m2k": th.convection_w_m2k, "emissivity": th.emissivity,
              "flange_conductance_w_k": th.flange_conductance_w_k, "specific_heat_j_kgk": th.specific_heat_j_kgk,
              "mass_kg": mass}
    return ThermalResult(duty.source, th.ambient_c, th.case_limit_c, diameter, length, area, cap, t_ss, loss_ss,
                         g_th, tau, duty_ok, loss_lim, heat_lim, precision, coeffs)


def with_equal_expansion(thermal: ThermalInputs, alpha_per_k: float) -> ThermalInputs:
    """The thermal inputs with every part's coefficient equal (the no-change check)."""
    return replace_model(thermal, housing_expansion_per_k=alpha_per_k, pin_expansion_per_k=alpha_per_k,
                         disc_expansion_per_k=alpha_per_k, crank_expansion_per_k=alpha_per_k,
                         needle_expansion_per_k=alpha_per_k, carrier_expansion_per_k=alpha_per_k,
                         gear_expansion_per_k=alpha_per_k)


def replace_model(m, **kw):
    return m.model_copy(update=kw)


__all__ = ["ClearanceChange", "clearance_change", "PrecisionAtTemperature", "precision_at_temperature",
           "unit_at_temperature", "crank_clearance_at_temperature", "other_stages_at_temperature",
           "transmission_at_temperature",
           "ThermalResult", "thermal_balance", "cycle_loss_w", "with_equal_expansion"]
