"""The wear of a load profile read at a unit's pins, compiled (docs/service-life.md, "The production
run"; analysis/service_life/units.py): a unit's load at its pins' phases, linear between them along
the tooth, worn into the flank (at each place), the pins (round a turning pin) and their seats (at
the normal's direction) by Archard's law per output revolution (``models.wear``'s formulas, the
weights in ``ProfileTables``), and the wear depths read back at every pin: its flank place and its
normal's direction. The same arithmetic as ``units.profile_wear`` + ``units.growth_at_pins`` on the
phase grid (tested to 1e-12), at a few microseconds a unit.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from rvbacklash._numba import njit

TWO_PI = 2.0 * math.pi


class ProfileTables(NamedTuple):
    """A design's wear weights on the phase grid (G places over both flanks of a tooth; the
    direction bins B at a pin): the depth [um] a load of 1 N/mm at a place adds per output revolution
    to the flank there (``flank``), to a turning pin's surface (``pin``) and to the bin of the normal's
    direction (``seat``, the pin's own surface when it does not turn, and its seat; to be divided by
    the bin's width [mm])."""

    phase_rad: np.ndarray  # (G,) uniform: (p + 1/2) 2 pi / G
    flank: np.ndarray  # (G,) [um per N/mm]
    pin: np.ndarray  # (G,) [um per N/mm]
    seat: np.ndarray  # (G,) [um mm per N/mm]
    direction_bin: np.ndarray  # (G,) int64
    bin_width_mm: np.ndarray  # (B,)
    direction_centres_rad: np.ndarray  # (B,) uniform
    k1: float


@njit(nogil=True, cache=True)
def _interp_uniform(grid, values, x, periodic):
    """values on a uniform increasing grid at x: linear, periodic over the grid's G steps or clamped."""
    g = grid.size
    step = grid[1] - grid[0]
    s = (x - grid[0]) / step
    if periodic:
        lo = math.floor(s)
        w = s - lo
        i0 = int(lo) % g
        i1 = (i0 + 1) % g
    else:
        s = min(max(s, 0.0), g - 1.0)
        i0 = min(int(math.floor(s)), g - 2)
        w = s - i0
        i1 = i0 + 1
    return (1.0 - w) * values[i0] + w * values[i1]


@njit(nogil=True, cache=True)
def pins_growth_um(load_n_per_mm, chi_rad, tables, scale, out):
    """out (n, discs, z_p) += scale x the gap growth [um] per output revolution of every pin of n units
    from their load profiles: load_n_per_mm (n, discs, z_p) at every pin's phase
    phi = 2 pi j / z_p - chi - 2 pi d / discs (chi_rad (n,)), linear between the pins' phases."""
    n, discs, zp = load_n_per_mm.shape
    g = tables.phase_rad.size
    b = tables.bin_width_mm.size
    pitch = TWO_PI / zp
    flank = np.empty(g)
    bins = np.empty(b)
    for u in range(n):
        for d in range(discs):
            v = load_n_per_mm[u, d]
            c = -chi_rad[u] - TWO_PI * d / discs  # pin j's phase: j pitch + c
            pin = 0.0
            for i in range(b):
                bins[i] = 0.0
            for p in range(g):
                s = (tables.phase_rad[p] - c) / pitch
                lo = math.floor(s)
                w = s - lo
                j0 = int(lo) % zp
                q = (1.0 - w) * v[j0] + w * v[(j0 + 1) % zp]
                flank[p] = tables.flank[p] * q
                pin += tables.pin[p] * q
                bins[tables.direction_bin[p]] += tables.seat[p] * q
            for i in range(b):
                bins[i] /= tables.bin_width_mm[i]
            for j in range(zp):
                phi = (j * pitch + c) % TWO_PI
                theta = math.atan2(tables.k1 * math.sin(phi), 1.0 - tables.k1 * math.cos(phi))
                out[u, d, j] += scale * (_interp_uniform(tables.phase_rad, flank, phi, True) + pin
                                         + _interp_uniform(tables.direction_centres_rad, bins, theta, False))
