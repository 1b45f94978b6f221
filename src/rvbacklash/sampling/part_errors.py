"""Part errors as real parts have them: a long-wave part plus a per-element part (docs/contact.md).

A part made on a rotary table or by hobbing carries, around its circle of N elements (teeth of
a disc, pin holes of the housing), a cumulative pitch deviation dominated by its first harmonics
(eccentricity of the set-up, then ovality or the table's indexing error) and a small
per-element (single pitch) part. Element k at theta_k = 2 pi k / N:

    tangential t_k = -u_x sin theta_k + u_y cos theta_k + c_x cos 2theta_k + c_y sin 2theta_k + s_k
    radial     r_k =  u_x cos theta_k + u_y sin theta_k + q_k                (pin holes only)

u (the first harmonic: for the pin holes the offset of the hole circle, which moves every hole
radially and tangentially at once) and c (the second harmonic) are isotropic normal vectors with
standard deviations sigma_1 and sigma_2 = SECOND_TO_FIRST sigma_1 per component; s_k, q_k are
independent normals (sigma_e). The sigmas are set so that a sampled part conforms to its
tolerances (problem.contact_errors: F_p = range of t, f_pt = largest |t_k - t_(k-1)|, F_r = range
of r) at the rate TARGET_CONFORMITY: sigma_e from f_pt alone (CALIBRATION_SINGLE of the parts
break f_pt through the per-element part), then sigma_1 by bisection on a fixed-seed sample of
CALIBRATION_PARTS parts (a calibration, the same for every run). ASSUMPTIONS: the ratio of the
harmonics, isotropy, the radial per-element scatter equal to the tangential one.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from dataclasses import dataclass
from statistics import NormalDist
from typing import NamedTuple

from rvbacklash._numba import njit, source_hash
import numpy as np

from rvbacklash.mechanics.fe_cache import cached
from rvbacklash.problem.contact_errors import IndexedPart

SECOND_TO_FIRST = 0.5  # sigma of the second harmonic over the first's (ASSUMPTION)
TARGET_CONFORMITY = 0.97  # share of sampled parts within every tolerance of their grade
CALIBRATION_SINGLE = 0.01  # share of parts whose per-element part alone breaks f_pt
CALIBRATION_PARTS = 4000
CALIBRATION_SEED = 20261122


@dataclass(frozen=True)
class HarmonicPart:
    """Standard deviations [um] of the long-wave model of one indexed part, and the conformity
    rate its calibration reached."""

    first_um: float  # each component of the first-harmonic vector u
    second_um: float  # each component of the second-harmonic vector c
    element_um: float  # s_k, tangential, per element
    radial_element_um: float  # q_k, radial, per element (0: the part has no radial tolerance)
    conformity: float


class Harmonics(NamedTuple):
    """cos theta_k, sin theta_k, cos 2 theta_k, sin 2 theta_k of a part's N elements (element_harmonics)."""

    cos1: np.ndarray
    sin1: np.ndarray
    cos2: np.ndarray
    sin2: np.ndarray


class Wave(NamedTuple):
    """One part's long-wave deviation [um]: its first-harmonic vector u and its second c."""

    first_x_um: float
    first_y_um: float
    second_x_um: float
    second_y_um: float


@njit(nogil=True, cache=True)
def element_harmonics(n):
    """The Harmonics of a part of n elements, theta_k = 2 pi k / n."""
    out = Harmonics(np.empty(n), np.empty(n), np.empty(n), np.empty(n))
    for k in range(n):
        th = 2.0 * math.pi * k / n
        out.cos1[k], out.sin1[k], out.cos2[k], out.sin2[k] = math.cos(th), math.sin(th), math.cos(2 * th), \
            math.sin(2 * th)
    return out


@njit(nogil=True, cache=True)
def harmonic_deviations(wave, s, q, trig, t_out, r_out):
    """t_k and r_k of one part (module docstring) [um] from its long-wave ``wave``, its per-element
    parts s_k, q_k and its ``element_harmonics``."""
    ux, uy, cx, cy = wave.first_x_um, wave.first_y_um, wave.second_x_um, wave.second_y_um
    for k in range(s.size):
        t_out[k] = -ux * trig.sin1[k] + uy * trig.cos1[k] + cx * trig.cos2[k] + cy * trig.sin2[k] + s[k]
        r_out[k] = ux * trig.cos1[k] + uy * trig.sin1[k] + q[k]


def conforms(t: np.ndarray, r: np.ndarray | None, part: IndexedPart) -> np.ndarray:
    """For parts (rows) of deviations t (and r) [um]: within F_p, f_pt (and F_r)?"""
    ok = (np.ptp(t, axis=-1) <= part.cumulative_pitch_um) & \
        (np.max(np.abs(t - np.roll(t, 1, axis=-1)), axis=-1) <= part.single_pitch_um)
    if r is not None and part.runout_um is not None:
        ok &= np.ptp(r, axis=-1) <= part.runout_um
    return ok


def sample_parts(part: IndexedPart, h: HarmonicPart, normals: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Deviations of parts from standard normals (rows: 4 + 2N per part) [um]."""
    n = part.elements
    theta = 2 * math.pi * np.arange(n) / n  # the same deviations as harmonic_deviations, vectorised
    u = normals[:, 0:2] * h.first_um
    c = normals[:, 2:4] * h.second_um
    s = normals[:, 4:4 + n] * h.element_um
    q = normals[:, 4 + n:4 + 2 * n] * h.radial_element_um
    t = (-u[:, :1] * np.sin(theta) + u[:, 1:2] * np.cos(theta) + c[:, :1] * np.cos(2 * theta)
         + c[:, 1:2] * np.sin(2 * theta) + s)
    r = u[:, :1] * np.cos(theta) + u[:, 1:2] * np.sin(theta) + q
    return t, r


@functools.lru_cache(maxsize=64)
def calibrate(part: IndexedPart) -> HarmonicPart:
    """The sigmas of ``part``'s long-wave model (module docstring), computed once per machine: the
    calibration (~70 samplings of CALIBRATION_PARTS parts, ~0.2 s a part) is kept in the disk
    cache of ``mechanics.fe_cache``, keyed by the tolerances it reads, numpy's version (its random
    stream) and the package's source (any change of the code computes it again).
    ``_calibrate`` computes it."""
    inputs = {"elements": part.elements, "cumulative_pitch_um": part.cumulative_pitch_um,
              "single_pitch_um": part.single_pitch_um, "runout_um": part.runout_um,
              "constants": [SECOND_TO_FIRST, TARGET_CONFORMITY, CALIBRATION_SINGLE, CALIBRATION_PARTS, CALIBRATION_SEED],
              "numpy": np.__version__, "source": source_hash()}
    return HarmonicPart(**cached("part-calibration", 1, inputs, lambda: dataclasses.asdict(_calibrate(part))))


def _calibrate(part: IndexedPart) -> HarmonicPart:
    n = part.elements
    z = NormalDist().inv_cdf(1.0 - CALIBRATION_SINGLE / (2.0 * n))
    element = part.single_pitch_um / (math.sqrt(2.0) * z)
    radial = element if part.runout_um is not None else 0.0
    normals = np.random.Generator(np.random.PCG64(CALIBRATION_SEED)).standard_normal((CALIBRATION_PARTS, 4 + 2 * n))

    def rate(first: float, el: float) -> float:
        h = HarmonicPart(first, SECOND_TO_FIRST * first, el, radial * el / element if element else 0.0, 0.0)
        t, r = sample_parts(part, h, normals)
        return float(np.mean(conforms(t, r if part.runout_um is not None else None, part)))

    if rate(0.0, element) < TARGET_CONFORMITY:  # f_pt is loose against F_p: the per-element part decides
        lo, hi = 0.0, element
        for _ in range(32):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if rate(0.0, mid) >= TARGET_CONFORMITY else (lo, mid)
        return HarmonicPart(0.0, 0.0, lo, radial * lo / element if element else 0.0, rate(0.0, lo))
    lo, hi = 0.0, part.cumulative_pitch_um
    for _ in range(32):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if rate(mid, element) >= TARGET_CONFORMITY else (lo, mid)
    return HarmonicPart(lo, SECOND_TO_FIRST * lo, element, radial, rate(lo, element))
