"""Exact geometry of the modified cycloid disc and its pins (docs/contact.md).

Frames: the housing frame has the pin-wheel axis at the origin; pin j sits at angle
psi_j = 2 pi j / z_p on the pin circle r_p. Disc d is on an eccentric at crank angle chi:
centre a (cos chi, sin chi), orientation -chi / z_c (fixed pins, z_p = z_c + 1).

The disc profile is the inner offset, by the generating pin radius r_rp + dr_rp, of the curve
C traced by a generating pin centre (pin circle r_p + dr_p) in the disc frame:

    C(t) = R(t / z_c) (r_g x - a (cos t, sin t)),   t in [0, 2 pi z_c),   r_g = r_p + dr_p

(an epitrochoid; C(t + 2 pi) = R(2 pi / z_c) C(t)). A pin whose centre lies at signed
distance s from C (positive away from the disc) has the gap  dr_rp + s - (pin radius error)
to the profile, exactly, as long as the offset is regular (no undercut: r_rp + dr_rp smaller
than the smallest radius of curvature of C on its concave side).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np


class StageGeometry(NamedTuple):
    """The cycloid stage as the compiled kernels read it (``ContactGeometry.stage_geometry``)."""

    a_mm: float  # eccentricity a
    rp_mm: float  # pin circle radius r_p
    zc: int  # teeth per disc
    zp: int  # pins
    discs: int
    pitch_radius_um: float  # a z_c [um]: the lever at which a disc's rotation is referred to (Eq. (1))


@dataclass(frozen=True)
class ContactGeometry:
    """Nominal cycloid stage [mm]: z_c teeth per disc, z_p pins, eccentricity a, pin circle r_p,
    pin radius r_rp, number of discs."""

    zc: int
    zp: int
    a_mm: float
    rp_mm: float
    rrp_mm: float
    discs: int

    @property
    def K1(self) -> float:
        return self.a_mm * self.zp / self.rp_mm

    @property
    def pitch_radius_um(self) -> float:
        """a z_c [um]: the lever arm at which the disc's rotation is referred to (Eq. (1))."""
        return self.a_mm * self.zc * 1e3

    @property
    def pin_angles(self) -> np.ndarray:
        """psi_j = 2 pi j / z_p [rad]."""
        return 2 * math.pi * np.arange(self.zp) / self.zp

    @property
    def stage_geometry(self) -> StageGeometry:
        return StageGeometry(float(self.a_mm), float(self.rp_mm), int(self.zc), int(self.zp), int(self.discs),
                             float(self.pitch_radius_um))

    def disc_crank_angle(self, chi: float, d: int) -> float:
        """Discs sit on eccentrics 360/discs degrees apart (180 deg for two) [rad]."""
        return chi + 2 * math.pi * d / self.discs


def rotate(v: np.ndarray, angle) -> np.ndarray:
    """Rotate 2-D vectors (..., 2) by ``angle`` [rad] (counter-clockwise)."""
    c, s = np.cos(angle), np.sin(angle)
    x, y = v[..., 0], v[..., 1]
    return np.stack([c * x - s * y, s * x + c * y], axis=-1)


@dataclass(frozen=True)
class PinCentreCurve:
    """C(t) of a disc generated with eccentricity a [mm], pin circle r_g [mm], z_c teeth."""

    a: float
    r_g: float
    zc: int

    def point(self, t):
        """C(t) [mm], shape (..., 2)."""
        t = np.asarray(t, float)
        base = np.stack([self.r_g - self.a * np.cos(t), -self.a * np.sin(t)], axis=-1)
        return rotate(base, t / self.zc)

    def d1(self, t):
        """dC/dt [mm/rad]."""
        t = np.asarray(t, float)
        k = 1.0 / self.zc
        base = np.stack([self.r_g - self.a * np.cos(t), -self.a * np.sin(t)], axis=-1)
        dbase = np.stack([self.a * np.sin(t), -self.a * np.cos(t)], axis=-1)
        return rotate(dbase, t * k) + k * rotate(np.stack([-base[..., 1], base[..., 0]], axis=-1), t * k)

    def d2(self, t):
        """d2C/dt2 [mm/rad^2] (central difference of the analytic first derivative)."""
        h = 1e-5
        return (self.d1(np.asarray(t, float) + h) - self.d1(np.asarray(t, float) - h)) / (2 * h)

    def outward_normal(self, t):
        """Unit normal of C pointing away from the disc centre."""
        d = self.d1(t)
        n = np.stack([d[..., 1], -d[..., 0]], axis=-1)
        n /= np.linalg.norm(n, axis=-1, keepdims=True)
        flip = np.sum(n * self.point(t), axis=-1) < 0
        return np.where(flip[..., None], -n, n)

    def signed_distance(self, q, t0, iterations: int = 8):
        """Signed distance [mm] of points q (..., 2) from C, positive away from the disc, and
        the parameter of the closest point; Newton on (C(t) - q) . C'(t) = 0 from t0."""
        t = np.asarray(t0, float).copy()
        for _ in range(iterations):
            c, d1, d2 = self.point(t), self.d1(t), self.d2(t)
            r = c - q
            f = np.sum(r * d1, axis=-1)
            fp = np.sum(d1 * d1, axis=-1) + np.sum(r * d2, axis=-1)
            t = t - f / fp
        r = q - self.point(t)
        return np.sum(r * self.outward_normal(t), axis=-1), t

    def min_convex_radius_of_curvature(self, samples: int = 20000) -> float:
        """Smallest radius of curvature [mm] where C bends around the disc centre (its centre of
        curvature on the disc side). Offsetting C towards the disc by the pin radius is regular
        only below this value; beyond it the profile is undercut (a cusp). inf if C never
        bends that way."""
        t = np.linspace(0, 2 * math.pi, samples, endpoint=False)  # one lobe is enough (symmetry)
        d1, d2 = self.d1(t), self.d2(t)
        cross = d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]
        speed = np.linalg.norm(d1, axis=1)
        convex = cross > 0  # C runs counter-clockwise: turning left = around the disc centre
        if not convex.any():
            return math.inf
        return float(np.min(speed[convex] ** 3 / cross[convex]))


def profile_points(a: float, r_p: float, r_rp: float, zc: int, dr_p_um: float = 0.0, dr_rp_um: float = 0.0,
                   samples_per_tooth: int = 200) -> np.ndarray:
    """Points [mm] of the modified disc profile in the disc frame (for plots)."""
    curve = PinCentreCurve(a, r_p + dr_p_um * 1e-3, zc)
    t = np.linspace(0, 2 * math.pi * zc, samples_per_tooth * zc, endpoint=False)
    return curve.point(t) - (r_rp + dr_rp_um * 1e-3) * curve.outward_normal(t)
