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
from dataclasses import dataclass, replace

import numba as nb
import numpy as np
from scipy import optimize

from rvbacklash.geometry.cycloid import ContactGeometry, PinCentreCurve, rotate
from rvbacklash.units import ARCMIN_PER_RAD

MIN_LEVER = 0.1  # pins whose lever arm is below 10 % of a z_c cannot stop a rotation (tooth tip/root)
PRELOAD_TOL_UM = 1e-6  # interference below a picometre is contact, not preload (round-off of the geometry)


@dataclass
class Realization:
    """One set of errors [um] (angles [rad]); arrays per pin (z_p) and per disc."""

    chi_rad: float
    pin_radial_um: np.ndarray
    pin_tangential_um: np.ndarray
    pin_radius_um: np.ndarray
    pin_clearance_um: np.ndarray
    tooth_pitch_um: np.ndarray  # (discs, z_c): cumulative pitch error of each tooth space, arc at r_p
    runout_um: np.ndarray  # (discs, 2): profile-centre offset along / across the eccentric
    eccentricity_error_um: np.ndarray  # (discs,)
    equidistance_um: np.ndarray  # (discs,) total dr_rp of each disc
    moving_distance_um: np.ndarray  # (discs,) total dr_p of each disc

    @classmethod
    def nominal(cls, g: ContactGeometry, equidistance_um: float = 0.0, moving_distance_um: float = 0.0,
                clearance_um: float = 0.0, chi_rad: float = 0.0) -> "Realization":
        z = np.zeros(g.zp)
        return cls(chi_rad, z.copy(), z.copy(), z.copy(), np.full(g.zp, clearance_um),
                   np.zeros((g.discs, g.zc)), np.zeros((g.discs, 2)), np.zeros(g.discs),
                   np.full(g.discs, float(equidistance_um)), np.full(g.discs, float(moving_distance_um)))

    def with_(self, **changes) -> "Realization":
        return replace(self, **changes)


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
    uniform clearance (normal to the profile, like an equidistance modification) that would."""

    discs: tuple[DiscPlay, ...]
    preload_um: float = 0.0
    pitch_radius_um: float = 1.0  # a z_c, to express a preload as a (negative) play

    @property
    def preloaded(self) -> bool:
        return self.preload_um > 0.0

    @property
    def play_ccw_rad(self) -> float:
        return min(d.play_ccw_rad for d in self.discs)

    @property
    def play_cw_rad(self) -> float:
        return min(d.play_cw_rad for d in self.discs)

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


# --- linearised play (also the Monte-Carlo kernel) ---------------------------------------------

N_COEF = 6  # per pin: radial, tangential, eccentric-direction and lever coefficients, 1/L, tooth space


@nb.njit(nogil=True, cache=True)
def mesh_coefficients(chi_d, k1, azc_um, zc, cos_psi, sin_psi, min_lever, coef, pins):
    """Linearisation coefficients of the pins that can stop disc rotation at crank angle chi_d.

    For the pin at phase phi = psi_j - chi_d, S = 1 + K1^2 - 2 K1 cos phi (docs/contact.md):
    rn = (1 - K1 cos phi)/sqrt(S), tn = K1 sin phi/sqrt(S), en = (cos phi - K1)/sqrt(S),
    lrel = sin phi/sqrt(S) = L_j / (a z_c); pins with |lrel| < min_lever are left out.
    Fills coef[m] = [rn, tn, en, lrel, 1/(lrel a z_c), tooth space] and pins[m] = j; returns m.
    """
    zp = cos_psi.size
    cx = math.cos(chi_d)
    sx = math.sin(chi_d)
    m = 0
    for j in range(zp):
        cphi = cos_psi[j] * cx + sin_psi[j] * sx
        sphi = sin_psi[j] * cx - cos_psi[j] * sx
        rs = 1.0 / math.sqrt(1.0 + k1 * k1 - 2.0 * k1 * cphi)
        lrel = sphi * rs
        if abs(lrel) < min_lever:
            continue
        coef[m, 0] = (1.0 - k1 * cphi) * rs
        coef[m, 1] = k1 * sphi * rs
        coef[m, 2] = (cphi - k1) * rs
        coef[m, 3] = lrel
        coef[m, 4] = 1.0 / (lrel * azc_um)
        coef[m, 5] = int(math.floor(j * zc / zp + chi_d / (2.0 * math.pi) + 0.5)) % zc
        pins[m] = j
        m += 1
    return m


@nb.njit(nogil=True, cache=True)
def disc_play(coef, pins, count, azc_over_rp, eq, md, dr, dt, rho, cl, ux, uy, da, teeth, out):
    """Linearised play of one disc [rad]; out = [ccw, cw, pin_ccw, pin_cw].

    gap_j [um] = eq + (dr_j - md) rn + dt_j tn - rho_j + cl_j / 2 - da en - (ux en + uy lrel)
                 - e_k lrel a z_c / r_p;   play = min over each side of gap_j / L_j.
    """
    best_p = np.inf
    best_m = np.inf
    pin_p = -1
    pin_m = -1
    for m in range(count):
        j = pins[m]
        rn = coef[m, 0]
        en = coef[m, 2]
        lrel = coef[m, 3]
        gap = (eq + (dr[j] - md) * rn + dt[j] * coef[m, 1] - rho[j] + 0.5 * cl[j] - da * en - ux * en - uy * lrel
               - teeth[int(coef[m, 5])] * lrel * azc_over_rp)
        r = gap * coef[m, 4]
        if lrel > 0:
            if r < best_p:
                best_p = r
                pin_p = j
        elif -r < best_m:
            best_m = -r
            pin_m = j
    out[0] = best_p
    out[1] = best_m
    out[2] = pin_p
    out[3] = pin_m


def linear_play(g: ContactGeometry, r: Realization, min_lever: float = MIN_LEVER) -> MeshPlay:
    """Play of every disc from the small-displacement linearisation (the Monte-Carlo kernel's formula)."""
    psi = g.pin_angles
    cos_psi, sin_psi = np.cos(psi), np.sin(psi)
    discs = []
    out = np.empty(4)
    coef, pins = np.empty((g.zp, N_COEF)), np.empty(g.zp, dtype=np.int64)
    azc_um = g.a_mm * g.zc * 1e3
    for d in range(g.discs):
        n = mesh_coefficients(g.disc_crank_angle(r.chi_rad, d), g.K1, azc_um, g.zc, cos_psi, sin_psi, min_lever,
                              coef, pins)
        disc_play(coef, pins, n, azc_um / (g.rp_mm * 1e3), r.equidistance_um[d], r.moving_distance_um[d],
                  r.pin_radial_um, r.pin_tangential_um, r.pin_radius_um, r.pin_clearance_um,
                  r.runout_um[d, 0], r.runout_um[d, 1], r.eccentricity_error_um[d], r.tooth_pitch_um[d], out)
        discs.append(DiscPlay(float(out[0]), float(out[1]), int(out[2]), int(out[3])))
    return MeshPlay(tuple(discs))


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
    return optimize.brentq(f, *sorted((lo, hi)), xtol=1e-14, rtol=1e-12)


def exact_play(g: ContactGeometry, r: Realization) -> MeshPlay:
    """Play of every disc and of the stage from exact signed distances of every pin.

    The disc turns by beta about its centre; m_d(beta) = min_j gap_j(beta) [um] is the smallest
    gap of disc d. Its free rotations are where m_d >= 0: from the most central position (the
    maximum of m_d, found from the linearisation and refined) the roots of m_d on either side.
    The discs turn together: the stage is preloaded when max_beta min_d m_d(beta) < 0, and
    that deficit is its preload [um].
    """
    curves = [PinCentreCurve(g.a_mm, g.rp_mm + r.moving_distance_um[d] * 1e-3, g.zc) for d in range(g.discs)]
    frames = [_disc_frame_pins(g, r, d) for d in range(g.discs)]

    def gaps(d: int, beta: float) -> np.ndarray:
        q, t0, _ = frames[d]
        s, _ = curves[d].signed_distance(rotate(q, -beta), t0)
        return r.equidistance_um[d] + s * 1e3 - r.pin_radius_um + 0.5 * r.pin_clearance_um

    lin = [linear_gaps_um(g, r, d) for d in range(g.discs)]
    scale = max(float(np.max(np.abs(lev))) for _, lev in lin)  # um per rad: sets the rotation step

    def central(fn, guess: float) -> tuple[float, float]:
        """(beta, value) of the maximum of fn near guess (fn is concave near its maximum)."""
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
    return MeshPlay(tuple(discs), preload, g.pitch_radius_um)
