"""Kinematics of one unit over a full output revolution: angular transmission error and the
rigid lost motion at every output position (docs/transmission-error.md).

The output (carrier) turns by theta in N equal steps; the crank eccentric of disc 0 is then at
chi = chi_0 - z_c theta in the housing frame (fixed pins, z_p = z_c + 1), every disc tooth and
housing pin indexed as they meet (the contact model's ``pin_frame`` numbering). At each position
the contact model (``models.contact.stage_play``) finds the output rotation at which each flank
first touches, on the exact geometry, with the unit's errors placed where they are at that
position:

- errors fixed in the housing (pin radii, pin positions, hole clearances) and per tooth space
  (cumulative pitch) as drawn, indexed by the contact model;
- errors fixed in the disc or the carrier (the disc's profile run-out, the crank-hole position
  errors) turn with the output: their components along / across the eccentric rotate by
  -(chi - chi_0) z_p / z_c;
- the involute stage turns each crank by d chi_k (centre-gear and planet eccentricities,
  ``crank_angle_errors``); their mean moves the discs along the crank circle (an offset a d chi
  across the eccentric), their differences turn the discs against the carrier;
- the over-constraint of the cranks: each disc sits on P eccentrics through P holes. It takes
  the rigid placement that fits the P eccentric centres best (least squares: translation = mean
  misfit, rotation = sum H_k x misfit_k / (P R_c^2)); the needle-bearing clearances are assumed to
  absorb the residual misfits (``crank_fit``). SIMPLIFIED: no elastic wind-up of a crank that
  cannot follow, the residual is not checked against the clearance.

Output angles follow the project's Eq. (1) convention (a disc rotation is the output rotation,
as in ``models.contact``); the exact kinematic factor 1 / (1 + (z1 + z2) / (z2 z_c)) of Yang
et al. (2021) Eq. (30) (0.969 for rv80e) is not applied, so that the lost motion here equals
the contact model's play at the same crank angle.

TE of a flank = the output's position with that flank in contact minus the same flank's
position in the error-free unit of the same design (so perfect parts give TE = 0 exactly; the
designed modifications' own order-z_c z_p ripple is part of the
nominal unit: 0.070 arcsec peak-to-peak for rv80e, reported as ``nominal_ripple_arcsec``).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from rvbacklash._numba import njit
from rvbacklash.factors.catalog import FACTOR_KEYS
from rvbacklash.geometry.cycloid import ContactGeometry
from rvbacklash.models.contact import (CANG, CCHI, CPSI, EUX, EUY, N_COEF, OX, OY, RHO, RHO_TIGHT_MM, SANG, SCHI, SIDE,
                                      SPSI, T0, TOOTH, PinGaps, StageWork, _lowest_gaps, free_interval_bounds,
                                      mesh_column_at, mesh_pin_angles, mesh_table, pin_base_um, pin_gaps, stage_play,
                                      stage_work, turned_gap)
from rvbacklash.models.unit_errors import Realization, unit_errors, with_disc_errors
from rvbacklash.problem import Problem
from rvbacklash.units import ARCMIN_PER_RAD

ARCSEC_PER_RAD = 648000.0 / math.pi
DEFAULT_POSITIONS = 1024  # output positions per revolution of one unit's curve: orders up to 512
# output positions per mesh table at most: a revolution of more positions is solved a table at a time
# (a table holds N_COEF values per pin and disc: 2048 positions of rv80e are 18 MB, and building it
# takes about twice that; 65 536 positions in one table took 2 GB)
TABLE_POSITIONS = 2048


class Kinematics(NamedTuple):
    """What the kinematic model needs of a design besides the contact geometry."""

    ratio: float
    base_radius_mm: float  # r_b2 of the planet gears
    crank_radius_mm: float  # R_c, the circle of crank axes
    planets: int


class PositionTable(NamedTuple):
    """The output positions of one revolution (output_positions) and the contact model's
    mesh_table at each (``position_table``)."""

    theta_rad: np.ndarray  # (N,) output angle
    chi_rad: np.ndarray  # (N,) crank angle of disc 0
    coef: np.ndarray  # (N, N_COEF, discs, z_p)


class HousingPins(NamedTuple):
    """What of a unit's pins does not change as the output turns (unit_pins), (z_p) each."""

    x_mm: np.ndarray  # each pin's centre in the housing frame
    y_mm: np.ndarray
    base_um: np.ndarray  # its gap's constant part -rho + cl / 2


class CurveScratch(NamedTuple):
    """te_curve's scratch (curve_scratch): the unit's disc errors placed at one output position,
    the cranks' angle errors, the pins' gaps and the contact model's work, the housing's pins, the
    discs' placement on the cranks (crank_fit)."""

    tooth_pitch_um: np.ndarray  # (discs, z_c)
    runout_along_um: np.ndarray  # (discs)
    runout_across_um: np.ndarray  # (discs)
    crank_angle_rad: np.ndarray  # (planets)
    gaps: PinGaps
    work: StageWork
    pins: HousingPins
    shift_um: np.ndarray  # (discs, 2)
    turn_rad: np.ndarray  # (discs)


class FlankCurve(NamedTuple):
    """Both flanks' output positions [rad] at every output position and the preload [um] (te_curve);
    when asked (``gap_um`` of as many rows as positions; else 0 rows), every pin's linearised gap
    [um] and lever [um/rad] there, (N, discs, z_p) each (PinGaps at each position: what
    step_extremes interpolates between the positions)."""

    ccw_rad: np.ndarray
    cw_rad: np.ndarray
    preload_um: np.ndarray
    gap_um: np.ndarray
    lever_um_per_rad: np.ndarray


def output_positions(g: ContactGeometry, positions: int, chi0_rad: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """(theta [rad], chi [rad]) of ``positions`` equal steps of one output revolution from the
    reference position theta = 0 (crank angle chi_0): chi = chi_0 - z_c theta."""
    theta = 2.0 * math.pi * np.arange(positions) / positions
    return theta, chi0_rad - g.zc * theta


@njit(nogil=True, cache=True)
def crank_fit(hole_disc_um, hole_carrier_um, crank_radius_mm, shift_um, turn_rad):
    """Rigid placement of each disc on the P eccentrics (module docstring): crank-hole position
    errors of the discs (discs, P, 2) and of the carrier (P, 2) [um, carrier frame] -> per disc the
    translation (shift_um (discs, 2) [um]) and the rotation against the carrier (turn_rad (discs,)).
    Hole k nominally at R_c (cos 2 pi k / P, sin 2 pi k / P). The least-squares fit of a rigid
    motion to P point misfits m_k: translation = mean m_k, rotation = sum H_k x (m_k - mean) /
    sum |H_k|^2 (small angles)."""
    discs, planets = hole_disc_um.shape[0], hole_disc_um.shape[1]
    for d in range(discs):
        mx, my = 0.0, 0.0
        for k in range(planets):
            mx += hole_carrier_um[k, 0] - hole_disc_um[d, k, 0]
            my += hole_carrier_um[k, 1] - hole_disc_um[d, k, 1]
        mx /= planets
        my /= planets
        cross = 0.0
        for k in range(planets):
            gk = 2.0 * math.pi * k / planets
            hx, hy = crank_radius_mm * math.cos(gk), crank_radius_mm * math.sin(gk)
            rx = hole_carrier_um[k, 0] - hole_disc_um[d, k, 0] - mx
            ry = hole_carrier_um[k, 1] - hole_disc_um[d, k, 1] - my
            cross += hx * ry - hy * rx
        shift_um[d, 0] = mx
        shift_um[d, 1] = my
        turn_rad[d] = cross * 1e-3 / (planets * crank_radius_mm * crank_radius_mm)


@njit(nogil=True, cache=True)
def crank_angle_errors(theta, centre_ecc_um, planet_ecc_um, kin, zp, out):
    """Angle error of each crank d chi_k [rad] at output angle theta from the involute stage: the
    centre gear (turning (i - 1) theta against the carrier) and planet k (turning -z_p theta) with
    eccentricity vectors e [um] in their own frames; each moves the mesh of planet k (at 2 pi k / P
    in the carrier) along its tangent by e . t, t the tangent at the mesh seen from the gear, and
    turns the planet by that over its base radius r_b2 [mm] (the centre gear is the reference:
    the input's angle is read on it). Transmission error of an eccentric gear pair: Smith, Gear
    Noise and Vibration (2003), ch. 2 (once-per-rev line of amplitude e / r_b). ``kin``: the design's
    Kinematics (ratio i, r_b2)."""
    planets = out.size
    base_radius_mm = kin.base_radius_mm
    p1 = (kin.ratio - 1.0) * theta
    p2 = -zp * theta
    for k in range(planets):
        gk = 2.0 * math.pi * k / planets
        a1 = gk - p1  # the mesh direction in the centre gear's frame
        d1 = -centre_ecc_um[0] * math.sin(a1) + centre_ecc_um[1] * math.cos(a1)
        a2 = gk + math.pi - p2  # the mesh (towards the axis) in planet k's frame
        d2 = -planet_ecc_um[k, 0] * math.sin(a2) + planet_ecc_um[k, 1] * math.cos(a2)
        out[k] = (d1 - d2) * 1e-3 / base_radius_mm


@njit(nogil=True, cache=True)
def unit_pins(coef, rp, unit, pins):
    """What of a unit's pins does not change as the output turns, into ``pins`` (HousingPins):
    each pin centre in the housing frame [mm] and its gap's constant part -rho + cl / 2 [um]
    (``pin_in_disc``, hoisted)."""
    dr, dt, rho, cl = unit.pin_radial_um, unit.pin_tangential_um, unit.pin_radius_um, unit.pin_clearance_um
    cx, cy, base = pins.x_mm, pins.y_mm, pins.base_um
    for j in range(cx.size):
        rad = rp + dr[j] * 1e-3
        cpsi, spsi = coef[CPSI, 0, j], coef[SPSI, 0, j]
        cx[j] = rad * cpsi - dt[j] * 1e-3 * spsi
        cy[j] = rad * spsi + dt[j] * 1e-3 * cpsi
        base[j] = -rho[j] + 0.5 * cl[j]


@njit(nogil=True, cache=True)
def free_interval(coef, stage, pins, unit, gaps, scratch):
    """``models.contact.unit_gaps`` without the pin centres it keeps for the exact solve, the pins'
    constant part hoisted (``pins``, HousingPins): every pin's gap [um] and lever [um/rad] at
    beta = 0 into ``gaps``; returns (lo, hi, flat) as unit_gaps does. The production run's fast
    path. ``unit``: the UnitErrors with the disc errors placed at this position. As in unit_gaps,
    each disc's pins are one pass the compiler runs four at a time, their tooth pitch errors
    gathered first into ``scratch`` (z_p)."""
    a, rp, zp = stage.a_mm, stage.rp_mm, stage.zp
    cx, cy, base = pins.x_mm, pins.y_mm, pins.base_um
    ux, uy, da, md = unit.runout_along_um, unit.runout_across_um, unit.eccentricity_error_um, unit.moving_distance_um
    for d in range(stage.discs):
        ex, ey, cang, sang = coef[CCHI, d, 0], coef[SCHI, d, 0], coef[CANG, d, 0], coef[SANG, d, 0]
        off = a + da[d] * 1e-3
        dx = off * ex + (ux[d] * ex - uy[d] * ey) * 1e-3  # the disc centre and its profile offset [mm]
        dy = off * ey + (ux[d] * ey + uy[d] * ex) * 1e-3
        mdd = md[d] * 1e-3
        tooth, teeth_d = coef[TOOTH, d], unit.tooth_pitch_um[d]
        for j in range(zp):
            scratch[j] = teeth_d[int(tooth[j])]
        ox_, oy_, eux, euy, side, rho_c = coef[OX, d], coef[OY, d], coef[EUX, d], coef[EUY, d], coef[SIDE, d], \
            coef[RHO, d]
        eqd, gap_d, lever_d = unit.equidistance_um[d], gaps.gap_um[d], gaps.lever_um_per_rad[d]
        for j in range(zp):
            px = cx[j] - dx
            py = cy[j] - dy
            dl = -scratch[j] * 1e-3 / rp  # as pin_in_disc
            dl2 = dl * dl
            cdl, sdl = 1.0 - 0.5 * dl2 + dl2 * dl2 / 24.0, dl - dl2 * dl / 6.0
            ca, sa = cang * cdl - sang * sdl, sang * cdl + cang * sdl
            qx, qy = ca * px - sa * py, sa * px + ca * py
            ox = ox_[j] + mdd * eux[j]
            oy = oy_[j] + mdd * euy[j]
            dist = math.sqrt((qx - ox) * (qx - ox) + (qy - oy) * (qy - oy))
            gap_d[j] = eqd + base[j] + side[j] * (dist - rho_c[j]) * 1e3
            lever_d[j] = side[j] * (qy * ox - qx * oy) / dist * 1e3
    return free_interval_bounds(gaps, stage.pitch_radius_um)


@njit(nogil=True, cache=True)
def balanced_rotation(gaps, lo, hi):
    """The rotation beta [rad] of a preloaded stage at which the interfering pins' contact forces
    balance, on the linearised gaps of PinGaps ``gaps`` (gap_j(beta) = g_j - l_j beta [um], l_j
    [um/rad]); (lo, hi): their free interval (free_interval_bounds).

    Each pin pressed into the profile by p_j = max(0, l_j beta - g_j) [um] pushes along the profile
    normal with k p_j, and l_j is that force's moment arm about the disc centre (a rotation d beta
    closes the gap by l_j d beta), so the stage rests without torque where
        F(beta) = sum_j l_j max(0, l_j beta - g_j) = 0,
    the minimum of the contacts' strain energy k/2 sum_j p_j^2 (the principle of minimum potential
    energy; ASSUMPTION: every pin contact equally stiff and linear, the first elastic refinement of
    the rigid model). F is continuous and non-decreasing in beta, and rises wherever a pin with a
    lever interferes: its root moves continuously with the gaps. (The rotation that maximises the
    smallest gap, used before, does not: when the deepest interference sits at a pin without lever,
    on the line of centres, that maximum is flat and its end jumps from one side to the other as the
    pin's lever changes sign: 53 arcsec within 1/65 536 rev, issue 36 item 8.) When hi < lo the
    root lies in [hi, lo] (below hi only rising gaps interfere: F < 0; above lo only falling ones);
    when only pins without lever interfere, every beta of [lo, hi] balances and the middle is
    returned. Newton on the piecewise-linear F (exact once the set of interfering pins is right),
    bisection when a step leaves the bracket."""
    gap, lever = gaps.gap_um, gaps.lever_um_per_rad
    discs, zp = gap.shape
    left, right = min(lo, hi), max(lo, hi)
    bracketed = math.isfinite(left) and math.isfinite(right)
    beta = 0.5 * (left + right) if bracketed else 0.0
    if not bracketed:
        left, right = -np.inf, np.inf
    for _ in range(100):
        f, slope = 0.0, 0.0
        for d in range(discs):
            for j in range(zp):
                lv = lever[d, j]
                p = lv * beta - gap[d, j]
                if p > 0.0:
                    f += lv * p
                    slope += lv * lv
        if f == 0.0 or slope == 0.0:
            return beta
        if f > 0.0:
            right = beta
        else:
            left = beta
        nxt = beta - f / slope
        if not left < nxt < right:
            if not (math.isfinite(left) and math.isfinite(right)):
                break  # pragma: no cover - a stage has pins with levers of both signs: F is bracketed at once
            nxt = 0.5 * (left + right)
        if abs(nxt - beta) <= 1e-15 + 1e-13 * abs(beta):
            return nxt
        beta = nxt
    return beta


# The rest of a preloaded stage on the exact gaps (exact_rest): found first on every pin's osculating
# circle, then on the exact curve of the pins that its osculating gap, less REST_REACH_RAD of its lever,
# puts within REST_SCREEN_UM of contact (the circles are within ~1e-3 um of the curve at the pins that
# interfere, and the rest moves by ~1e-6 rad from one to the other); no exact gap is solved more than
# REST_REACH_RAD from the osculating rest (a far start finds another foot of the curve). Solved to
# REST_TOL_RAD.
REST_SCREEN_UM = 0.5
REST_REACH_RAD = 1e-5
REST_TOL_RAD = 1e-13  # 2e-8 arcsec
FREE_SCREEN_TIGHT_UM, FREE_SCREEN_UM = 0.5, 0.02  # exact_free: the pins checked on the exact curve


@njit(nogil=True, cache=True)
def _rest_force(exact, beta, coef, stage, unit, work):
    """(F, dF/dbeta, deepest interference [um]) at rotation beta [rad] of balanced_rotation's
    F = sum_j l_j max(0, -gap_j) [um^2/rad] (l_j = -d gap_j / d beta; the slope taken as sum l_j^2 over
    the interfering pins, exact for straight gaps). ``exact`` False: every pin's gap on its osculating
    circle (contact._lowest_gaps into ``work``); True: on the exact curve (turned_gap, from the pin's
    nominal foot), the pins that work.value_um and work.lever_um_per_rad (the screen) put within
    REST_SCREEN_UM of contact over REST_REACH_RAD."""
    a, rp, zc, discs, zp = stage.a_mm, stage.rp_mm, stage.zc, stage.discs, stage.zp
    md, val, lev = unit.moving_distance_um, work.value_um, work.lever_um_per_rad
    f, slope, depth = 0.0, 0.0, 0.0
    if not exact:
        _lowest_gaps(coef, work, md, beta)
    for d in range(discs):
        rg = rp + md[d] * 1e-3
        for j in range(zp):
            if exact:
                if val[d, j] - abs(lev[d, j]) * REST_REACH_RAD >= REST_SCREEN_UM:
                    continue
                gap, dgap, foot = turned_gap(work.pin_x_mm[d, j], work.pin_y_mm[d, j], beta, pin_base_um(unit, d, j),
                                             a, rg, zc, work.estimate_rad[d, j])
                work.estimate_rad[d, j] = foot  # the next call starts from this foot (exact_rest set them)
                lv = -dgap
            else:
                gap, lv = val[d, j], lev[d, j]
            if gap < 0.0:
                f -= lv * gap
                slope += lv * lv
                depth = max(depth, -gap)
    return f, slope, depth


@njit(nogil=True, cache=True)
def illinois_update(xa, fa, xb, fb, kept, x, fx):
    """One false-position step's bracket update, Illinois variant (Dowell & Jarratt 1971, BIT 11: 168-174):
    the bracket xa .. xb (values fa, fb of opposite signs) with the point x (value fx, not 0): x replaces the
    end whose value has fx's sign; where the same end is replaced twice in a row the other end's value is
    halved, so that the bracket closes from both sides. ``kept``: the end replaced last (1: a, -1: b, 0:
    none). Returns (xa, fa, xb, fb, kept)."""
    if (fx > 0.0) == (fa > 0.0):
        xa, fa = x, fx
        if kept == 1:
            fb *= 0.5
        kept = 1
    else:
        xb, fb = x, fx
        if kept == -1:
            fa *= 0.5
        kept = -1
    return xa, fa, xb, fb, kept


@njit(nogil=True, cache=True)
def _rest_root(exact, beta, reach, coef, stage, unit, work):
    """(beta, deepest interference there [um]): a root of _rest_force's F near the start beta [rad] at
    which F rises (the contacts' strain energy has a minimum there): a bracket found by steps that
    double from the Newton step (no farther than ``reach`` [rad] from the start: else the start is
    returned), then false position inside it (Illinois) to REST_TOL_RAD. Returns at once where F = 0 (no
    pin interferes)."""
    f, slope, depth = _rest_force(exact, beta, coef, stage, unit, work)
    if f == 0.0:
        return beta, depth
    start, depth0 = beta, depth
    step = min(abs(f) / slope, reach / 8.0) if slope > 0.0 else reach / 1024.0
    sgn = -1.0 if f > 0.0 else 1.0  # towards the root
    xa, fa = beta, f
    xb, fb, sb, db = beta, f, slope, depth
    found = False
    while abs(xa + sgn * step - start) <= reach:  # the bracket: the last point of the start's sign, the first past it
        xb = xa + sgn * step
        fb, sb, db = _rest_force(exact, xb, coef, stage, unit, work)
        if fb == 0.0:
            return xb, db
        if (fb > 0.0) != (fa > 0.0):
            found = True
            break
        xa, fa = xb, fb
        step *= 2.0
    if not found:
        return start, depth0
    # the bracket: F < 0 at its left end, > 0 at its right; false position (Illinois: the end that stays
    # put has its value halved), superlinear where F bends (a Newton step on sum l_j^2 converged linearly)
    xl, fl, xr, fr = (xa, fa, xb, fb) if sgn > 0.0 else (xb, fb, xa, fa)
    beta, depth, side = xb, db, 0
    for _ in range(100):
        nxt = (xl * fr - xr * fl) / (fr - fl)
        if not xl < nxt < xr:
            nxt = 0.5 * (xl + xr)
        if abs(nxt - beta) <= REST_TOL_RAD or xr - xl <= REST_TOL_RAD:
            return nxt, depth
        beta = nxt
        f, _, depth = _rest_force(exact, beta, coef, stage, unit, work)
        if f == 0.0:
            return beta, depth
        xr, fr, xl, fl, side = illinois_update(xr, fr, xl, fl, side, beta, f)
    return beta, depth


@njit(nogil=True, cache=True)
def exact_rest(coef, stage, unit, work, beta0):
    """(ccw, cw, preload) of a stage that the contact solver finds preloaded, or whose exact first
    contacts cross, on the exact gaps: both flanks [rad] at the rotation where the interfering pins'
    contact forces balance (balanced_rotation's F(beta) = sum_j l_j max(0, -gap_j(beta)) = 0, with
    gap_j and l_j = -d gap_j / d beta on the exact curve: turned_gap) and the deepest interference
    there [um]; or, if the exact gaps leave a free interval there after all, its ends (the first
    contacts, preload 0). ``coef``: the mesh_table column; ``unit``: the UnitErrors as placed;
    ``work``: the StageWork that stage_play (unit_gaps) left: the pins' centres in the disc frames;
    beta0: the start (balanced_rotation on the linearised gaps, or between crossed contacts).

    Why: the free stage's flanks are the exact first contacts, and the linearised gaps at beta = 0
    miss a pin facing a tooth tip by up to tenths of a um (the curve bends there with a radius of
    ~0.13 mm), so the balanced rotation on them did not meet the first contacts where the stage frees:
    the curve jumped by up to 5.5 arcsec (seed 0, unit 1). On the exact gaps, F's root tends to the
    point where the two first contacts meet as the preload tends to 0. First on the osculating circles
    of every pin (closed forms, good at any rotation), then on the exact curve of the screened pins
    (REST_SCREEN_UM), screened again at the exact rest (_rest_root)."""
    a, rp, zc, discs, zp = stage.a_mm, stage.rp_mm, stage.zc, stage.discs, stage.zp
    md, val, lev = unit.moving_distance_um, work.value_um, work.lever_um_per_rad
    for d in range(discs):  # the pins' feet on the curve, from their nominal ones (_rest_force keeps them)
        for j in range(zp):
            work.estimate_rad[d, j] = coef[T0, d, j]
    beta, depth = _rest_root(False, beta0, np.inf, coef, stage, unit, work)
    for _ in range(2):  # the exact curve, the pins screened at the rest so far (again if it moved farther
        _lowest_gaps(coef, work, md, beta)  # than the screen reaches)
        start = beta
        beta, depth = _rest_root(True, beta, 10.0 * REST_REACH_RAD, coef, stage, unit, work)
        if abs(beta - start) <= REST_REACH_RAD:
            break
    if depth > 0.0:
        return beta, beta, depth
    # free on the exact gaps: the nearest contact of each side among the screened pins (Newton on each
    # pin's gap from beta; the interval is about as narrow as the osculating circles' error)
    ccw, cw = np.inf, -np.inf
    for d in range(discs):
        rg = rp + md[d] * 1e-3
        for j in range(zp):
            if val[d, j] - abs(lev[d, j]) * REST_REACH_RAD >= REST_SCREEN_UM:
                continue
            px, py, base, t = work.pin_x_mm[d, j], work.pin_y_mm[d, j], pin_base_um(unit, d, j), coef[T0, d, j]
            gap, dgap, _ = turned_gap(px, py, beta, base, a, rg, zc, t)
            x = beta
            for _ in range(20):
                if dgap == 0.0 or abs(x - beta) > 10.0 * REST_REACH_RAD:
                    break
                x -= gap / dgap
                gap, dgap, _ = turned_gap(px, py, x, base, a, rg, zc, t)
                if abs(gap) < 1e-9:
                    break
            if abs(gap) >= 1e-6 or abs(x - beta) > 10.0 * REST_REACH_RAD:
                continue
            if dgap < 0.0:  # a falling gap stops a counter-clockwise turn
                ccw = min(ccw, x)
            elif dgap > 0.0:
                cw = max(cw, x)
    if ccw > cw and math.isfinite(ccw) and math.isfinite(cw):
        return ccw, cw, 0.0
    return beta, beta, 0.0


@njit(nogil=True, cache=True)
def exact_free(coef, stage, unit, work, beta):
    """Whether every pin is free at rotation beta [rad] on the exact curve: the pins that their
    osculating circles (contact._lowest_gaps into ``work``) put within REST_SCREEN_UM of contact, on
    the exact curve (turned_gap). At the middle of the free interval that stage_play found it need not
    be: the circles miss a pin facing a tooth tip by up to ~1e-3 um, and there the contact solver can
    return crossed or far contacts (seed 0, unit 1, 998.97590 steps of 1024: 33 661 arcsec); exact_rest
    places the stage there."""
    a, rp, zc, discs, zp = stage.a_mm, stage.rp_mm, stage.zc, stage.discs, stage.zp
    md, val = unit.moving_distance_um, work.value_um
    _lowest_gaps(coef, work, md, beta)
    for d in range(discs):
        rg = rp + md[d] * 1e-3
        for j in range(zp):
            # the circles' error at the rest's rotations, measured (3 units of seed 3, every pin below 2 um):
            # up to 0.25 um where C bends tightly (RHO < RHO_TIGHT_MM), 0.003 um elsewhere
            screen = FREE_SCREEN_TIGHT_UM if coef[RHO, d, j] < RHO_TIGHT_MM else FREE_SCREEN_UM
            if val[d, j] < screen and turned_gap(work.pin_x_mm[d, j], work.pin_y_mm[d, j], beta,
                                                         pin_base_um(unit, d, j), a, rg, zc, coef[T0, d, j])[0] < 0.0:
                return False
    return True


@njit(nogil=True, cache=True)
def te_curve(stage, kin, table, unit, chi0, scratch, curve, exact):
    """Both flanks' output positions [rad] at every output position of ``table`` (PositionTable: the
    contact model's mesh_table at each) and the preload [um] (0 where the stage is free) into
    ``curve`` (FlankCurve) for the unit whose UnitErrors are ``unit``, its reference position at
    crank angle chi0 (module docstring). ``stage``: StageGeometry; ``kin``: the design's Kinematics;
    ``scratch``: curve_scratch. Where the stage is preloaded both flanks sit at the rotation where
    the interfering pins' forces balance and the lost motion is 0: ``exact``, on the exact gaps
    (exact_rest, also where the exact first contacts cross); else on the linearised ones
    (balanced_rotation). ``exact``:
    each first contact solved on the exact curve (stage_play); else linearised at the assembled
    position (unit_gaps' free interval: the production run's fast path, error bounded in the tests)."""
    a, rp, zc, zp, discs = stage.a_mm, stage.rp_mm, stage.zc, stage.zp, stage.discs
    crank_radius_mm = kin.crank_radius_mm
    coef, chis, thetas = table.coef, table.chi_rad, table.theta_rad
    dchi, teeth, ux, uy = scratch.crank_angle_rad, scratch.tooth_pitch_um, scratch.runout_along_um, \
        scratch.runout_across_um
    shift_um, turn_rad = scratch.shift_um, scratch.turn_rad
    teeth0, ux0, uy0 = unit.tooth_pitch_um, unit.runout_along_um, unit.runout_across_um
    planets = dchi.size
    crank_fit(unit.disc_crank_hole_um, unit.carrier_crank_hole_um, crank_radius_mm, shift_um, turn_rad)
    placed = with_disc_errors(unit, teeth, ux, uy)  # the disc errors as placed at each position, below
    unit_pins(coef[0], rp, unit, scratch.pins)
    gaps = scratch.gaps
    for n in range(chis.size):
        chi = chis[n]
        crank_angle_errors(thetas[n], unit.centre_gear_eccentricity_um, unit.planet_eccentricity_um, kin, zp, dchi)
        mean = 0.0
        for k in range(planets):
            mean += dchi[k]
        mean /= planets
        w = -(chi - chi0) * zp / zc  # disc-fixed vectors against the eccentric
        cos_w, sin_w = math.cos(w), math.sin(w)
        for d in range(discs):
            rel = chi + 2.0 * math.pi * d / discs + chi / zc  # the eccentric's direction in the carrier frame
            cr, sr = math.cos(rel), math.sin(rel)
            ux[d] = cos_w * ux0[d] - sin_w * uy0[d] + shift_um[d, 0] * cr + shift_um[d, 1] * sr
            uy[d] = sin_w * ux0[d] + cos_w * uy0[d] - shift_um[d, 0] * sr + shift_um[d, 1] * cr + a * mean * 1e3
            turn = turn_rad[d]
            for k in range(planets):  # the cranks' differences turn the disc (crank_fit with a d chi_k e_perp)
                turn += a * (dchi[k] - mean) * math.cos(rel - 2.0 * math.pi * k / planets) / (planets * crank_radius_mm)
            for k in range(zc):
                teeth[d, k] = teeth0[d, k] + turn * rp * 1e3
        if exact:
            play = stage_play(coef[n], stage, placed, gaps, scratch.work, exact)  # exact: True, not as a literal
            #                                                       (contact_source.contact_block says why)
            free, ccw, cw, preload = not math.isnan(play.play_ccw_rad), play.play_ccw_rad, play.play_cw_rad, \
                play.preload_um
        else:
            lo, hi, flat = free_interval(coef[n], stage, scratch.pins, placed, gaps, scratch.work.pin_tooth_pitch_um[0])
            free, ccw, cw, preload = not (hi < lo or flat < 0.0), hi, -lo, 0.0
        if curve.gap_um.shape[0] > 0:
            curve.gap_um[n] = gaps.gap_um
            curve.lever_um_per_rad[n] = gaps.lever_um_per_rad
        crossed = exact and free and (ccw + cw < 0.0 or not exact_free(coef[n], stage, placed, scratch.work,
                                                                                    0.5 * (ccw - cw)))
        if not free or crossed:
            if exact:
                lo, hi, _ = free_interval_bounds(gaps, stage.pitch_radius_um)
                start = 0.5 * (ccw - cw) if ccw + cw < 0.0 else balanced_rotation(gaps, lo, hi)
                # on the exact gaps, so that the rest meets the first contacts where the stage frees
                ccw, cw, depth = exact_rest(coef[n], stage, placed, scratch.work, start)
                curve.ccw_rad[n] = ccw
                curve.cw_rad[n] = cw
                curve.preload_um[n] = 0.0 if ccw > cw else (preload if preload > 0.0 else depth)
            else:
                b = balanced_rotation(gaps, lo, hi)
                curve.ccw_rad[n] = b
                curve.cw_rad[n] = b
                curve.preload_um[n] = preload
        else:
            curve.ccw_rad[n] = ccw
            curve.cw_rad[n] = -cw
            curve.preload_um[n] = 0.0


@njit(nogil=True, cache=True)
def curve_scratch(zp, zc, discs, planets):
    """Scratch of te_curve (CurveScratch)."""
    return CurveScratch(np.empty((discs, zc)), np.empty(discs), np.empty(discs), np.empty(planets),
                        pin_gaps(discs, zp), stage_work(discs, zp),
                        HousingPins(np.empty(zp), np.empty(zp), np.empty(zp)), np.empty((discs, 2)), np.empty(discs))


def flank_positions(g: ContactGeometry, r, theta: np.ndarray, chis: np.ndarray, kin: Kinematics, exact: bool = True,
                    coef: np.ndarray | None = None, record: bool = False) -> FlankCurve:
    """Both flanks' positions [rad] and the preload [um] of one unit (a Realization) at the output
    positions (theta, chis) of ``output_positions``. ``coef``: the mesh_table there
    (``position_table``'s); None: built TABLE_POSITIONS positions at a time (each position is solved
    on its own: the same numbers, in bounded memory). ``record``: also every pin's gap and lever at
    each position (FlankCurve; single precision: they only say where to look between positions)."""
    n = chis.size
    rows = n if record else 0
    curve = FlankCurve(np.empty(n), np.empty(n), np.empty(n), np.empty((rows, g.discs, g.zp), np.float32),
                       np.empty((rows, g.discs, g.zp), np.float32))
    stage, unit, scratch = g.stage_geometry, unit_errors(r, kin.planets), curve_scratch(g.zp, g.zc, g.discs, kin.planets)
    step = TABLE_POSITIONS if coef is None else max(n, 1)
    for start in range(0, n, step):
        part = slice(start, start + step)
        table = PositionTable(theta[part], chis[part], mesh_table(g, chis[part]) if coef is None else coef)
        te_curve(stage, kin, table, unit, float(r.chi_rad), scratch, FlankCurve(*(x[part] for x in curve)), exact)
    return curve


# The extremes of a TE curve between its positions (curve_extremes). The curve has features narrower
# than a position step: in a free stage a flank's position is the first contact, the least of the pins'
# contact rotations, so it peaks in a cusp wherever the first contact switches pins (z_c z_p times a
# revolution, 1560 for rv80e: more often than the default 1024 positions); a preloaded stage swings
# from one end of the rotation its other pins leave to the other when the one pin that interferes
# crosses the line of centres (balanced_rotation); a stage may be freed, or preloaded, for a fraction
# of a step. The sampled peak-to-peak then depends on where the positions fall (issue 36 item 8: +4.2 %
# on average from 1024 to 4096 positions, up to +20.7 %). Every pin's gap and lever are smooth in the
# output angle (the unit's errors and the osculating circles turn smoothly with it), so between the
# positions they are interpolated (cubic, through the two positions either side), and the flank
# positions they give - first contacts, or the balanced rotation where they interfere - are evaluated
# at STEP_POINTS - 1 points a step and either side of each point where a pin that may interfere has
# its lever cross zero (a swing; step_extremes: no trigonometry, a few ms a curve): that shows where in
# a step a cusp, a swing or a short free stretch lies, and how far it reaches. The steps whose
# estimate passes the sampled extreme (the CANDIDATES best for each of the four extremes) are then
# solved on the exact curve at the estimate's point (and at NEAR_OFFSETS about the best one: a narrow
# feature of the solved curve sits near, not at, its estimate) and searched about the best
# (ZOOM_LEVELS pattern-search levels): every figure is a point of the solved curve, never an
# interpolated one. The cubic is poor where a pin passes a tooth tip (the pin-centre curve's radius is
# ~0.13 mm there: the gap bends within a step, the cubic misses its lowest value by up to ~0.3 um): a
# swing there may hide behind interpolated gaps that show a free stage. So wherever a pin near contact
# has its lever change sign (its gap there below SWING_GAP_UM, the screen that reads the swing points),
# the swing's reach - the ends of the rotation the other pins leave - is an estimate too, and the
# steps whose reach passes the sampled extremes are solved about the lever's zero (issue 36 item 8:
# unit 3 of seed 3 read 47.68 at 1024 positions against 48.70 arcsec at 4096, now 48.68; 4 of the 6
# units of seed 0 that read more than 1 % apart are within it; a fourth-difference estimate of the
# cubic's error, tried first, underestimated it at the tips and left them). The curve solved exactly rests
# on the exact gaps (exact_rest), the estimates on the linearised ones: where a pin passing a tooth tip holds
# the stage the exact rest slides with the tip while the linearised one jumps, up to ~0.15 of a default
# step apart, so about each candidate in a step where the stage rests a window of +-WINDOW_REV is solved
# (2 WINDOW_POINTS + 1 points) and the pattern search also starts from each window's best within
# ZOOM_MARGIN_RAD of the extreme (seed 3 unit 11 read -3.95 % at 1024 positions against 16 384 without).
STEP_POINTS, CANDIDATES, ZOOM_LEVELS = 8, 4, 5
# the swings solved for each extreme, best estimate first: a unit whose TE is a fraction of an arcsec (the
# error-free unit warm, preloaded everywhere: every step's swing passes its extreme) solved 15 000 - 19 000
# points at 80 - 87 degC without a cap
SWING_CANDIDATES = 8
NEAR_OFFSETS = tuple(0.01 * k for k in (-4, -3, -2, -1, 1, 2, 3, 4))  # of a step
SWING_SIDE = 1e-3  # of a step: where a swing is read, either side of the lever's zero
SWING_GAP_UM = 1.0  # a pin's lever crossing 0 is read if its gap at either end is below this (it may interfere between)
SWING_OFFSETS = (-1e-3, -1e-4, -1e-5, 0.0, 1e-5, 1e-4, 1e-3)  # of a step: about a solved lever zero (solved_lever_zero)
WINDOW_REV, WINDOW_POINTS = 0.25 / DEFAULT_POSITIONS, 4  # exact rest: a window about each candidate [rev], points a side
ZOOM_MARGIN_RAD = 2.0 / ARCSEC_PER_RAD  # a window's best this close to the extreme is searched about too
LEVER_ZERO_ITERATIONS, LEVER_ZERO_TOL = 8, 1e-5  # regula falsi on the solved lever: at most, and the last move [steps]


@njit(nogil=True, cache=True, inline="always")
def cubic_weights(f):
    """Lagrange weights of the values at -1, 0, 1, 2 for the point f (0 <= f <= 1) between 0 and 1
    (cubic through four equally spaced points; Abramowitz & Stegun 25.2.13, interpolation error
    O(h^4) for a smooth function)."""
    return (-f * (f - 1.0) * (f - 2.0) / 6.0, (f + 1.0) * (f - 1.0) * (f - 2.0) / 2.0,
            -(f + 1.0) * f * (f - 2.0) / 2.0, (f + 1.0) * f * (f - 1.0) / 6.0)


@njit(nogil=True, cache=True)
def interpolated_flanks(curve, n, f, azc_um, gaps):
    """(ccw, cw) flank positions [rad] at the point f (0..1) of step n -> n + 1 of FlankCurve
    ``curve`` (recorded: its gaps and levers, a closed revolution), from every pin's gap and lever
    interpolated there (cubic_weights) into ``gaps`` (PinGaps scratch): the first contacts of the
    free interval (free_interval_bounds; azc_um: a z_c [um]), or where they interfere both flanks at
    the balanced rotation (te_curve's rules on the linearised gaps)."""
    rows = curve.gap_um.shape[0]
    w = cubic_weights(f)
    ks = ((n - 1) % rows, n, (n + 1) % rows, (n + 2) % rows)
    g, lv = gaps.gap_um, gaps.lever_um_per_rad
    discs, zp = g.shape
    for d in range(discs):
        for j in range(zp):
            gv, lv_ = 0.0, 0.0
            for i in range(4):
                gv += w[i] * curve.gap_um[ks[i], d, j]
                lv_ += w[i] * curve.lever_um_per_rad[ks[i], d, j]
            g[d, j] = gv
            lv[d, j] = lv_
    lo, hi, flat = free_interval_bounds(gaps, azc_um)
    if hi < lo or flat < 0.0:
        b = balanced_rotation(gaps, lo, hi)
        return b, b
    return hi, lo


class ReferenceFlanks(NamedTuple):
    """The error-free unit's flank positions [rad] at the output positions and between them
    (reference_flanks): what every unit's TE subtracts."""

    ccw_rad: np.ndarray  # (N,)
    cw_rad: np.ndarray
    between_rad: np.ndarray  # (2, N, points): ccw, cw at the point s / points of step n (s = 0: the position)


@njit(nogil=True, cache=True)
def flanks_between(curve, azc_um, out):
    """Both flank positions [rad] at the points s / points (s = 1 .. points - 1; points =
    out.shape[2]) of every step of the recorded FlankCurve ``curve`` (interpolated_flanks) into out
    (2, N, points); s = 0: the sampled positions."""
    rows, discs, zp = curve.gap_um.shape
    points = out.shape[2]
    gaps = pin_gaps(discs, zp)
    for n in range(rows):
        out[0, n, 0] = curve.ccw_rad[n]
        out[1, n, 0] = curve.cw_rad[n]
        for s in range(1, points):
            out[0, n, s], out[1, n, s] = interpolated_flanks(curve, n, s / points, azc_um, gaps)


def reference_flanks(curve: FlankCurve, azc_um: float, points: int = STEP_POINTS) -> ReferenceFlanks:
    """ReferenceFlanks of the error-free unit's recorded FlankCurve (flanks_between)."""
    between = np.empty((2, curve.ccw_rad.size, points))
    flanks_between(curve, azc_um, between)
    return ReferenceFlanks(np.array(curve.ccw_rad), np.array(curve.cw_rad), between)


@njit(nogil=True, cache=True)
def lever_zero(run, n, d, j):
    """Where (the fraction of step n -> n + 1) the lever of pin j of disc d, interpolated as
    interpolated_flanks does (cubic_weights), crosses 0, given that its ends have opposite signs:
    bisection to 1e-6 of a step."""
    rows = run.lever_um_per_rad.shape[0]
    ks = ((n - 1) % rows, n, (n + 1) % rows, (n + 2) % rows)
    lo, hi = 0.0, 1.0
    sign0 = run.lever_um_per_rad[n, d, j] > 0.0
    while hi - lo > 1e-6:
        mid = 0.5 * (lo + hi)
        w = cubic_weights(mid)
        v = 0.0
        for i in range(4):
            v += w[i] * run.lever_um_per_rad[ks[i], d, j]
        if (v > 0.0) == sign0:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


@njit(nogil=True, cache=True, inline="always")
def reference_at(ref, n, f):
    """The error-free unit's (ccw, cw) flank positions [rad] at the point f (0..1) of step n, linear
    between the points of ReferenceFlanks ``ref`` (its ripple is 0.07 arcsec for rv80e)."""
    points, rows = ref.between_rad.shape[2], ref.between_rad.shape[1]
    x = f * points
    s = min(int(x), points - 1)
    t = x - s
    n2, s2 = (n, s + 1) if s + 1 < points else ((n + 1) % rows, 0)
    return ((1.0 - t) * ref.between_rad[0, n, s] + t * ref.between_rad[0, n2, s2],
            (1.0 - t) * ref.between_rad[1, n, s] + t * ref.between_rad[1, n2, s2])


class StepEstimates(NamedTuple):
    """What step_extremes estimates of each step n -> n + 1 of a recorded revolution, for each of the
    four extremes (ccw max, ccw min, cw max, cw min: the largest of +TE_ccw, -TE_ccw, +TE_cw, -TE_cw),
    (4, N) each: the largest interpolated value [rad] and where (the fraction of the step); the reach
    of a swing the interpolation cannot rule out [rad] (-inf: none) and where."""

    value: np.ndarray
    at: np.ndarray
    swing_value: np.ndarray
    swing_at: np.ndarray
    swing_pin: np.ndarray  # the swing's pin, d z_p + j (-1: none)


def step_estimates(n: int) -> StepEstimates:
    return StepEstimates(np.empty((4, n)), np.empty((4, n)), np.empty((4, n)), np.empty((4, n)),
                         np.empty((4, n), np.int64))


@njit(nogil=True, cache=True)
def swing_reach(gaps, d0, j0, azc_um):
    """(lo, hi) [rad]: the free interval that the pins other than pin j0 of disc d0 leave
    (free_interval_bounds without it) on the PinGaps ``gaps``: where a stage that this pin alone
    (without a lever) holds can swing to (balanced_rotation)."""
    gap, lever = gaps.gap_um, gaps.lever_um_per_rad
    discs, zp = gap.shape
    tol = 1e-9 * azc_um
    lo, hi = -np.inf, np.inf
    for d in range(discs):
        for j in range(zp):
            if d == d0 and j == j0:
                continue
            g, lv = gap[d, j], lever[d, j]
            if lv > tol:
                hi = min(hi, g / lv)
            elif lv < -tol:
                lo = max(lo, g / lv)
    return lo, hi


@njit(nogil=True, cache=True)
def step_extremes(run, ref, azc_um, out):
    """For each step n -> n + 1 of a revolution and each of the four extremes the largest value [rad]
    in the step, interpolated (interpolated_flanks) on the unit's recorded FlankCurve ``run`` less the
    error-free unit's there (``ref``: ReferenceFlanks, reference_at), and where (the fraction of the
    step), into ``out`` (StepEstimates). Read at the interior points s / points of the step (points:
    ref.between_rad.shape[2]) and on both sides of each point where a pin near contact has its lever
    change sign (a swing of the balanced rotation, narrower than a step: the comment above). At such a
    point a swing that the interpolation cannot rule out - the pin's interpolated gap there below
    SWING_GAP_UM: the cubic misses a tooth tip's gap by tenths of a um - is given its reach, the ends
    of the rotation the other pins leave (swing_reach), in out.swing_value: curve_extremes solves the
    steps whose reach passes the sampled extremes on the exact curve."""
    rows, discs, zp = run.gap_um.shape
    points = ref.between_rad.shape[2]
    gaps = pin_gaps(discs, zp)
    fs = np.empty(points - 1 + 2 * discs * zp)
    value, at, swing_value, swing_at, swing_pin = out.value, out.at, out.swing_value, out.swing_at, out.swing_pin
    for n in range(rows):
        for i in range(4):
            value[i, n] = -np.inf
            at[i, n] = 0.5
            swing_value[i, n] = -np.inf
            swing_at[i, n] = 0.5
            swing_pin[i, n] = -1
        m = 0
        for s in range(1, points):
            fs[m] = s / points
            m += 1
        n1 = (n + 1) % rows
        for d in range(discs):
            for j in range(zp):
                l0, l1 = run.lever_um_per_rad[n, d, j], run.lever_um_per_rad[n1, d, j]
                if min(run.gap_um[n, d, j], run.gap_um[n1, d, j]) < SWING_GAP_UM and l0 * l1 < 0.0:
                    f0 = lever_zero(run, n, d, j)
                    fs[m] = max(f0 - SWING_SIDE, 1e-6)
                    fs[m + 1] = min(f0 + SWING_SIDE, 1.0 - 1e-6)
                    m += 2
                    interpolated_flanks(run, n, f0, azc_um, gaps)
                    if gaps.gap_um[d, j] < SWING_GAP_UM:  # it may interfere there (the cubic misses a tip by tenths of a um)
                        lo, hi = swing_reach(gaps, d, j, azc_um)
                        c0, w0 = reference_at(ref, n, f0)
                        for i, v in enumerate((hi - c0, c0 - lo, hi - w0, w0 - lo)):
                            if math.isfinite(v) and v > swing_value[i, n]:
                                swing_value[i, n] = v
                                swing_at[i, n] = f0
                                swing_pin[i, n] = d * zp + j
        for k in range(m):
            f = fs[k]
            c, w = interpolated_flanks(run, n, f, azc_um, gaps)
            c0, w0 = reference_at(ref, n, f)
            te_c, te_w = c - c0, w - w0
            for i, v in enumerate((te_c, -te_c, te_w, -te_w)):
                if v > value[i, n]:
                    value[i, n] = v
                    at[i, n] = f


@njit(nogil=True, cache=True)
def mesh_columns(stage, chis, out):
    """mesh_table at the crank angles ``chis`` [rad], compiled (contact.mesh_column_at, the pins' angles
    computed once), into ``out`` (len(chis), N_COEF, discs, z_p): equal to mesh_table to round-off, and
    ~40 times cheaper (numpy's ~100 us a column was most of a solved point's cost)."""
    pins = np.empty((4, stage.zp))
    mesh_pin_angles(stage, pins)
    for n in range(chis.size):
        mesh_column_at(stage, chis[n], pins, out[n])


def flank_te(g: ContactGeometry, r, reference, kin: Kinematics, theta: np.ndarray,
             exact: bool = True) -> np.ndarray:
    """TE [rad] of both flanks of unit ``r`` (a Realization) at output angles ``theta`` [rad], (2,
    theta.size): ccw, cw. Each flank's position minus the error-free unit's (``reference``) there,
    both from the crank angle r.chi_rad."""
    chi0 = float(r.chi_rad)
    chis = np.ascontiguousarray(chi0 - g.zc * np.asarray(theta, float))
    coef = np.empty((chis.size, N_COEF, g.discs, g.zp))
    mesh_columns(g.stage_geometry, chis, coef)
    a = flank_positions(g, r, theta, chis, kin, exact, coef)
    b = flank_positions(g, reference, theta, chis, kin, exact, coef)
    return np.stack([a.ccw_rad - b.ccw_rad, a.cw_rad - b.cw_rad])


def curve_extremes(g: ContactGeometry, r, reference, kin: Kinematics, run: FlankCurve, ref: ReferenceFlanks,
                   exact: bool = True) -> tuple[tuple[float, float], tuple[float, float]]:
    """((min, max) of the ccw flank's TE, (min, max) of the cw flank's) [rad] over the revolution of
    unit ``r``: ``run`` its recorded FlankCurve (flank_positions(record=True)) at equal output steps
    from theta = 0, ``ref`` the error-free unit's (``reference``) ReferenceFlanks. The sampled extremes,
    refined between the positions (the comment above): each figure is the solved curve's value at
    a position or at a point found between two."""
    n = run.ccw_rad.size
    te = np.stack([run.ccw_rad - ref.ccw_rad, run.cw_rad - ref.cw_rad])
    goals = ((0, 1.0), (0, -1.0), (1, 1.0), (1, -1.0))  # (flank, sign): maximise sign * TE of the flank
    best = np.array([float((sign * te[f]).max()) for f, sign in goals])
    where = np.array([float(np.argmax(sign * te[f])) for f, sign in goals])  # in steps
    est = step_estimates(n)
    step_extremes(run, ref, g.pitch_radius_um, est)
    value, at = est.value, est.at
    step = 2.0 * math.pi / n

    solved: dict[float, tuple[float, float]] = {}  # a point (in steps) -> TE of both flanks there
    zeros: dict[tuple[int, int], float | None] = {}  # (step, pin) -> its solved lever's zero (solved_lever_zero)

    def solve(points: list[list[float]]) -> None:
        """Solve the curve at each goal's points (in steps) not solved yet (the pattern search's next
        level repeats half of its points when the best stays put) and keep what passes its best."""
        new = sorted({x for p in points for x in p if x not in solved})
        if new:
            w = flank_te(g, r, reference, kin, (np.asarray(new) % n) * step, exact)  # a revolution is closed
            solved.update(zip(new, zip(w[0].tolist(), w[1].tolist())))
        for i, (f, sign) in enumerate(goals):
            for x in points[i]:
                v = sign * solved[x][f]
                if v > best[i]:
                    best[i], where[i] = v, x

    # the steps whose interpolated extreme passes the sampled one, best first
    first, windows = [], []
    w = WINDOW_REV * n  # a window's half-width [steps]
    grid = [w * k / WINDOW_POINTS for k in range(-WINDOW_POINTS, WINDOW_POINTS + 1)]

    def rests(k: int) -> bool:
        """Whether the stage rests (is preloaded) at either end of step k: where the exact rest can part
        from the linearised one the estimates read."""
        return bool(run.preload_um[k % n] > 0.0 or run.preload_um[(k + 1) % n] > 0.0)

    for i in range(4):
        order = np.argsort(value[i])[::-1][:CANDIDATES]
        points = [float(k + at[i, k]) for k in order if value[i, k] > best[i]]
        centres = [x for x in points if rests(int(x))]
        if points:  # about the best estimate too: the solved curve's narrow features sit near, not at, it
            points += [points[0] + o for o in NEAR_OFFSETS]
        # the swings the interpolation cannot rule out whose reach passes it (step_extremes), at the
        # interpolated lever's zero and about it (the solved lever's zero sits near, not at, it)
        swings = np.flatnonzero(est.swing_value[i] > best[i])
        for k in swings[np.argsort(est.swing_value[i][swings])[::-1][:SWING_CANDIDATES]]:
            x = float(k + est.swing_at[i, k])
            centres.append(x)
            points += [x - SWING_SIDE, x + SWING_SIDE] + [x + o for o in NEAR_OFFSETS]
            z = solved_lever_zero(g, r, kin, run, int(k), int(est.swing_pin[i, k]), zeros)
            if z is not None:  # the solved lever's zero: a swing narrower than the offsets above (unit 83)
                points += [z + o for o in SWING_OFFSETS]
        if exact:  # the exact rest's features sit up to ~0.15 of a default step from the linearised ones
            for x in centres:
                points += [x + o for o in grid]
        first.append(points)
        windows.append(centres)
    solve(first)
    # a pattern search about each extreme found, and about the best of each window that comes within
    # ZOOM_MARGIN of it: a cusp or a swing's end to within a small part of a step
    starts = []
    for i, (f, sign) in enumerate(goals):
        local = [where[i]]
        if exact:
            for x in windows[i]:
                xs = [x + o for o in grid if x + o in solved]
                if xs:
                    xb = max(xs, key=lambda y: sign * solved[y][f])
                    if sign * solved[xb][f] > best[i] - ZOOM_MARGIN_RAD and all(abs(xb - y) > 1e-9 for y in local):
                        local.append(xb)
        starts.append(local)
    d = min(1.0 / STEP_POINTS, w / WINDOW_POINTS) if exact else 1.0 / STEP_POINTS
    levels = ZOOM_LEVELS + (int(math.ceil(math.log2(1.0 / STEP_POINTS / d))) if d < 1.0 / STEP_POINTS else 0)
    for _ in range(levels):
        pts = [[float(x + o * d) for x in starts[i] for o in (-1.0, -0.5, 0.5, 1.0)] for i in range(4)]
        solve(pts)
        for i, (f, sign) in enumerate(goals):  # each start moves to the best of its neighbours
            starts[i] = [max([x] + [x + o * d for o in (-1.0, -0.5, 0.5, 1.0)], key=lambda y: sign * solved[y][f]
                             if y in solved else sign * te[f][int(round(y)) % n]) for x in starts[i]]
        d *= 0.5
    return (-best[1], best[0]), (-best[3], best[2])


def solved_lever_zero(g: ContactGeometry, r, kin: Kinematics, run: FlankCurve, n: int, pin: int,
                      memo: dict) -> float | None:
    """Where (in steps, n .. n + 1) the lever of pin ``pin`` (d z_p + j) of unit ``r`` crosses 0 on the
    solved curve: regula falsi (Illinois) from the recorded levers at positions n and n + 1 (opposite
    signs: step_extremes), the lever at each point from the pins' linearised gaps there (flank_positions,
    recorded), until an estimate moves less than LEVER_ZERO_TOL of a step. A swing can be narrower than
    the distance between the cubic's lever zero and the solved one (issue 36 item 8, unit 83 of seed 0:
    a swing 1/200 of a step wide, its solved zero 0.008 of a step from the cubic's); it is read about
    this zero. None when the recorded ends
    do not bracket a zero. ``memo``: (n, pin) -> the zero, shared by the four extremes."""
    if (n, pin) in memo:
        return memo[(n, pin)]
    rows = run.lever_um_per_rad.shape[0]
    d, j = divmod(pin, g.zp)
    step = 2.0 * math.pi / rows
    xa, xb = float(n), float(n + 1)
    la, lb = float(run.lever_um_per_rad[n, d, j]), float(run.lever_um_per_rad[(n + 1) % rows, d, j])
    zero = None
    if la * lb < 0.0:
        side, x = 0, xa
        for _ in range(LEVER_ZERO_ITERATIONS):
            last, x = x, xa - la * (xb - xa) / (lb - la)
            if abs(x - last) < LEVER_ZERO_TOL:
                break
            theta = np.array([(x % rows) * step])
            # the pins' levers at the assembled position: the same linearisation whether or not the flanks
            # are then solved exactly (te_curve records unit_gaps' either way), so the fast path is enough
            lx = float(flank_positions(g, r, theta, float(r.chi_rad) - g.zc * theta, kin, False,
                                       record=True).lever_um_per_rad[0, d, j])
            if lx == 0.0:
                xa = xb = x
                break
            xa, la, xb, lb, side = illinois_update(xa, la, xb, lb, side, x, lx)
        zero = x  # the last estimate: an Illinois bracket need not close on both sides
    memo[(n, pin)] = zero
    return zero


def kinematics(problem: Problem) -> Kinematics:
    g = problem.geometry
    return Kinematics(g.ratio, g.planet_pitch_radius_mm * math.cos(math.radians(g.pressure_angle_deg)),
                      g.crank_circle_radius_mm, problem.design.first_stage.planets)


def perfect_unit(problem: Problem, chi_rad: float = 0.0) -> Realization:
    """The error-free unit: nominal modifications, the pin/hole clearance at its zone mean."""
    s2 = problem.design.second_stage
    clearance = float(problem.means_um[FACTOR_KEYS.index("pin_hole_clearance")])
    return Realization.nominal(problem.cycloid, s2.equidistance_modification_um, s2.moving_distance_modification_um,
                               clearance, chi_rad)


@functools.lru_cache(maxsize=8)
def position_table(g, positions: int, chi0_rad: float) -> PositionTable:
    """The PositionTable of ``positions`` output positions from crank angle chi0 (built once per
    geometry and start: the table is most of a single curve's cost). Shared: do not modify."""
    theta, chis = output_positions(g, positions, chi0_rad)
    return PositionTable(theta, chis, mesh_table(g, chis))


def cached_table(g: ContactGeometry, positions: int, chi0_rad: float) -> PositionTable | None:
    """``position_table`` up to TABLE_POSITIONS positions; None beyond (such a revolution is solved a
    table at a time: flank_positions)."""
    return position_table(g, positions, chi0_rad) if positions <= TABLE_POSITIONS else None


def revolution_curve(g: ContactGeometry, r, positions: int, chi0_rad: float, kin: Kinematics, exact: bool,
                     table: PositionTable | None, record: bool = False) -> tuple[np.ndarray, FlankCurve]:
    """(theta, FlankCurve) of unit ``r`` at ``positions`` output positions from chi0 (``table``:
    their PositionTable, or None; ``record``: flank_positions')."""
    if table is None:
        theta, chis = output_positions(g, positions, chi0_rad)
        return theta, flank_positions(g, r, theta, chis, kin, exact, record=record)
    return table.theta_rad, flank_positions(g, r, table.theta_rad, table.chi_rad, kin, exact, table.coef, record)


def lost_motion_arcmin(ccw_rad, cw_rad) -> np.ndarray:
    """Lost motion at each output position [arcmin]: the gap between the two flanks' positions,
    dtheta(theta) = theta_ccw(theta) - theta_cw(theta) [rad -> arcmin], the output turned
    counter-clockwise and clockwise from theta until a flank touches (rigid, no load; 0 where the
    stage is preloaded and both flanks sit at one position). The transmission model's "lost motion
    at every output position" (analysis.transmission); a bench reads the same gap between the TE
    of its two runs (analysis.bench, the upper run as ccw). Sun et al. (2014)'s lost motion is the
    play at one position; valid for any flank positions of one unit at the same theta."""
    return (np.asarray(ccw_rad) - np.asarray(cw_rad)) * ARCMIN_PER_RAD


@dataclass(frozen=True)
class Revolution:
    """Flank positions of one unit [rad] at the output positions (theta [rad]); preload [um]."""

    theta_rad: np.ndarray
    ccw_rad: np.ndarray
    cw_rad: np.ndarray
    preload_um: np.ndarray
    curve: FlankCurve | None = None  # recorded (every pin's gap and lever: curve_extremes), when asked
    between: ReferenceFlanks | None = None  # the error-free unit's (reference_revolution), recorded


def revolution(problem: Problem, r: Realization, positions: int = DEFAULT_POSITIONS, exact: bool = True,
               table: PositionTable | None = None, record: bool = False) -> Revolution:
    """Both flanks' positions of unit ``r`` over one output revolution from its crank angle r.chi_rad
    (models.kinematics). ``table``: a PositionTable to reuse; ``record``: keep the recorded curve."""
    g = problem.cycloid
    table = table if table is not None else cached_table(g, positions, float(r.chi_rad))
    theta, curve = revolution_curve(g, r, positions, float(r.chi_rad), kinematics(problem), exact, table, record)
    return Revolution(theta, curve.ccw_rad, curve.cw_rad, curve.preload_um, curve if record else None)


@functools.lru_cache(maxsize=8)
def _reference(g, kin: Kinematics, equidistance_um: float, moving_distance_um: float, clearance_um: float,
               chi0_rad: float, positions: int, exact: bool, record: bool) -> Revolution:
    r = Realization.nominal(g, equidistance_um, moving_distance_um, clearance_um, chi0_rad)
    theta, curve = revolution_curve(g, r, positions, chi0_rad, kin, exact, cached_table(g, positions, chi0_rad),
                                    record)
    between = reference_flanks(curve, g.pitch_radius_um) if record else None
    for x in (*curve, *(between or ())):
        x.flags.writeable = False
    return Revolution(theta, curve.ccw_rad, curve.cw_rad, curve.preload_um, curve if record else None, between)


def reference_revolution(problem: Problem, positions: int, chi0_rad: float = 0.0, exact: bool = True,
                         record: bool = False) -> Revolution:
    """The error-free unit's revolution (``perfect_unit``): the same for every unit of a design, so
    it is computed once per design, start and resolution (cached; read-only arrays). ``record``:
    revolution's."""
    s2 = problem.design.second_stage
    clearance = float(problem.means_um[FACTOR_KEYS.index("pin_hole_clearance")])
    return _reference(problem.cycloid, kinematics(problem), float(s2.equidistance_modification_um),
                      float(s2.moving_distance_modification_um), clearance, float(chi0_rad), int(positions), exact,
                      bool(record))
