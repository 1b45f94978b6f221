"""Geometric contact model of the cycloid-pin mesh (docs/contact.md).

With the input and the carrier locked, each disc may turn about its centre on the eccentric
until its profile touches a pin. Its play in one direction is set by the smallest gap over
all pins, measured against each pin's lever arm: per-pin errors do not add, the first
contact goes to the extreme pin. Two functions compute the play of one realisation of all
errors:

- ``exact_play``: signed distances between the actual pins and the exact modified profile
  (``cycloid_geometry``), root-finding on the disc rotation;
- ``linear_play``: the small-displacement linearisation, gap_j = g_j0 + sum(error x
  coefficient), play = min_j gap_j / L_j. It is what the Monte-Carlo kernel runs; tests bound
  its error against ``exact_play``.

Assumptions: rigid bodies, no load; a pin floats in its housing hole and gives way by half its
diametral clearance; the discs are tied together by the cranks, so the output turns until the
first contact of either disc; a disc's rotation is referred to the output as in Eq. (1)
(lever arm a z_c; docs/model.md discusses the exact kinematic lever arm).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

from rvbacklash._numba import njit, njit_borrowing
import numpy as np

from rvbacklash.geometry.cycloid import ContactGeometry, PinCentreCurve, rotate
from rvbacklash.models.unit_errors import Realization, unit_errors
from rvbacklash.units import ARCMIN_PER_RAD

PRELOAD_TOL_UM = 1e-6  # interference below a picometre is contact, not preload (round-off of the geometry)
PRELOAD_STEP_UM = 1e-6  # the preload's max-min search stops when the two lowest gaps agree to a picometre


@dataclass(frozen=True)
class DiscPlay:
    """Free rotation of one disc [rad] in each direction from the assembled position (beta = 0)
    and the pins that stop it; NaN and pin -1 when no rotation frees every pin of the disc."""

    play_ccw_rad: float
    play_cw_rad: float
    contact_pin_ccw: int
    contact_pin_cw: int

    @property
    def total_rad(self) -> float:
        return self.play_ccw_rad + self.play_cw_rad


@dataclass(frozen=True)
class MeshPlay:
    """Play of the cycloid stage. The cranks tie the discs: the output turns until the first
    contact of either disc. ``preload_um`` > 0: no rotation frees every pin; it is the smallest
    uniform clearance (normal to the profile, like an equidistance modification) that would.
    ``discs`` holds each disc's own play where it was resolved (exact play)."""

    discs: tuple[DiscPlay, ...]
    preload_um: float
    pitch_radius_um: float  # a z_c, to express a preload as a (negative) play
    play_ccw_rad: float  # free rotation of the stage from the assembled position (NaN if preloaded)
    play_cw_rad: float

    @property
    def preloaded(self) -> bool:
        return self.preload_um > 0.0

    @property
    def total_rad(self) -> float:
        """Free rotation of the stage [rad]; when preloaded, the play an equidistance modification of
        -preload would give, -2 preload / (a z_c): negative, and only its sign is a play."""
        if self.preloaded:
            return -2.0 * self.preload_um / self.pitch_radius_um
        return self.play_ccw_rad + self.play_cw_rad

    @property
    def lost_motion_rad(self) -> float:
        return max(self.total_rad, 0.0)

    @property
    def total_arcmin(self) -> float:
        return self.total_rad * ARCMIN_PER_RAD

    @property
    def lost_motion_arcmin(self) -> float:
        return self.lost_motion_rad * ARCMIN_PER_RAD


# --- the Monte-Carlo kernel: osculating circles and an exact refinement ------------------------

# Columns of the table of one pin at one crank angle (mesh_table): the tooth space facing it, its
# parameter on the pin-centre curve C, and C's osculating circle at the pin (centre, radius, on
# which side), the direction in which a moving-distance modification shifts C there.
TOOTH, T0, OX, OY, RHO, SIDE, EUX, EUY, CPSI, SPSI, CCHI, SCHI, CANG, SANG = range(14)
N_COEF = 14  # the last six: cos and sin of the pin's angle, of the disc's crank angle and of chi_d / z_c
RHO_MAX_MM = 1e3  # near an inflection of C its osculating circle is a line: 1 m is straight enough
# Pins whose estimated contact rotation is within a band of the first are checked on the exact curve:
# the osculating circle's error is third order in the displacement over its radius, so a pin on a
# tightly bent stretch of C (radius below RHO_TIGHT_MM, near the tooth tips) gets the wide band.
BAND_WIDE, BAND_NARROW, RHO_TIGHT_MM = 0.10, 0.005, 3.0


class PinGaps(NamedTuple):
    """Every pin's gap and lever at zero rotation, (discs, z_p) each (unit_gaps): what the elastic
    model reads of a unit."""

    gap_um: np.ndarray  # free gap of pin j to disc d, normal to the profile [um] (negative: interference)
    lever_um_per_rad: np.ndarray  # gap(beta) = gap - lever beta [um/rad] (> 0 stops a ccw rotation)


class StageWork(NamedTuple):
    """Scratch of unit_gaps and stage_play, (discs, z_p) each."""

    pin_x_mm: np.ndarray  # each pin's centre in its disc's frame (unit_gaps)
    pin_y_mm: np.ndarray
    pin_tooth_pitch_um: np.ndarray  # the tooth pitch error facing each pin, gathered (unit_gaps)
    closing_distance_mm: np.ndarray  # the distance from its osculating circle's centre at which a gap closes
    estimate_rad: np.ndarray  # each pin's estimated contact rotation (stage_play)
    value_um: np.ndarray  # each gap and its lever on the osculating circles at one rotation (_lowest_gaps)
    lever_um_per_rad: np.ndarray


class FreeInterval(NamedTuple):
    """The linearised free interval of a unit's turn (unit_gaps, free_interval_bounds): lo <= beta <=
    hi [rad], and the smallest gap of a pin without a lever [um]."""

    lo_rad: float
    hi_rad: float
    flat_um: float


class StagePlay(NamedTuple):
    """The cycloid stage's play (stage_play): its free rotation from the assembled position in
    each direction [rad] and the pin (and its disc) that stops it; when preloaded, NaN plays, pins
    -1 and the preload [um] (0 when free)."""

    play_ccw_rad: float
    play_cw_rad: float
    preload_um: float
    pin_ccw: int
    disc_ccw: int
    pin_cw: int
    disc_cw: int


class DiscFrame(NamedTuple):
    """Where a disc sits (pin_in_disc): the cos and sin of its crank angle chi_d and of its turn
    chi_d / z_c, and its profile's offset: run-out along and across the eccentric, eccentricity
    error [um]."""

    cos_chi: float
    sin_chi: float
    cos_turn: float
    sin_turn: float
    runout_along_um: float
    runout_across_um: float
    eccentricity_error_um: float


class Turn(NamedTuple):
    """A disc rotation's start beta [rad] (its cos and sin) and direction (+1: counter-clockwise)."""

    beta_rad: float
    cos_beta: float
    sin_beta: float
    sign: float


@njit(nogil=True, cache=True, inline="always")
def crank_step_angle_rad(step, zp, steps):
    """The crank angle of step ``step`` of ``steps`` per pin pitch (the geometry repeats every pin
    pitch; a production run measures each unit at one of them): chi = 2 pi / z_p (step + 1/2) /
    steps [rad]."""
    return 2.0 * math.pi / zp * (step + 0.5) / steps


@njit(nogil=True, cache=True, inline="always")
def pin_base_um(unit, d, j):
    """The part of pin j's gap to disc d [um] that does not depend on where the pin sits: the disc's
    equidistance modification, less the pin's radius error, plus half its hole's clearance."""
    return unit.equidistance_um[d] - unit.pin_radius_um[j] + 0.5 * unit.pin_clearance_um[j]


@njit(nogil=True, cache=True, inline="always")
def recorded_stage(play):
    """The cycloid stage as a run records a unit's (``--save-units``): its play [arcmin] from a
    StagePlay, or -preload [um] when preloaded."""
    if math.isnan(play.play_ccw_rad):
        return -play.preload_um
    return (play.play_ccw_rad + play.play_cw_rad) * ARCMIN_PER_RAD


@njit(nogil=True, cache=True)
def stage_work(discs, zp):
    """Scratch space of stage_play and unit_gaps."""
    return StageWork(np.empty((discs, zp)), np.empty((discs, zp)), np.empty((discs, zp)), np.empty((discs, zp)),
                     np.empty((discs, zp)), np.empty((discs, zp)), np.empty((discs, zp)))


@njit(nogil=True, cache=True)
def pin_gaps(discs, zp):
    """An empty PinGaps to compute into."""
    return PinGaps(np.empty((discs, zp)), np.empty((discs, zp)))


def mesh_table(g: ContactGeometry, chis: np.ndarray) -> np.ndarray:
    """The osculating circle of the nominal pin-centre curve C at every pin of every disc, at the
    crank angles ``chis`` [rad]: shape (len(chis), N_COEF, discs, z_p), disc frame [mm]. Columns
    first: the kernels' loops over the pins read each column contiguously, which lets the compiler
    run them four pins at a time (SIMD).

    A nominal pin centre lies on C at parameter T0 = chi_d - psi_j + 2 pi j. There C has the
    centre of curvature (OX, OY) and radius RHO = |C'|^3 / |C' x C''| (do Carmo, Differential
    Geometry of Curves and Surfaces, 1.5); SIDE = +1 where the centre lies on the disc's side
    (the gap of a point is |q - O| - RHO), -1 where it lies outside (RHO - |q - O|). A moving
    distance dr_p shifts C by dr_p (cos(t/z_c), sin(t/z_c)) = dr_p (EUX, EUY).
    """
    chis = np.atleast_1d(np.asarray(chis, float))
    j = np.arange(g.zp)
    chi_d = chis[:, None] + 2 * math.pi * np.arange(g.discs)[None, :] / g.discs  # (n, discs)
    t = chi_d[:, :, None] - g.pin_angles[None, None, :] + 2 * math.pi * j[None, None, :]
    curve = PinCentreCurve(g.a_mm, g.rp_mm, g.zc)
    p, d1 = curve.point(t), curve.d1(t)
    d2 = _curve_d2_exact(g.a_mm, g.rp_mm, g.zc, t)
    cross = d1[..., 0] * d2[..., 1] - d1[..., 1] * d2[..., 0]
    speed = np.linalg.norm(d1, axis=-1)
    rho = np.minimum(speed ** 3 / np.maximum(np.abs(cross), 1e-300), RHO_MAX_MM)
    left = np.stack([-d1[..., 1], d1[..., 0]], axis=-1) / speed[..., None]
    to_centre = np.where((cross >= 0)[..., None], left, -left)
    centre = p + rho[..., None] * to_centre
    outward = curve.outward_normal(t)
    out = np.empty(t.shape + (N_COEF,))
    out[..., TOOTH] = np.floor(j[None, None, :] * g.zc / g.zp + chi_d[:, :, None] / (2 * math.pi) + 0.5) % g.zc
    out[..., T0] = t
    out[..., OX], out[..., OY] = centre[..., 0], centre[..., 1]
    out[..., RHO] = rho
    out[..., SIDE] = np.where(np.sum(to_centre * outward, axis=-1) < 0, 1.0, -1.0)
    out[..., EUX], out[..., EUY] = np.cos(t / g.zc), np.sin(t / g.zc)
    out[..., CPSI], out[..., SPSI] = np.cos(g.pin_angles), np.sin(g.pin_angles)
    out[..., CCHI], out[..., SCHI] = np.cos(chi_d)[:, :, None], np.sin(chi_d)[:, :, None]
    out[..., CANG], out[..., SANG] = np.cos(chi_d / g.zc)[:, :, None], np.sin(chi_d / g.zc)[:, :, None]
    return np.ascontiguousarray(np.moveaxis(out, -1, 1))


@njit(nogil=True, cache=True)
def mesh_column(stage, chi, out):
    """``mesh_table`` at one crank angle chi [rad], compiled, into ``out`` (N_COEF, discs, z_p):
    the same closed forms, so a kernel can place the mesh anywhere between a table's positions (the
    transmission model's production run refines its extremes there: models.te_refine). Equal to
    mesh_table's row to round-off (tested). The angles are built by angle addition from the disc's
    and the pins' (t = chi_d - psi_j + 2 pi j: cos t = cos(chi_d - psi_j); t / z_c = chi_d / z_c +
    (2 pi j - psi_j) / z_c), so a column costs 2 z_p + 4 discs sines and cosines, not 8 z_p discs;
    ``mesh_column_at`` takes the pins' (mesh_pin_angles) computed once: 4 discs.
    ``stage``: StageGeometry."""
    pins = np.empty((4, stage.zp))
    mesh_pin_angles(stage, pins)
    mesh_column_at(stage, chi, pins, out)


@njit(nogil=True, cache=True)
def mesh_pin_angles(stage, pins):
    """What of ``mesh_column`` does not depend on the crank angle, into ``pins`` (4, z_p): cos and sin of
    each pin's angle psi_j = 2 pi j / z_p and of w_j = (2 pi j - psi_j) / z_c."""
    zc, zp = stage.zc, stage.zp
    for j in range(zp):
        psi = 2.0 * math.pi * j / zp
        pins[0, j] = math.cos(psi)
        pins[1, j] = math.sin(psi)
        w = (2.0 * math.pi * j - psi) / zc  # = psi when z_p = z_c + 1
        pins[2, j] = math.cos(w)
        pins[3, j] = math.sin(w)


@njit(nogil=True, cache=True)
def mesh_column_at(stage, chi, pins, out):
    """``mesh_column`` with the pins' angles given (``pins``: mesh_pin_angles)."""
    a, rg, zc, zp, discs = stage.a_mm, stage.rp_mm, stage.zc, stage.zp, stage.discs
    k = 1.0 / zc
    for d in range(discs):
        chi_d = chi + 2.0 * math.pi * d / discs
        cchi, schi = math.cos(chi_d), math.sin(chi_d)
        cang, sang = math.cos(chi_d / zc), math.sin(chi_d / zc)
        for j in range(zp):
            cpsi, spsi, cw, sw = pins[0, j], pins[1, j], pins[2, j], pins[3, j]
            ct, st = cchi * cpsi + schi * spsi, schi * cpsi - cchi * spsi  # t = chi_d - psi_j (mod 2 pi)
            cu, su = cang * cw - sang * sw, sang * cw + cang * sw  # u = t / z_c
            bx, by = rg - a * ct, -a * st  # curve_point's closed forms
            dbx, dby = a * st, -a * ct
            ddbx, ddby = a * ct, a * st
            x, y = cu * bx - su * by, su * bx + cu * by
            px, py = dbx - k * by, dby + k * bx
            qx, qy = ddbx - 2 * k * dby - k * k * bx, ddby + 2 * k * dbx - k * k * by
            dx, dy = cu * px - su * py, su * px + cu * py
            ddx, ddy = cu * qx - su * qy, su * qx + cu * qy
            cross = dx * ddy - dy * ddx
            speed = math.sqrt(dx * dx + dy * dy)
            rho = min(speed ** 3 / max(abs(cross), 1e-300), RHO_MAX_MM)
            lx, ly = -dy / speed, dx / speed  # the left normal, towards the centre of curvature
            if cross < 0.0:
                lx, ly = -lx, -ly
            nx, ny = dy / speed, -dx / speed  # the outward normal (PinCentreCurve.outward_normal)
            if nx * x + ny * y < 0.0:
                nx, ny = -nx, -ny
            out[TOOTH, d, j] = math.floor(j * zc / zp + chi_d / (2.0 * math.pi) + 0.5) % zc
            out[T0, d, j] = chi_d - 2.0 * math.pi * j / zp + 2.0 * math.pi * j
            out[OX, d, j] = x + rho * lx
            out[OY, d, j] = y + rho * ly
            out[RHO, d, j] = rho
            out[SIDE, d, j] = 1.0 if lx * nx + ly * ny < 0.0 else -1.0
            out[EUX, d, j] = cu
            out[EUY, d, j] = su
            out[CPSI, d, j] = cpsi
            out[SPSI, d, j] = spsi
            out[CCHI, d, j] = cchi
            out[SCHI, d, j] = schi
            out[CANG, d, j] = cang
            out[SANG, d, j] = sang


def _curve_d2_exact(a: float, rg: float, zc: int, t: np.ndarray) -> np.ndarray:
    """d2C/dt2 [mm/rad^2] in closed form (curve_point's, vectorised)."""
    k = 1.0 / zc
    bx, by = rg - a * np.cos(t), -a * np.sin(t)
    dbx, dby = a * np.sin(t), -a * np.cos(t)
    qx = a * np.cos(t) - 2 * k * dby - k * k * bx
    qy = a * np.sin(t) + 2 * k * dbx - k * k * by
    u = t * k
    return np.stack([np.cos(u) * qx - np.sin(u) * qy, np.sin(u) * qx + np.cos(u) * qy], axis=-1)


@njit(nogil=True, cache=True)
def curve_point(a, rg, zc, t):
    """C(t) of geometry.cycloid.PinCentreCurve and its first and second derivatives [mm]."""
    ct, st = math.cos(t), math.sin(t)
    u = t / zc
    cu, su = math.cos(u), math.sin(u)
    bx, by = rg - a * ct, -a * st  # base point before the rotation by t / z_c
    dbx, dby = a * st, -a * ct
    ddbx, ddby = a * ct, a * st
    k = 1.0 / zc
    x, y = cu * bx - su * by, su * bx + cu * by
    # d/dt [R(u) b] = R(u) b' + k R(u) J b ;  d2/dt2 = R(u) b'' + 2k R(u) J b' - k^2 R(u) b
    px, py = dbx - k * by, dby + k * bx
    qx, qy = ddbx - 2 * k * dby - k * k * bx, ddby + 2 * k * dbx - k * k * by
    return x, y, cu * px - su * py, su * px + cu * py, cu * qx - su * qy, su * qx + cu * qy


@njit(nogil=True, cache=True)
def curve_distance(a, rg, zc, qx, qy, t0):
    """(signed distance [um] of the point (qx, qy) [mm] from the pin-centre curve, positive away
    from the disc; the curve parameter t of its foot; the unit outward normal there (nx, ny)):
    Newton on (C(t) - q) . C'(t) = 0 from t0, as PinCentreCurve.signed_distance. A start from a
    nearby point's foot converges in 1-2 steps. The distance is read at the last foot once its
    Newton step is below 1e-9: the normal projection's error is second order in the foot's,
    |C'|^2 kappa step^2 / 2 < 1e-13 um with |C'| < 4 mm and kappa < 10 /mm."""
    t = t0
    for _ in range(12):
        x, y, dx, dy, ddx, ddy = curve_point(a, rg, zc, t)
        rx, ry = x - qx, y - qy
        f = rx * dx + ry * dy
        fp = dx * dx + dy * dy + rx * ddx + ry * ddy
        step = f / fp
        t -= step  # for the next start; this foot's point (x, y) gives the distance
        if abs(step) < 1e-9:
            break
    nx, ny = dy, -dx
    if nx * x + ny * y < 0:  # outward: away from the disc centre
        nx, ny = -nx, -ny
    norm = math.sqrt(nx * nx + ny * ny)
    nx, ny = nx / norm, ny / norm
    return ((qx - x) * nx + (qy - y) * ny) * 1e3, t, nx, ny


@njit(nogil=True, cache=True)
def turned_gap(px, py, beta, base_um, a, rg, zc, t0):
    """(gap [um], d gap / d beta [um/rad], foot parameter) of a pin at (px, py) in its disc's frame
    [mm] once the disc has turned by beta [rad]: base_um (eq_d - rho_j + cl_j / 2) plus its signed
    distance from the curve of generating radius rg [mm] (the disc's modification included). The
    pin turns to q = R(-beta) p, dq/dbeta = (q_y, -q_x), and the distance's gradient is the unit
    normal at the foot."""
    cb, sb = math.cos(beta), math.sin(beta)
    qx, qy = cb * px + sb * py, -sb * px + cb * py
    dist, t, nx, ny = curve_distance(a, rg, zc, qx, qy, t0)
    return base_um + dist, (nx * qy - ny * qx) * 1e3, t


@njit(nogil=True, cache=True)
def exact_gap_um(j, d, beta, chi, stage, unit, t0):
    """Exact gap [um] of pin j to disc d turned by beta [rad]: the pin centre with all its errors
    in the disc frame, its signed distance from the modified pin-centre curve (the compiled form
    of ``exact_gaps_um``, one pin at a time)."""
    px, py = pin_frame(j, d, chi, stage, unit)
    return turned_gap(px, py, beta, pin_base_um(unit, d, j), stage.a_mm, stage.rp_mm + unit.moving_distance_um[d] * 1e-3, stage.zc,
                      t0)[0]


@njit(nogil=True, cache=True)
def pin_in_disc(cpsi, spsi, dr_j, dt_j, tooth, frame, a, rp):
    """Centre of a pin with all its errors in the frame of its disc (not turned) [mm]: the pin at
    angle psi (cos, sin) displaced radially by dr and tangentially by dt [um], less the disc
    centre a (1 + da) along the eccentric e and its profile offset (ux, uy) [um] (``frame``, a
    DiscFrame), turned into the disc frame by chi_d / z_c and back by the tooth space's pitch error
    [um] at r_p."""
    ex, ey, cang, sang = frame.cos_chi, frame.sin_chi, frame.cos_turn, frame.sin_turn
    ux_d, uy_d = frame.runout_along_um, frame.runout_across_um
    rad = rp + dr_j * 1e-3
    cx = rad * cpsi - dt_j * 1e-3 * spsi
    cy = rad * spsi + dt_j * 1e-3 * cpsi
    off = a + frame.eccentricity_error_um * 1e-3
    px = cx - off * ex - (ux_d * ex - uy_d * ey) * 1e-3
    py = cy - off * ey - (ux_d * ey + uy_d * ex) * 1e-3
    dl = -tooth * 1e-3 / rp  # a pitch error is a small angle: cos, sin to 4th order
    dl2 = dl * dl  # (not dl ** 4: a power call would stop unit_gaps' loop from running four pins at a time)
    cdl, sdl = 1.0 - 0.5 * dl2 + dl2 * dl2 / 24.0, dl - dl2 * dl / 6.0
    ca, sa = cang * cdl - sang * sdl, sang * cdl + cang * sdl
    return ca * px - sa * py, sa * px + ca * py


@njit(nogil=True, cache=True)
def pin_frame(j, d, chi, stage, unit):
    """Centre of pin j with all its errors in the frame of disc d (not turned) [mm], at crank angle chi."""
    zc, zp = stage.zc, stage.zp
    chi_d = chi + 2.0 * math.pi * d / stage.discs
    psi = 2.0 * math.pi * j / zp
    k = int(math.floor(j * zc / zp + chi_d / (2.0 * math.pi) + 0.5)) % zc
    frame = DiscFrame(math.cos(chi_d), math.sin(chi_d), math.cos(chi_d / zc), math.sin(chi_d / zc),
                      unit.runout_along_um[d], unit.runout_across_um[d], unit.eccentricity_error_um[d])
    return pin_in_disc(math.cos(psi), math.sin(psi), unit.pin_radial_um[j], unit.pin_tangential_um[j],
                       unit.tooth_pitch_um[d, k], frame, stage.a_mm, stage.rp_mm)


@njit(nogil=True, cache=True)
def _contact_rotation(c0, p1, p2, dt_mm, start, sgn):
    """Smallest x > 0 such that the disc turned by start + sgn x brings the pin to the distance
    dt_mm from the circle's centre: D(beta)^2 = c0 - 2 (p1 cos beta + p2 sin beta); inf if never."""
    r = math.sqrt(p1 * p1 + p2 * p2)
    if r == 0.0:
        return np.inf
    v = (c0 - dt_mm * dt_mm) / (2.0 * r)
    if v > 1.0 or v < -1.0:
        return np.inf
    gamma = math.atan2(p2, p1)
    w = math.acos(v)
    best = np.inf
    for root in (gamma + w, gamma - w):
        root += 2.0 * math.pi * math.floor((start - root) / (2.0 * math.pi) + 0.5)  # the turn nearest to start
        for shift in (-2.0 * math.pi, 0.0, 2.0 * math.pi):
            x = sgn * (root + shift - start)
            if 0.0 < x < best:
                best = x
    return best


@njit(nogil=True, cache=True, inline="always")
def _contact_rotation_bound(c0, p1, p2, dt_mm, side, turn):
    """A lower bound [rad] of _contact_rotation(c0, p1, p2, dt_mm, start, sgn), without its
    trigonometry (``turn``: start, its cos and sin, sgn; side: the pin's SIDE). h(beta) = SIDE (D^2(beta) -
    dt^2) has the sign of the gap, and |h''| = |2 (p1 cos beta + p2 sin beta)| <= 2 r with r = |(p1,
    p2)|, so h(start + sgn x) >= H - S x - r x^2, H = h(start), S = -sgn h'(start) (Taylor); the
    positive root of the right side, 2 H / (S + sqrt(S^2 + 4 r H)), comes no later than the contact.
    0 when the pin is not free at start (H <= 0)."""
    cs, ss, sgn = turn.cos_beta, turn.sin_beta, turn.sign
    h = side * (c0 - dt_mm * dt_mm - 2.0 * (p1 * cs + p2 * ss))
    if h <= 0.0:
        return 0.0
    rate = -sgn * 2.0 * side * (p1 * ss - p2 * cs)
    return 2.0 * h / (rate + math.sqrt(rate * rate + 4.0 * math.sqrt(p1 * p1 + p2 * p2) * h))


@njit(nogil=True, cache=True)
def _linear_maxmin(gaps, lo, hi):
    """The rotation maximising min_j (gap_j - lever_j beta) of PinGaps ``gaps`` (active-set
    iteration on the lines)."""
    gap, lever = gaps.gap_um, gaps.lever_um_per_rad
    discs, zp = gap.shape
    beta = 0.5 * (lo + hi) if math.isfinite(lo) and math.isfinite(hi) else 0.0
    for _ in range(50):
        fall, rise = np.inf, np.inf
        gf, lf, gr, lr = 0.0, 0.0, 0.0, 0.0
        for d in range(discs):
            for j in range(zp):
                v = gap[d, j] - lever[d, j] * beta
                if lever[d, j] > 0.0:
                    if v < fall:
                        fall, gf, lf = v, gap[d, j], lever[d, j]
                elif v < rise:
                    rise, gr, lr = v, gap[d, j], lever[d, j]
        if not (math.isfinite(fall) and math.isfinite(rise)) or lf == lr:
            break
        nxt = (gf - gr) / (lf - lr)
        if abs(nxt - beta) <= 1e-15 + 1e-12 * abs(beta):
            break
        beta = nxt
    return beta


@njit(nogil=True, cache=True, inline="always")
def _circle_terms(ox, oy, eux, euy, qx, qy, md_d):
    """(c0, p1, p2) [mm^2] of a pin's distance from its osculating circle's centre as the disc turns
    by beta: D^2(beta) = c0 - 2 (p1 cos beta + p2 sin beta); (ox, oy) the circle's centre and (eux,
    euy) its shift per moving distance (mesh_table's OX, OY, EUX, EUY), (qx, qy) the pin's centre
    in the disc frame [mm], md_d its disc's moving-distance modification [um]."""
    ox = ox + md_d * 1e-3 * eux
    oy = oy + md_d * 1e-3 * euy
    return qx * qx + qy * qy + ox * ox + oy * oy, qx * ox + qy * oy, qy * ox - qx * oy


@njit(nogil=True, cache=True, inline="always")
def _screened_contact(coef, work, md_d, d, j, first_lin, first, turn):
    """Contact rotation [rad] of pin j of disc d on its osculating circle from ``turn``'s start in
    its direction (_contact_rotation), or inf when screened out: its linear estimate
    (work.estimate_rad) is beyond 3 first_lin (unless on a tightly bent stretch of C), it never
    closes (closing distance <= 0), or its lower bound (_contact_rotation_bound) is beyond the band
    of ``first``. md_d: its disc's moving-distance modification [um]."""
    rho_c = coef[RHO, d, j]
    est, tgt = work.estimate_rad[d, j], work.closing_distance_mm[d, j]
    if (est > 3.0 * first_lin and rho_c >= RHO_TIGHT_MM) or tgt <= 0.0:
        return np.inf
    c0, p1, p2 = _circle_terms(coef[OX, d, j], coef[OY, d, j], coef[EUX, d, j], coef[EUY, d, j], work.pin_x_mm[d, j],
                               work.pin_y_mm[d, j], md_d)
    band = BAND_WIDE if rho_c < RHO_TIGHT_MM else BAND_NARROW
    if _contact_rotation_bound(c0, p1, p2, tgt, coef[SIDE, d, j], turn) > first * (1.0 + band):
        return np.inf
    return _contact_rotation(c0, p1, p2, tgt, turn.beta_rad, turn.sign)


@njit(nogil=True, cache=True)
def _lowest_gaps(coef, work, md, beta):
    """(value, lever) of the lowest falling gap and of the lowest rising gap at rotation beta [um,
    um/rad], every gap on its osculating circle (see stage_play; work: stage_work as unit_gaps
    left it). Every pin's gap on its circle,
        gap_j = SIDE ((RHO - tgt_j) + (D_j(beta) - RHO)) 1e3,  lever_j = -d gap_j / d beta,
    in one pass per disc that the compiler runs four pins at a time (into work.value_um and
    work.lever_um_per_rad), then the lowest of each side in a second pass. md: the discs'
    moving-distance modifications [um]."""
    discs, zp = work.value_um.shape
    cb, sb = math.cos(beta), math.sin(beta)
    for d in range(discs):
        qx, qy, tgt = work.pin_x_mm[d], work.pin_y_mm[d], work.closing_distance_mm[d]
        val, slope = work.value_um[d], work.lever_um_per_rad[d]
        ox_, oy_, eux, euy = coef[OX, d], coef[OY, d], coef[EUX, d], coef[EUY, d]
        side, rho = coef[SIDE, d], coef[RHO, d]
        mdd = md[d]
        for j in range(zp):
            c0, p1, p2 = _circle_terms(ox_[j], oy_[j], eux[j], euy[j], qx[j], qy[j], mdd)
            dist = math.sqrt(max(c0 - 2.0 * (p1 * cb + p2 * sb), 1e-300))
            val[j] = side[j] * ((rho[j] - tgt[j]) + (dist - rho[j])) * 1e3
            slope[j] = -side[j] * 1e3 * (p1 * sb - p2 * cb) / dist
    fall, rise, lf, lr = np.inf, np.inf, 0.0, 0.0
    for d in range(discs):
        val, slope = work.value_um[d], work.lever_um_per_rad[d]
        for j in range(zp):
            v, lv = val[j], slope[j]
            if lv > 0.0:
                if v < fall:
                    fall, lf = v, lv
            elif v < rise:
                rise, lr = v, lv
    return fall, lf, rise, lr


@njit(nogil=True, cache=True)
def _max_min_gap(coef, work, md, gaps, lo, hi):
    """(max over beta of min_j gap_j(beta) [um], the beta [rad]) on the osculating circles
    (stage_play): negative, the unit's preload.

    The max lies where the lowest falling gap (lever > 0) meets the lowest rising one: Newton on
    their difference from the linear answer (_linear_maxmin), inside the bracket the evaluations
    build (a falling gap lowest at its right end, a rising one at its left). A Newton step that
    leaves the bracket (the lowest gaps switch pins near a vertex, where plain Newton cycles) is
    replaced by the meeting point of the falling gap's tangent at the right end and the rising
    gap's at the left end (exact when the gaps are straight), or by bisection when that too falls
    outside. It stops when the two lowest gaps agree to PRELOAD_STEP_UM, or when those tangents
    promise less than that above the best value found (the max is a single pin's peak)."""
    beta = _linear_maxmin(gaps, lo, hi)
    left, right = -np.inf, np.inf
    fl_v, fl_l, rl_v, rl_l = 0.0, 0.0, 0.0, 0.0  # the right end's falling tangent, the left end's rising one
    best, best_beta = -np.inf, beta
    for _ in range(80):
        fall, lf, rise, lr = _lowest_gaps(coef, work, md, beta)
        m = min(fall, rise)
        if m > best:
            best, best_beta = m, beta
        if abs(fall - rise) < PRELOAD_STEP_UM:
            return m, beta
        if not (math.isfinite(fall) and math.isfinite(rise)):
            break
        if fall > rise:
            left, rl_v, rl_l = beta, rise, lr
        else:
            right, fl_v, fl_l = beta, fall, lf
        if right - left < 1e-15:
            break
        nxt = beta + (fall - rise) / (lf - lr)
        if not left < nxt < right and math.isfinite(left) and math.isfinite(right):
            nxt = (fl_v + fl_l * right - rl_v - rl_l * left) / (fl_l - rl_l)
            if fl_v - fl_l * (nxt - right) - best < PRELOAD_STEP_UM:
                break
            if not left < nxt < right:
                nxt = 0.5 * (left + right)
        beta = nxt
    return best, best_beta


@njit(nogil=True, cache=True, inline="always")
def free_interval_bounds(gaps, azc_um):
    """(lo, hi, flat) of PinGaps, linearised gaps gap_j - lever_j beta [um, um/rad]: the free
    interval lo <= beta <= hi [rad] that every pin with a lever allows, and the smallest gap of a
    pin without one (|lever| <= 1e-9 a z_c, azc_um [um]) [um]."""
    gap, lever = gaps.gap_um, gaps.lever_um_per_rad
    discs, zp = gap.shape
    hi = np.inf
    lo = -np.inf
    flat = np.inf
    tol = 1e-9 * azc_um
    for d in range(discs):
        for j in range(zp):
            g, lv = gap[d, j], lever[d, j]
            if lv > tol:
                hi = min(hi, g / lv)
            elif lv < -tol:
                lo = max(lo, g / lv)
            else:
                flat = min(flat, g)
    return lo, hi, flat


@njit(nogil=True, cache=True)
def unit_gaps(coef, stage, unit, gaps, work):
    """Every pin's gap [um] and lever [um/rad] at beta = 0 on its osculating circle (see stage_play)
    of the unit whose UnitErrors are ``unit`` into ``gaps`` (PinGaps); ``work`` (StageWork)
    receives the pin centres in the disc frame and the distance from the circle's centre at which
    each gap closes. Returns (lo, hi, flat): the linearised free interval of beta [rad] and the
    smallest gap of a pin without a lever [um].

    The pins of a disc are one pass that the compiler runs four at a time (SIMD): each pin's tooth
    pitch error is gathered first (an indexed load stops the compiler from vectorising a loop), and
    the free interval is reduced in a second pass."""
    a, rp, zp = stage.a_mm, stage.rp_mm, stage.zp
    dr, dt, rho, cl = unit.pin_radial_um, unit.pin_tangential_um, unit.pin_radius_um, unit.pin_clearance_um
    for d in range(stage.discs):
        qx_, qy_, tooth_err, tgt = work.pin_x_mm[d], work.pin_y_mm[d], work.pin_tooth_pitch_um[d], \
            work.closing_distance_mm[d]
        gap_d, lever_d = gaps.gap_um[d], gaps.lever_um_per_rad[d]
        tooth, teeth_d = coef[TOOTH, d], unit.tooth_pitch_um[d]
        for j in range(zp):
            tooth_err[j] = teeth_d[int(tooth[j])]
        cpsi, spsi = coef[CPSI, d], coef[SPSI, d]
        # the disc's crank angle and turn are the same at every pin (mesh_table)
        frame = DiscFrame(coef[CCHI, d, 0], coef[SCHI, d, 0], coef[CANG, d, 0], coef[SANG, d, 0],
                          unit.runout_along_um[d], unit.runout_across_um[d], unit.eccentricity_error_um[d])
        ox_, oy_, eux, euy, side, rho_c = coef[OX, d], coef[OY, d], coef[EUX, d], coef[EUY, d], coef[SIDE, d], \
            coef[RHO, d]
        eqd, mdd = unit.equidistance_um[d], unit.moving_distance_um[d]
        for j in range(zp):
            qx, qy = pin_in_disc(cpsi[j], spsi[j], dr[j], dt[j], tooth_err[j], frame, a, rp)
            qx_[j] = qx
            qy_[j] = qy
            ox = ox_[j] + mdd * 1e-3 * eux[j]
            oy = oy_[j] + mdd * 1e-3 * euy[j]
            dist = math.sqrt((qx - ox) * (qx - ox) + (qy - oy) * (qy - oy))
            base = eqd - rho[j] + 0.5 * cl[j]  # pin_base_um, hoisted (the loop runs four pins at a time)
            gap_d[j] = base + side[j] * (dist - rho_c[j]) * 1e3
            lever_d[j] = side[j] * (qy * ox - qx * oy) / dist * 1e3
            tgt[j] = rho_c[j] - side[j] * base * 1e-3  # the distance D at which the gap is 0
    return free_interval_bounds(gaps, stage.pitch_radius_um)


@njit_borrowing(nogil=True, cache=True)
def stage_play(coef, stage, unit, gaps, work, play=True):
    """Play of the cycloid stage of one unit (its UnitErrors ``unit``; StageGeometry ``stage``;
    ``coef``: the mesh_table at its crank angle) as a StagePlay: plays [rad] from the assembled
    position, the pins that stop them; NaN and pins -1 when preloaded, with the preload [um].

    Each pin's gap as the disc turns by beta is its distance from the osculating circle of the
    pin-centre curve at that pin (mesh_table), with every error placed exactly (pin_in_disc):
        gap_j(beta) = eq + SIDE (D_j(beta) - RHO) 1e3 - rho_j + cl_j / 2,
        D_j(beta) = |q_j - R(beta) (O_j + dr_p e_u)|,
    exact to second order in the displacements (the curve's own curvature included), which the
    near-tip pins need: C bends there with radii down to 0.2 mm. ``gaps`` (PinGaps, (discs, z_p))
    receive gap_j(0) [um] and lever_j = -d gap_j / d beta (0) [um/rad] (> 0 stops a
    counter-clockwise rotation), the elastic model's inputs; ``work`` (stage_work) is scratch
    space. The discs are tied by the cranks (one beta). The unit is preloaded when the linearised
    gaps admit no beta that frees every pin, or when, at the middle of the interval they admit, a
    pin's osculating gap still interferes (a pin facing a tooth tip, where the gap bends back
    within the interval); its preload [um] is then -max_beta min_j gap_j(beta), and a unit whose
    max-min gap turns out positive is free after all, centred on that beta.
    Otherwise, from the middle of the free interval, each side's first contact is the nearest
    root of the pins' gaps; the pins within a band of it (BAND_NARROW, BAND_WIDE near the tips)
    are checked on the exact curve (turned_gap, from the centres unit_gaps placed) and the first of
    them solved exactly, then the pins within the band of that refined contact are checked again
    (the osculating estimate can be off by more than the band near a tip). ``play`` False: a free
    unit stops there (plays 0, pins -1): the elastic model reads the gaps, the levers and the
    preload only.
    """
    lo, hi, flat = unit_gaps(coef, stage, unit, gaps, work)
    return play_from_gaps(coef, stage, unit, gaps, work, FreeInterval(lo, hi, flat), play)


@njit(nogil=True, cache=True, inline="always")
def shift_pin_radius(coef, unit, gaps, work, j, radius_um):
    """Pin j's radius error set to ``radius_um`` [um] in a unit whose gaps unit_gaps has found
    (``gaps``, ``work``): a pin's gap is linear in its radius (pin_base_um) and its lever and centre
    do not depend on it, so every disc's gap to pin j and the distance at which it closes move by
    the change, without placing the pins again (selective assembly: the pins swapped after the
    gaps were read). Call free_interval_bounds afterwards for stage_play's bounds."""
    delta = radius_um - unit.pin_radius_um[j]
    unit.pin_radius_um[j] = radius_um
    for d in range(gaps.gap_um.shape[0]):
        gaps.gap_um[d, j] -= delta
        work.closing_distance_mm[d, j] += coef[SIDE, d, j] * delta * 1e-3


@njit_borrowing(nogil=True, cache=True)
def play_from_gaps(coef, stage, unit, gaps, work, free, play):
    """stage_play of a unit whose gaps unit_gaps has found (``gaps``, ``work``; ``free``: the
    FreeInterval it returned): everything stage_play does after unit_gaps."""
    lo, hi, flat = free.lo_rad, free.hi_rad, free.flat_um
    a, rp, zc, zp, discs = stage.a_mm, stage.rp_mm, stage.zc, stage.zp, stage.discs
    md = unit.moving_distance_um
    gap, lever = gaps.gap_um, gaps.lever_um_per_rad
    qx_, qy_, est = work.pin_x_mm, work.pin_y_mm, work.estimate_rad
    preloaded = hi < lo or flat < 0.0
    bc = 0.5 * (lo + hi) if math.isfinite(lo) and math.isfinite(hi) else 0.0
    if not preloaded:
        # the linear screen can miss a pin facing a tooth tip: its gap bends back (RHO ~ 0.1 mm) and
        # may interfere at every rotation; on the osculating circles every pin must be free at bc
        fall, _, rise, _ = _lowest_gaps(coef, work, md, bc)
        preloaded = min(fall, rise) < -PRELOAD_TOL_UM
    recentred = False
    if preloaded:  # the deepest interference at the best rotation (or, if it is positive, a free unit after all)
        m, beta = _max_min_gap(coef, work, md, gaps, lo, hi)
        if m < PRELOAD_TOL_UM:
            return StagePlay(np.nan, np.nan, max(-m, 0.0), -1, -1, -1, -1)
        bc = beta
        recentred = True
    if not play:
        return StagePlay(0.0, 0.0, 0.0, -1, -1, -1, -1)
    if recentred:
        # free after all, but the gaps linearised at beta = 0 are not: extrapolated to bc some are
        # negative, and a negative linear estimate would turn the screen below inside out (the pins
        # beyond 3 x a negative first estimate are all of them: the first contact went unseen, issue
        # 36 item 7). The screen's estimates come from the osculating gaps at bc instead: all >= m > 0.
        _lowest_gaps(coef, work, md, bc)
    cbc, sbc = math.cos(bc), math.sin(bc)
    play_ccw, play_cw, pin_ccw, disc_ccw, pin_cw, disc_cw = 0.0, 0.0, -1, -1, -1, -1
    for side in range(2):  # 0: counter-clockwise (beta > 0), 1: clockwise
        sgn = 1.0 if side == 0 else -1.0
        turn = Turn(bc, cbc, sbc, sgn)
        first_lin = np.inf  # the linear estimate screens out the pins far from contact
        dl, jl = -1, -1
        for d in range(discs):
            for j in range(zp):
                if recentred:  # the gap and lever at bc on the osculating circles (_lowest_gaps)
                    slope = sgn * work.lever_um_per_rad[d, j]
                    est[d, j] = work.value_um[d, j] / slope if slope > 0.0 else np.inf
                else:  # the gap at 0 and its lever, linearly extrapolated to bc
                    slope = sgn * lever[d, j]
                    est[d, j] = (gap[d, j] - lever[d, j] * bc) / slope if slope > 0.0 else np.inf
                if est[d, j] < first_lin:
                    first_lin, dl, jl = est[d, j], d, j
        # contact rotation of the pins near it, on their osculating circles: first the pin the linear
        # estimate puts first, then each pin whose lower bound is within the band of the first so far
        lead = np.inf
        if dl >= 0:
            lead = _screened_contact(coef, work, md[dl], dl, jl, first_lin, lead, turn)
        first = lead
        for d in range(discs):
            for j in range(zp):
                if d == dl and j == jl:
                    est[d, j] = lead
                    continue
                est[d, j] = _screened_contact(coef, work, md[d], d, j, first_lin, first, turn)
                first = min(first, est[d, j])
        # the candidates on the exact curve: one Newton step each from their estimate; a second pass
        # takes the pins within the band of the refined first contact that the estimate's band left out
        # (a tip pin's osculating circle can put its estimate early)
        best = np.inf
        bd, bj = -1, -1
        bpx, bpy, bbase, bt = 0.0, 0.0, 0.0, 0.0  # the best pin's frame position, base and foot
        for rnd in range(2):
            ref = first if rnd == 0 else best
            for d in range(discs):
                rg = rp + md[d] * 1e-3
                for j in range(zp):
                    x = est[d, j]
                    band = BAND_WIDE if coef[RHO, d, j] < RHO_TIGHT_MM else BAND_NARROW
                    if x > ref * (1.0 + band) or (rnd == 1 and x <= first * (1.0 + band)):
                        continue
                    px, py = qx_[d, j], qy_[d, j]  # its centre as unit_gaps placed it (pin_frame's, from the table)
                    base = pin_base_um(unit, d, j)
                    f1, s1, t1 = turned_gap(px, py, bc + sgn * x, base, a, rg, zc, coef[T0, d, j])
                    if s1 != 0.0:
                        x -= f1 / (sgn * s1)
                    if x < best:
                        best, bd, bj = x, d, j
                        bpx, bpy, bbase, bt = px, py, base, t1
            if not best > first:
                break
        rg = rp + md[bd] * 1e-3
        for _ in range(4):  # the first of them to full precision (Newton)
            f1, s1, bt = turned_gap(bpx, bpy, bc + sgn * best, bbase, a, rg, zc, bt)
            if abs(f1) < 1e-9 or s1 == 0.0:
                break
            best -= f1 / (sgn * s1)
        if side == 0:  # rotations from beta = 0
            play_ccw, pin_ccw, disc_ccw = best + sgn * bc, bj, bd
        else:
            play_cw, pin_cw, disc_cw = best + sgn * bc, bj, bd
    return StagePlay(play_ccw, play_cw, 0.0, pin_ccw, disc_ccw, pin_cw, disc_cw)


@njit(nogil=True, cache=True)
def exact_disc_gaps(d, beta, chi, stage, unit, out):
    """exact_gap_um of every pin of disc d [um] into out (z_p)."""
    zp = stage.zp
    chi_d = chi + 2.0 * math.pi * d / stage.discs
    for j in range(zp):
        t0 = chi_d - 2.0 * math.pi * j / zp + 2.0 * math.pi * j
        out[j] = exact_gap_um(j, d, beta, chi, stage, unit, t0)


def kernel_play(g: ContactGeometry, r: Realization) -> MeshPlay:
    """The Monte-Carlo kernel's play of one unit at its exact crank angle (no crank-angle steps)."""
    coef = mesh_table(g, np.array([r.chi_rad]))[0]
    p = stage_play(coef, g.stage_geometry, unit_errors(r), pin_gaps(g.discs, g.zp), stage_work(g.discs, g.zp),
                   True)  # given, not the default: the kernels' compiled stage_play (contact_source.contact_block)
    return MeshPlay((), float(p.preload_um), g.pitch_radius_um, float(p.play_ccw_rad), float(p.play_cw_rad))


# --- exact play ------------------------------------------------------------------------------

def _disc_frame_pins(g: ContactGeometry, r: Realization, d: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Actual pin centres in disc d's frame [mm] (run-out and tooth pitch errors applied), the
    nominal curve parameter of each pin, and the lever-arm ratio sin(phi)/sqrt(S)."""
    chi = g.disc_crank_angle(r.chi_rad, d)
    psi = g.pin_angles
    radial = g.rp_mm + r.pin_radial_um * 1e-3
    centres = np.stack([radial * np.cos(psi), radial * np.sin(psi)], axis=1) \
        + (r.pin_tangential_um * 1e-3)[:, None] * np.stack([-np.sin(psi), np.cos(psi)], axis=1)
    e = np.array([math.cos(chi), math.sin(chi)])
    e_perp = np.array([-e[1], e[0]])
    disc_centre = (g.a_mm + r.eccentricity_error_um[d] * 1e-3) * e
    theta = -chi / g.zc
    runout = (r.runout_um[d, 0] * e + r.runout_um[d, 1] * e_perp) * 1e-3
    q = rotate(centres - disc_centre - runout, -theta)
    k = np.floor(np.arange(g.zp) * g.zc / g.zp + chi / (2 * math.pi) + 0.5).astype(int) % g.zc
    q = rotate(q, -(r.tooth_pitch_um[d, k] * 1e-3) / g.rp_mm)
    t0 = chi - psi + 2 * math.pi * np.arange(g.zp)
    phi = psi - chi
    lrel = np.sin(phi) / np.sqrt(1 + g.K1 ** 2 - 2 * g.K1 * np.cos(phi))
    return q, t0, lrel


def exact_gaps_um(g: ContactGeometry, r: Realization, d: int, beta: float = 0.0) -> np.ndarray:
    """Gap of every pin to disc d [um] with the disc turned by beta [rad] about its centre."""
    q, t0, _ = _disc_frame_pins(g, r, d)
    curve = PinCentreCurve(g.a_mm, g.rp_mm + r.moving_distance_um[d] * 1e-3, g.zc)
    s, _ = curve.signed_distance(rotate(q, -beta), t0)
    return r.equidistance_um[d] + s * 1e3 - r.pin_radius_um + 0.5 * r.pin_clearance_um


def linear_gaps_um(g: ContactGeometry, r: Realization, d: int) -> tuple[np.ndarray, np.ndarray]:
    """Linearised gaps of every pin of disc d: gap_j(beta) = gap0_j - lever_j beta [um], lever_j =
    L_j [um/rad] (signed: > 0 stops a counter-clockwise rotation). Same formula as the kernel's
    ``disc_play``, every pin included."""
    chi = g.disc_crank_angle(r.chi_rad, d)
    phi = g.pin_angles - chi
    k1 = g.K1
    rs = 1.0 / np.sqrt(1.0 + k1 * k1 - 2.0 * k1 * np.cos(phi))
    rn, tn, en, lrel = (1.0 - k1 * np.cos(phi)) * rs, k1 * np.sin(phi) * rs, (np.cos(phi) - k1) * rs, np.sin(phi) * rs
    teeth = np.floor(np.arange(g.zp) * g.zc / g.zp + chi / (2 * math.pi) + 0.5).astype(int) % g.zc
    ux, uy = r.runout_um[d]
    gap0 = (r.equidistance_um[d] + (r.pin_radial_um - r.moving_distance_um[d]) * rn + r.pin_tangential_um * tn
            - r.pin_radius_um + 0.5 * r.pin_clearance_um - (r.eccentricity_error_um[d] + ux) * en - uy * lrel
            - r.tooth_pitch_um[d, teeth] * lrel * g.a_mm * g.zc / g.rp_mm)
    return gap0, lrel * g.pitch_radius_um


def maxmin_rotation(gap0: np.ndarray, lever: np.ndarray) -> tuple[float, float]:
    """(beta*, m*) maximising m(beta) = min_j (gap0_j - lever_j beta): the most central position
    of a disc (or of discs turning together) and its smallest gap there [rad, um]. m is concave
    and piecewise linear; its maximum lies where a rising line (lever < 0) meets a falling one."""
    up, down = lever < 0, lever > 0
    flat = gap0[lever == 0].min() if np.any(lever == 0) else math.inf
    if not up.any() or not down.any():
        return 0.0, float(min(flat, gap0.min()))
    a, b = gap0[down][:, None], lever[down][:, None]  # falling lines
    c, e = gap0[up][None, :], lever[up][None, :]  # rising lines
    beta = ((a - c) / (b - e)).ravel()
    values = np.min(gap0[None, :] - lever[None, :] * beta[:, None], axis=1)
    i = int(np.argmax(values))
    return float(beta[i]), float(min(values[i], flat))


def _exact_root(f, start: float, step: float) -> float:
    """The rotation beyond ``start`` (direction and first step ``step``) where the smallest gap f
    reaches 0; f(start) >= 0 and f decreases that way."""
    lo, hi = start, start + step
    for _ in range(60):
        if f(hi) < 0:
            break
        lo, hi, step = hi, hi + step, 2 * step
    else:  # pragma: no cover - a cycloid stage always has pins on both sides
        raise ArithmeticError("exact play: no contact in this direction")
    from scipy import optimize  # here: scipy.optimize costs a third of a second to import, and a run never needs it

    return optimize.brentq(f, *sorted((lo, hi)), xtol=1e-14, rtol=1e-12)


def exact_play(g: ContactGeometry, r: Realization) -> MeshPlay:
    """Play of every disc and of the stage from exact signed distances of every pin.

    The disc turns by beta about its centre; m_d(beta) = min_j gap_j(beta) [um] is the smallest
    gap of disc d. Its free rotations are where m_d >= 0: from the most central position (the
    maximum of m_d, found from the linearisation and refined) the roots of m_d on either side.
    The discs turn together: the stage is preloaded when max_beta min_d m_d(beta) < 0, and
    that deficit is its preload [um].
    """
    stage, unit = g.stage_geometry, unit_errors(r)
    buf = np.empty(g.zp)

    def gaps(d: int, beta: float) -> np.ndarray:  # exact_gaps_um, compiled
        exact_disc_gaps(d, beta, r.chi_rad, stage, unit, buf)
        return buf.copy()

    lin = [linear_gaps_um(g, r, d) for d in range(g.discs)]
    scale = max(float(np.max(np.abs(lev))) for _, lev in lin)  # um per rad: sets the rotation step

    def central(fn, guess: float) -> tuple[float, float]:
        """(beta, value) of the maximum of fn near guess (fn is concave near its maximum)."""
        from scipy import optimize  # here, as in _exact_root

        width = 2.0 * max(abs(guess), 1.0 / scale)
        res = optimize.minimize_scalar(lambda b: -fn(b), bounds=(guess - width, guess + width), method="bounded",
                                       options={"xatol": 1e-14 + 1e-9 * abs(guess)})
        return float(res.x), -float(res.fun)

    g_all, l_all = np.concatenate([a for a, _ in lin]), np.concatenate([b for _, b in lin])
    beta0, _ = maxmin_rotation(g_all, l_all)
    beta_stage, m_stage = central(lambda b: min(float(gaps(d, b).min()) for d in range(g.discs)), beta0)
    discs = []
    for d in range(g.discs):
        bd, md = central(lambda b: float(gaps(d, b).min()), maxmin_rotation(*lin[d])[0])
        if md < -PRELOAD_TOL_UM:
            discs.append(DiscPlay(math.nan, math.nan, -1, -1))
            continue
        step = max(md, 1e-3) / scale
        if md <= 0:  # touching everywhere at once (no clearance at all): no free rotation
            discs.append(DiscPlay(bd, -bd, int(np.argmin(gaps(d, bd))), int(np.argmin(gaps(d, bd)))))
            continue
        hi = _exact_root(lambda b: float(gaps(d, b).min()), bd, step)
        lo = _exact_root(lambda b: float(gaps(d, b).min()), bd, -step)
        discs.append(DiscPlay(hi, -lo, int(np.argmin(gaps(d, hi))), int(np.argmin(gaps(d, lo)))))
    preload = -m_stage if m_stage < -PRELOAD_TOL_UM else 0.0
    if preload > 0:
        return MeshPlay(tuple(discs), preload, g.pitch_radius_um, math.nan, math.nan)
    return MeshPlay(tuple(discs), 0.0, g.pitch_radius_um, min(x.play_ccw_rad for x in discs),
                    min(x.play_cw_rad for x in discs))
