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
from rvbacklash.models.contact import (CANG, CCHI, CPSI, EUX, EUY, OX, OY, RHO, SANG, SCHI, SIDE, SPSI, TOOTH, PinGaps,
                                      StageWork, free_interval_bounds, mesh_table, pin_gaps,
                                      stage_play, stage_work)
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
    """Both flanks' output positions [rad] at every output position and the preload [um] (te_curve)."""

    ccw_rad: np.ndarray
    cw_rad: np.ndarray
    preload_um: np.ndarray


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


@njit(nogil=True, cache=True)
def te_curve(stage, kin, table, unit, chi0, scratch, curve, exact):
    """Both flanks' output positions [rad] at every output position of ``table`` (PositionTable: the
    contact model's mesh_table at each) and the preload [um] (0 where the stage is free) into
    ``curve`` (FlankCurve) for the unit whose UnitErrors are ``unit``, its reference position at
    crank angle chi0 (module docstring). ``stage``: StageGeometry; ``kin``: the design's Kinematics;
    ``scratch``: curve_scratch. Where the stage is preloaded both flanks sit at the rotation where
    the interfering pins' forces balance (balanced_rotation, on the linearised gaps) and the lost
    motion is 0. ``exact``:
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
        if not free:
            if exact:
                lo, hi, _ = free_interval_bounds(gaps, stage.pitch_radius_um)
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
                    coef: np.ndarray | None = None) -> FlankCurve:
    """Both flanks' positions [rad] and the preload [um] of one unit (a Realization) at the output
    positions (theta, chis) of ``output_positions``. ``coef``: the mesh_table there
    (``position_table``'s); None: built TABLE_POSITIONS positions at a time (each position is solved
    on its own: the same numbers, in bounded memory)."""
    n = chis.size
    curve = FlankCurve(np.empty(n), np.empty(n), np.empty(n))
    stage, unit, scratch = g.stage_geometry, unit_errors(r, kin.planets), curve_scratch(g.zp, g.zc, g.discs, kin.planets)
    step = TABLE_POSITIONS if coef is None else max(n, 1)
    for start in range(0, n, step):
        part = slice(start, start + step)
        table = PositionTable(theta[part], chis[part], mesh_table(g, chis[part]) if coef is None else coef)
        te_curve(stage, kin, table, unit, float(r.chi_rad), scratch, FlankCurve(*(x[part] for x in curve)), exact)
    return curve


# The extremes of a TE curve between its positions (curve_extremes). The curve has features narrower
# than a position step: in a free stage a flank's position is the first contact, the least of the pins'
# contact rotations, so its TE peaks in a cusp wherever the first contact switches pins (z_c z_p times a
# revolution, 1560 for rv80e: more often than the default 1024 positions); and a preloaded stage whose
# interference only a pin near the line of centres carries (a pin with almost no lever) swings to one
# end of the rotation the other pins leave (balanced_rotation), or is freed for a fraction of a pin pitch
# between two preloaded positions. The sampled peak-to-peak then depends on where the positions fall
# (issue 36 item 8: +4.2 % on average from 1024 to 4096 positions, up to +20.7 %). Refined by branch and
# bound over the steps between positions, for both flanks' min and max at once:
# - a step can hold a value beyond its ends' mean by at most half the largest change between two free
#   neighbours (the curve's sampled slope) times SLOPE_SAFETY;
# - a step with a preloaded end can reach the other flank's position at the free positions beside it
#   (a swing);
# the steps whose bound passes the best value found are searched, largest excess first, at REFINE_POINTS
# sub-steps and then, for the goals the step improved, REFINE_LEVELS zooms of ZOOM_POINTS about their best, until no bound passes
# (at most REFINE_STEPS steps). Not caught: a stage freed, or swung, only between two preloaded positions
# whose curve shows nothing of it (the residue measured in docs/transmission-error.md).
SLOPE_SAFETY, REFINE_POINTS, ZOOM_POINTS, REFINE_LEVELS, REFINE_STEPS = 2.0, 16, 8, 3, 256


def flank_te(g: ContactGeometry, r, reference, kin: Kinematics, theta: np.ndarray,
             exact: bool = True) -> np.ndarray:
    """TE [rad] of both flanks of unit ``r`` (a Realization) at output angles ``theta`` [rad], (2,
    theta.size): ccw, cw. Each flank's position minus the error-free unit's (``reference``) there,
    both from the crank angle r.chi_rad."""
    chi0 = float(r.chi_rad)
    chis = chi0 - g.zc * theta
    coef = mesh_table(g, chis)
    a = flank_positions(g, r, theta, chis, kin, exact, coef)
    b = flank_positions(g, reference, theta, chis, kin, exact, coef)
    return np.stack([a.ccw_rad - b.ccw_rad, a.cw_rad - b.cw_rad])


def curve_extremes(g: ContactGeometry, r, reference, kin: Kinematics, run, ref,
                   exact: bool = True) -> tuple[tuple[float, float], tuple[float, float]]:
    """((min, max) of the ccw flank's TE, (min, max) of the cw flank's) [rad] over the revolution of
    unit ``r``: ``run`` and ``ref`` its and the error-free unit's (``reference``) flank positions and
    the preload at equal output steps from theta = 0 (FlankCurve or Revolution). The sampled
    extremes, refined between the positions (the comment above). A flat curve (the error-free
    unit) is returned as sampled."""
    n = run.ccw_rad.size
    te = np.stack([run.ccw_rad - ref.ccw_rad, run.cw_rad - ref.cw_rad])
    other = np.stack([run.cw_rad - ref.ccw_rad, run.ccw_rad - ref.cw_rad])  # the other flank, on each one's scale
    # objectives: sign * te[flank] to maximise, (flank, sign) in this order
    goals = ((0, 1.0), (0, -1.0), (1, 1.0), (1, -1.0))
    best = np.array([float(sign * te[f].max()) for f, sign in goals])
    if np.ptp(te) == 0.0:
        return (float(te[0].min()), float(te[0].max())), (float(te[1].min()), float(te[1].max()))
    step = 2.0 * math.pi / n
    pre = np.asarray(run.preload_um)
    preloaded = pre > 0.0
    after = np.roll(preloaded, -1)
    free_pair = ~preloaded & ~after  # steps free at both ends
    bounds = np.empty((4, n))
    for i, (f, sign) in enumerate(goals):
        s = sign * te[f]
        nxt = np.roll(s, -1)
        change = np.abs(nxt - s)[free_pair]
        b = 0.5 * (s + nxt) + SLOPE_SAFETY * 0.5 * (float(change.max()) if change.size else 0.0)
        reach = np.where(preloaded, -np.inf, sign * other[f])  # the other flank's position at free positions
        reach = np.maximum.reduce([np.roll(reach, k) for k in (1, 0, -1, -2)])
        b = np.where(preloaded | after, np.maximum(b, reach), b)
        bounds[i] = b
    open_ = np.ones(n, bool)
    for _ in range(REFINE_STEPS):
        excess = np.where(open_, np.max(bounds - best[:, None], axis=0), -np.inf)
        k = int(np.argmax(excess))
        if not excess[k] > 0.0:
            break
        open_[k] = False
        # search step k: sub-steps, then zooms about each goal's best
        at = k * step + step * np.linspace(0.0, 1.0, REFINE_POINTS + 1)
        w = flank_te(g, r, reference, kin, at, exact)
        centres, goals_in = [], []  # zoomed: the goals this step improved
        for i, (f, sign) in enumerate(goals):
            j = int(np.argmax(sign * w[f]))
            if sign * w[f, j] > best[i]:
                best[i] = float(sign * w[f, j])
                centres.append(at[j])
                goals_in.append(i)
        half = step / REFINE_POINTS
        for _ in range(REFINE_LEVELS if goals_in else 0):
            offsets = half * np.linspace(-1.0, 1.0, ZOOM_POINTS + 1)
            at = (np.array(centres)[:, None] + offsets[None, :]).ravel()
            w = flank_te(g, r, reference, kin, at, exact).reshape(2, len(goals_in), ZOOM_POINTS + 1)
            for c, i in enumerate(goals_in):
                f, sign = goals[i]
                j = int(np.argmax(sign * w[f, c]))
                best[i] = max(best[i], float(sign * w[f, c, j]))
                centres[c] = centres[c] + offsets[j]
            half *= 2.0 / ZOOM_POINTS
    return (-best[1], best[0]), (-best[3], best[2])


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
                     table: PositionTable | None) -> tuple[np.ndarray, FlankCurve]:
    """(theta, FlankCurve) of unit ``r`` at ``positions`` output positions from chi0 (``table``:
    their PositionTable, or None)."""
    if table is None:
        theta, chis = output_positions(g, positions, chi0_rad)
        return theta, flank_positions(g, r, theta, chis, kin, exact)
    return table.theta_rad, flank_positions(g, r, table.theta_rad, table.chi_rad, kin, exact, table.coef)


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


def revolution(problem: Problem, r: Realization, positions: int = DEFAULT_POSITIONS, exact: bool = True,
               table: PositionTable | None = None) -> Revolution:
    """Both flanks' positions of unit ``r`` over one output revolution from its crank angle r.chi_rad
    (models.kinematics). ``table``: a PositionTable to reuse."""
    g = problem.cycloid
    table = table if table is not None else cached_table(g, positions, float(r.chi_rad))
    theta, curve = revolution_curve(g, r, positions, float(r.chi_rad), kinematics(problem), exact, table)
    return Revolution(theta, curve.ccw_rad, curve.cw_rad, curve.preload_um)


@functools.lru_cache(maxsize=8)
def _reference(g, kin: Kinematics, equidistance_um: float, moving_distance_um: float, clearance_um: float,
               chi0_rad: float, positions: int, exact: bool) -> Revolution:
    r = Realization.nominal(g, equidistance_um, moving_distance_um, clearance_um, chi0_rad)
    theta, curve = revolution_curve(g, r, positions, chi0_rad, kin, exact, cached_table(g, positions, chi0_rad))
    for x in curve:
        x.flags.writeable = False
    return Revolution(theta, curve.ccw_rad, curve.cw_rad, curve.preload_um)


def reference_revolution(problem: Problem, positions: int, chi0_rad: float = 0.0, exact: bool = True) -> Revolution:
    """The error-free unit's revolution (``perfect_unit``): the same for every unit of a design, so
    it is computed once per design, start and resolution (cached; read-only arrays)."""
    s2 = problem.design.second_stage
    clearance = float(problem.means_um[FACTOR_KEYS.index("pin_hole_clearance")])
    return _reference(problem.cycloid, kinematics(problem), float(s2.equidistance_modification_um),
                      float(s2.moving_distance_modification_um), clearance, float(chi0_rad), int(positions), exact)
