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

from rvbacklash.design.schema import Design
from rvbacklash.model.cycloid_geometry import PinCentreCurve, rotate
from rvbacklash.units import ARCMIN_PER_RAD

MIN_LEVER = 0.1  # pins whose lever arm is below 10 % of a z_c cannot stop a rotation (tooth tip/root)


@dataclass(frozen=True)
class ContactGeometry:
    """Nominal cycloid stage [mm] of a design."""

    zc: int
    zp: int
    a_mm: float
    rp_mm: float
    rrp_mm: float
    discs: int

    @classmethod
    def from_design(cls, design: Design) -> "ContactGeometry":
        s = design.second_stage
        return cls(s.cycloid_teeth, s.pins, s.eccentricity_mm, s.pin_circle_radius_mm, s.pin_radius_mm, s.discs)

    @property
    def K1(self) -> float:
        return self.a_mm * self.zp / self.rp_mm

    @property
    def pin_angles(self) -> np.ndarray:
        return 2 * math.pi * np.arange(self.zp) / self.zp

    def disc_crank_angle(self, chi: float, d: int) -> float:
        """Discs sit on eccentrics 360/discs degrees apart (180 deg for two)."""
        return chi + 2 * math.pi * d / self.discs


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
    """Free rotation of one disc [rad] in each direction and the pins that stop it."""

    play_ccw_rad: float
    play_cw_rad: float
    contact_pin_ccw: int
    contact_pin_cw: int

    @property
    def total_rad(self) -> float:
        return self.play_ccw_rad + self.play_cw_rad


@dataclass(frozen=True)
class MeshPlay:
    discs: tuple[DiscPlay, ...]

    @property
    def play_ccw_rad(self) -> float:
        return min(d.play_ccw_rad for d in self.discs)

    @property
    def play_cw_rad(self) -> float:
        return min(d.play_cw_rad for d in self.discs)

    @property
    def total_rad(self) -> float:
        """Output play of the stage: the cranks tie the discs, the first contact of either stops it.
        Negative: no rotation frees every pin, the stage is preloaded (interference); only the
        sign is meaningful then, the lost motion of the stage is 0."""
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


def exact_play(g: ContactGeometry, r: Realization, min_lever: float = MIN_LEVER) -> MeshPlay:
    """Play of every disc from exact signed distances (brentq on the rotation)."""
    guesses = linear_play(g, r, min_lever).discs  # the linearisation brackets each root
    discs = []
    for d in range(g.discs):
        _, _, lrel = _disc_frame_pins(g, r, d)
        res = []
        for sign in (+1, -1):
            pins = np.nonzero(sign * lrel >= min_lever)[0]

            def closest(beta: float) -> float:
                return float(np.min(exact_gaps_um(g, r, d, sign * beta)[pins]))

            b0 = guesses[d].play_ccw_rad if sign > 0 else guesses[d].play_cw_rad
            span = max(0.1 * abs(b0), 1e-7)
            lo, hi = b0 - span, b0 + span
            for _ in range(40):  # the linear guess is close: widen until the root is bracketed
                if closest(lo) > 0 and closest(hi) < 0:
                    break
                lo, hi, span = lo - span, hi + span, 2 * span
            else:
                raise ArithmeticError("exact play: no root near the linear estimate")
            beta = optimize.brentq(closest, lo, hi, xtol=1e-13, rtol=1e-12)
            gaps = exact_gaps_um(g, r, d, sign * beta)
            res.append((beta, int(pins[np.argmin(gaps[pins])])))
        discs.append(DiscPlay(res[0][0], res[1][0], res[0][1], res[1][1]))
    return MeshPlay(tuple(discs))
