"""The selection rules, one small compiled function each (docs/selective-assembly.md, "Rules").

What the factory predicts of a unit before it picks its parts is the cycloid stage's *linearised
rigid play* (``models.contact.free_interval_bounds``: the free interval hi - lo of the disc's turn
that every pin's linearised gap gap_j - lever_j beta allows; negative: the pins interfere), read
from the unit's measured discs and housing with every pin at its class's mean radius; each pin's
gap is linear in its radius (``models.contact.pin_base_um``: gap = ... - rho_j), so

    P(s) = [min_{lever > 0} (g0_j - s) / lever_j - max_{lever < 0} (g0_j - s) / lever_j] ARCMIN_PER_RAD,
    g0_j = gap_j + rho_j  (the gap the pin hole leaves a pin of nominal radius),

with s the pins' radius deviation [um]; P decreases with s. The measurement's error e ~ N(0,
noise) [um of pin radius] shifts what the factory reads: it predicts P(s + e).
"""

from __future__ import annotations

import math

import numpy as np

from rvbacklash._numba import njit
from rvbacklash.units import ARCMIN_PER_RAD


@njit(nogil=True, cache=True)
def predicted_play_arcmin(gap, lever, radius, shift_um, tol):
    """P(shift) [arcmin] of a unit's gaps (discs, z_p) [um] and levers [um/rad] found with pin radii
    ``radius`` (z_p) [um], every pin's radius set to ``shift_um`` (module docstring); levers within
    ``tol`` [um/rad] of 0 do not bound the turn."""
    lo, hi = -np.inf, np.inf
    discs, zp = gap.shape
    for d in range(discs):
        for j in range(zp):
            g, lv = gap[d, j] + radius[j] - shift_um, lever[d, j]
            if lv > tol:
                hi = min(hi, g / lv)
            elif lv < -tol:
                lo = max(lo, g / lv)
    return (hi - lo) * ARCMIN_PER_RAD


@njit(nogil=True, cache=True, inline="always")
def window_distance(x, lo, hi):
    """How far x lies outside the window [lo, hi] (0 inside)."""
    return max(x - hi, 0.0) + max(lo - x, 0.0)


@njit(nogil=True, cache=True, inline="always")
def _better(e, c, best, best_c, k):
    """Class c (distance e) beats the best so far: nearer the window, or as near and nearer the
    middle class of k (the most abundant: the classes are centred on the law's mean)."""
    if e < best - 1e-12:
        return True
    return e <= best + 1e-12 and abs(2 * c - (k - 1)) < abs(2 * best_c - (k - 1))


@njit(nogil=True, cache=True)
def pin_class_rule(gap, lever, radius, pins, noise_um, window, tol):
    """The pin class whose mean radius brings the unit's predicted play (read with the measurement
    error ``noise_um``) into ``window`` (lo, hi) [arcmin], or nearest it; among the classes that do
    equally well, the one nearest the middle; a class no part falls in (share 0) is never taken.
    Returns (class, its predicted play [arcmin])."""
    k = pins.mean_um.size
    best, best_c, best_p = np.inf, -1, 0.0
    for c in range(k):
        if pins.share[c] <= 0.0:
            continue
        p = predicted_play_arcmin(gap, lever, radius, pins.mean_um[c] + noise_um, tol)
        e = window_distance(p, window[0], window[1])
        if best_c < 0 or _better(e, c, best, best_c, k):
            best, best_c, best_p = e, c, p
    return best_c, best_p


@njit(nogil=True, cache=True)
def roller_class_rule(play_arcmin, rollers, sens_arcmin_per_um, target_arcmin):
    """The roller class that brings the unit's predicted play (a closed stage adds none) plus the
    crank bearings' share at the class's mean clearance to ``target_arcmin`` or below, or nearest
    it; among the classes that do equally well, the one nearest the middle: the rollers take up what
    the pin classes could not."""
    k = rollers.mean_um.size
    best, best_c = np.inf, -1
    base = max(play_arcmin, 0.0)
    for c in range(k):
        if rollers.share[c] <= 0.0:
            continue
        e = window_distance(base + sens_arcmin_per_um * rollers.mean_um[c], -np.inf, target_arcmin)
        if best_c < 0 or _better(e, c, best, best_c, k):
            best, best_c = e, c
    return best_c


@njit(nogil=True, cache=True)
def in_class_um(x_um, table, c):
    """A part drawn as ``x_um`` from the law, taken from class c instead: the class's part at the same
    quantile (the law's cdf, then the class band's inverse cdf; ``classes.ClassTable``)."""
    u = np.interp(x_um, table.x_um, table.cdf)
    k = table.ppf_um.shape[1]
    t = u * k - 0.5
    i = min(max(int(math.floor(t)), 0), k - 2)
    w = min(max(t - i, 0.0), 1.0)
    row = table.ppf_um[c]
    return row[i] + w * (row[i + 1] - row[i])
