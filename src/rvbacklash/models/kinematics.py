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

import numpy as np

from rvbacklash._numba import njit
from rvbacklash.factors.catalog import FACTOR_KEYS
from rvbacklash.geometry.cycloid import ContactGeometry
from rvbacklash.models.contact import (CANG, CCHI, CPSI, EUX, EUY, OX, OY, RHO, SANG, SCHI, SIDE, SPSI, TOOTH,
                                      Realization, _linear_maxmin, free_interval_bounds, mesh_table, stage_play,
                                      stage_work, unit_arrays)
from rvbacklash.problem import Problem

ARCSEC_PER_RAD = 648000.0 / math.pi
DEFAULT_POSITIONS = 1024  # output positions per revolution of one unit's curve: orders up to 512


def output_positions(g: ContactGeometry, positions: int, chi0_rad: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """(theta [rad], chi [rad]) of ``positions`` equal steps of one output revolution from the
    reference position theta = 0 (crank angle chi_0): chi = chi_0 - z_c theta."""
    theta = 2.0 * math.pi * np.arange(positions) / positions
    return theta, chi0_rad - g.zc * theta


@njit(nogil=True, cache=True)
def crank_fit(hole_disc_um, hole_carrier_um, crank_radius_mm, planets, discs, shift_um, turn_rad):
    """Rigid placement of each disc on the P eccentrics (module docstring): crank-hole position
    errors of the discs (discs, P, 2) and of the carrier (P, 2) [um, carrier frame] -> per disc the
    translation (shift_um (discs, 2) [um]) and the rotation against the carrier (turn_rad (discs,)).
    Hole k nominally at R_c (cos 2 pi k / P, sin 2 pi k / P). The least-squares fit of a rigid
    motion to P point misfits m_k: translation = mean m_k, rotation = sum H_k x (m_k - mean) /
    sum |H_k|^2 (small angles)."""
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
def crank_angle_errors(theta, centre_ecc_um, planet_ecc_um, ratio, zp, base_radius_mm, out):
    """Angle error of each crank d chi_k [rad] at output angle theta from the involute stage: the
    centre gear (turning (i - 1) theta against the carrier) and planet k (turning -z_p theta) with
    eccentricity vectors e [um] in their own frames; each moves the mesh of planet k (at 2 pi k / P
    in the carrier) along its tangent by e . t, t the tangent at the mesh seen from the gear, and
    turns the planet by that over its base radius r_b2 [mm] (the centre gear is the reference:
    the input's angle is read on it). Transmission error of an eccentric gear pair: Smith, Gear
    Noise and Vibration (2003), ch. 2 (once-per-rev line of amplitude e / r_b)."""
    planets = out.size
    p1 = (ratio - 1.0) * theta
    p2 = -zp * theta
    for k in range(planets):
        gk = 2.0 * math.pi * k / planets
        a1 = gk - p1  # the mesh direction in the centre gear's frame
        d1 = -centre_ecc_um[0] * math.sin(a1) + centre_ecc_um[1] * math.cos(a1)
        a2 = gk + math.pi - p2  # the mesh (towards the axis) in planet k's frame
        d2 = -planet_ecc_um[k, 0] * math.sin(a2) + planet_ecc_um[k, 1] * math.cos(a2)
        out[k] = (d1 - d2) * 1e-3 / base_radius_mm


@njit(nogil=True, cache=True)
def unit_pins(coef, rp, dr, dt, rho, cl, cx, cy, base):
    """What of a unit's pins does not change as the output turns: each pin centre in the housing
    frame (cx, cy) [mm] and its gap's constant part -rho + cl / 2 [um] (``pin_in_disc``, hoisted)."""
    for j in range(cx.size):
        rad = rp + dr[j] * 1e-3
        cpsi, spsi = coef[CPSI, 0, j], coef[SPSI, 0, j]
        cx[j] = rad * cpsi - dt[j] * 1e-3 * spsi
        cy[j] = rad * spsi + dt[j] * 1e-3 * cpsi
        base[j] = -rho[j] + 0.5 * cl[j]


@njit(nogil=True, cache=True)
def free_interval(coef, a, rp, zp, discs, azc_um, cx, cy, base, teeth, eq, md, ux, uy, da, gap, lever, scratch):
    """``models.contact.unit_gaps`` without the pin centres it keeps for the exact solve, the pins'
    constant part hoisted (``unit_pins``): every pin's gap [um] and lever [um/rad] at beta = 0 into
    gap/lever; returns (lo, hi, flat) as unit_gaps does. The production run's fast path. As in
    unit_gaps, each disc's pins are one pass the compiler runs four at a time, their tooth pitch
    errors gathered first into ``scratch`` (z_p)."""
    for d in range(discs):
        ex, ey, cang, sang = coef[CCHI, d, 0], coef[SCHI, d, 0], coef[CANG, d, 0], coef[SANG, d, 0]
        off = a + da[d] * 1e-3
        dx = off * ex + (ux[d] * ex - uy[d] * ey) * 1e-3  # the disc centre and its profile offset [mm]
        dy = off * ey + (ux[d] * ey + uy[d] * ex) * 1e-3
        mdd = md[d] * 1e-3
        tooth, teeth_d = coef[TOOTH, d], teeth[d]
        for j in range(zp):
            scratch[j] = teeth_d[int(tooth[j])]
        ox_, oy_, eux, euy, side, rho_c = coef[OX, d], coef[OY, d], coef[EUX, d], coef[EUY, d], coef[SIDE, d], \
            coef[RHO, d]
        eqd, gap_d, lever_d = eq[d], gap[d], lever[d]
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
    return free_interval_bounds(gap, lever, discs, zp, azc_um)


@njit(nogil=True, cache=True)
def te_curve(coef, chis, thetas, chi0, a, rp, zc, zp, discs, azc_um, ratio, base_radius_mm, crank_radius_mm,
             dr, dt, rho, cl, teeth0, eq, md, ux0, uy0, da, centre_ecc_um, planet_ecc_um, shift_um, turn_rad,
             teeth, ux, uy, dchi, gap, lever, work, res, te_ccw, te_cw, preload, exact):
    """Both flanks' output positions [rad] at every output position (module docstring) into te_ccw,
    te_cw (N,) and the preload [um] (0 where the stage is free). ``coef`` is the contact model's
    mesh_table at ``chis``; shift_um/turn_rad come from crank_fit; teeth, ux, uy, dchi, gap, lever,
    work, res are scratch. Where the stage is preloaded both flanks sit at the rotation that
    balances the deepest interferences (its linearisation) and the lost motion is 0. ``exact``:
    each first contact solved on the exact curve (stage_play); else linearised at the assembled
    position (unit_gaps' free interval: the production run's fast path, error bounded in the tests)."""
    planets = dchi.size
    pcx, pcy, pbase = np.empty(zp), np.empty(zp), np.empty(zp)
    unit_pins(coef[0], rp, dr, dt, rho, cl, pcx, pcy, pbase)
    for n in range(chis.size):
        chi = chis[n]
        crank_angle_errors(thetas[n], centre_ecc_um, planet_ecc_um, ratio, zp, base_radius_mm, dchi)
        mean = 0.0
        for k in range(planets):
            mean += dchi[k]
        mean /= planets
        w = -(chi - chi0) * zp / zc  # disc-fixed vectors against the eccentric
        cw, sw = math.cos(w), math.sin(w)
        for d in range(discs):
            rel = chi + 2.0 * math.pi * d / discs + chi / zc  # the eccentric's direction in the carrier frame
            cr, sr = math.cos(rel), math.sin(rel)
            ux[d] = cw * ux0[d] - sw * uy0[d] + shift_um[d, 0] * cr + shift_um[d, 1] * sr
            uy[d] = sw * ux0[d] + cw * uy0[d] - shift_um[d, 0] * sr + shift_um[d, 1] * cr + a * mean * 1e3
            turn = turn_rad[d]
            for k in range(planets):  # the cranks' differences turn the disc (crank_fit with a d chi_k e_perp)
                turn += a * (dchi[k] - mean) * math.cos(rel - 2.0 * math.pi * k / planets) / (planets * crank_radius_mm)
            for k in range(zc):
                teeth[d, k] = teeth0[d, k] + turn * rp * 1e3
        if exact:
            stage_play(coef[n], a, rp, zc, zp, discs, azc_um, dr, dt, rho, cl, teeth, eq, md, ux, uy, da,
                       gap, lever, work, res)
        else:
            lo, hi, flat = free_interval(coef[n], a, rp, zp, discs, azc_um, pcx, pcy, pbase, teeth, eq, md, ux, uy,
                                         da, gap, lever, work[2, 0])
            if hi < lo or flat < 0.0:
                res[0] = np.nan
                res[2] = 0.0
            else:
                res[0] = hi
                res[1] = -lo
        if math.isnan(res[0]):
            b = _linear_maxmin(gap, lever, np.inf, np.inf, discs, zp)
            te_ccw[n] = b
            te_cw[n] = b
            preload[n] = res[2]
        else:
            te_ccw[n] = res[0]
            te_cw[n] = -res[1]
            preload[n] = 0.0


@njit(nogil=True, cache=True)
def curve_scratch(zp, zc, discs, planets):
    """Scratch arrays of te_curve: teeth, ux, uy, dchi, gap, lever, work, res."""
    return (np.empty((discs, zc)), np.empty(discs), np.empty(discs), np.empty(planets), np.empty((discs, zp)),
            np.empty((discs, zp)), stage_work(discs, zp), np.empty(7))


def kinematic_arrays(r, discs: int, planets: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The kinematic errors of a Realization (zeros where None): centre-gear eccentricity (2,),
    planet eccentricities (P, 2), disc crank holes (discs, P, 2), carrier crank holes (P, 2) [um]."""
    def arr(v, shape):
        return np.zeros(shape) if v is None else np.ascontiguousarray(np.broadcast_to(np.asarray(v, float), shape))
    return (arr(r.centre_gear_eccentricity_um, (2,)), arr(r.planet_eccentricity_um, (planets, 2)),
            arr(r.disc_crank_hole_um, (discs, planets, 2)), arr(r.carrier_crank_hole_um, (planets, 2)))


def flank_positions(g: ContactGeometry, r, coef: np.ndarray, thetas: np.ndarray, chis: np.ndarray, ratio: float,
                    base_radius_mm: float, crank_radius_mm: float, planets: int, exact: bool = True
                    ) -> tuple[np.ndarray, ...]:
    """(te_ccw, te_cw [rad], preload [um]) of one unit (a models.contact.Realization) at the output
    positions (thetas, chis) of ``output_positions``; ``coef`` = mesh_table(g, chis)."""
    centre, planet, hd, hc = kinematic_arrays(r, g.discs, planets)
    shift, turn = np.empty((g.discs, 2)), np.empty(g.discs)
    crank_fit(hd, hc, crank_radius_mm, planets, g.discs, shift, turn)
    dr, dt, rho, cl, teeth, eq, md, ux, uy, da = (np.ascontiguousarray(x, dtype=float) for x in unit_arrays(r))
    n = chis.size
    te_ccw, te_cw, preload = np.empty(n), np.empty(n), np.empty(n)
    te_curve(coef, chis, thetas, float(r.chi_rad), g.a_mm, g.rp_mm, g.zc, g.zp, g.discs, g.pitch_radius_um,
             float(ratio), float(base_radius_mm), float(crank_radius_mm), dr, dt, rho, cl, teeth, eq, md, ux, uy, da,
             centre, planet, shift, turn, *curve_scratch(g.zp, g.zc, g.discs, planets), te_ccw, te_cw, preload, exact)
    return te_ccw, te_cw, preload


@dataclass(frozen=True)
class Kinematics:
    """What the kinematic model needs of a design besides the contact geometry."""

    ratio: float
    base_radius_mm: float  # r_b2 of the planet gears
    crank_radius_mm: float  # R_c, the circle of crank axes
    planets: int


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
def position_table(g, positions: int, chi0_rad: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(theta, chi, mesh_table) of ``positions`` output positions from crank angle chi0 (built once
    per geometry and start: the table is most of a single curve's cost). Shared: do not modify."""
    theta, chis = output_positions(g, positions, chi0_rad)
    return theta, chis, mesh_table(g, chis)


@dataclass(frozen=True)
class Revolution:
    """Flank positions of one unit [rad] at the output positions (theta [rad]); preload [um]."""

    theta_rad: np.ndarray
    ccw_rad: np.ndarray
    cw_rad: np.ndarray
    preload_um: np.ndarray


def revolution(problem: Problem, r: Realization, positions: int = DEFAULT_POSITIONS, exact: bool = True,
               table: tuple | None = None) -> Revolution:
    """Both flanks' positions of unit ``r`` over one output revolution from its crank angle r.chi_rad
    (models.kinematics). ``table``: (theta, chi, mesh_table) to reuse."""
    g = problem.cycloid
    theta, chis, coef = table if table is not None else position_table(g, positions, float(r.chi_rad))
    k = kinematics(problem)
    ccw, cw, pre = flank_positions(g, r, coef, theta, chis, k.ratio, k.base_radius_mm, k.crank_radius_mm, k.planets,
                                   exact)
    return Revolution(theta, ccw, cw, pre)


@functools.lru_cache(maxsize=8)
def _reference(g, kin: Kinematics, equidistance_um: float, moving_distance_um: float, clearance_um: float,
               chi0_rad: float, positions: int, exact: bool) -> Revolution:
    r = Realization.nominal(g, equidistance_um, moving_distance_um, clearance_um, chi0_rad)
    theta, chis, coef = position_table(g, positions, chi0_rad)
    ccw, cw, pre = flank_positions(g, r, coef, theta, chis, kin.ratio, kin.base_radius_mm, kin.crank_radius_mm,
                                   kin.planets, exact)
    for x in (ccw, cw, pre):
        x.flags.writeable = False
    return Revolution(theta, ccw, cw, pre)


def reference_revolution(problem: Problem, positions: int, chi0_rad: float = 0.0, exact: bool = True) -> Revolution:
    """The error-free unit's revolution (``perfect_unit``): the same for every unit of a design, so
    it is computed once per design, start and resolution (cached; read-only arrays)."""
    s2 = problem.design.second_stage
    clearance = float(problem.means_um[FACTOR_KEYS.index("pin_hole_clearance")])
    return _reference(problem.cycloid, kinematics(problem), float(s2.equidistance_modification_um),
                      float(s2.moving_distance_modification_um), clearance, float(chi0_rad), int(positions), exact)
