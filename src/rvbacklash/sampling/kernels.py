"""Compiled inner loops (numba, nogil so that threads run them in parallel).

Draw order is part of the reproducibility contract: for each sample, factor by factor, two
``rng.random()`` (Box-Muller). numba's Generator methods reproduce numpy's streams bit for bit,
so the numpy fallbacks in ``engine`` give the same numbers. The default method's normals are
drawn by ``fast_normals`` (its own generator inside the kernel).
"""

from __future__ import annotations

import math
from typing import NamedTuple

from rvbacklash._numba import njit
import numpy as np

TWO_PI = 2.0 * math.pi


@njit(nogil=True, cache=True)
def box_muller_normal(r1, r2):
    """Sun et al. 2014, Eq. (8) with mu = 0, sigma = 1: z = sqrt(-2 ln R1) sin(2 pi R2).
    R1 is taken as 1 - u, u in [0, 1), so that ln never sees 0."""
    return math.sqrt(-2.0 * math.log(1.0 - r1)) * math.sin(TWO_PI * r2)


@njit(nogil=True, cache=True)
def linear_box_muller_block(rng, n, weights, offset, out):
    """out[i] = offset + sum_j z_ij * weights[j] (in order j), each z from two uniforms of
    ``rng`` by Eq. (8): the linear model with sigma folded into the weights."""
    k = weights.size
    for i in range(n):
        y = offset
        for j in range(k):
            r1 = rng.random()
            r2 = rng.random()
            y += box_muller_normal(r1, r2) * weights[j]
        out[i] = y


@njit(nogil=True, cache=True)
def box_muller_normals(rng, n, k, out):
    """(n, k) standard normals by Eq. (8), same draw order as ``linear_box_muller_block``."""
    for i in range(n):
        for j in range(k):
            r1 = rng.random()
            r2 = rng.random()
            out[i, j] = box_muller_normal(r1, r2)


class BlockSummary(NamedTuple):
    """One block's mergeable summary of one output (``accumulate``): the sums of its values shifted
    by (about) the mean, so that they do not cancel, its least and greatest value, and how many
    values pass the limit, are valid (not NaN) and are negative."""

    shifted_sum: float  # sum(y - shift)
    shifted_sum_sq: float  # sum((y - shift)^2)
    min: float
    max: float
    passing: int
    valid: int
    negative: int


@njit(nogil=True, cache=True)
def accumulate(y, shift, limit, upper, hist, h_lo, h_scale):
    """One block's BlockSummary of one output's values ``y``; NaN marks a sample the output does not
    apply to (e.g. the lost motion of a preloaded unit) and is skipped. Passing: y <= limit if
    ``upper`` else y >= limit;
    hist[1 + floor((y - h_lo) * h_scale)] += 1, with hist[0] / hist[-1] the under/overflow.
    """
    nb_bins = hist.size - 2
    s1 = 0.0
    s2 = 0.0
    mn = np.inf
    mx = -np.inf
    ok = 0
    valid = 0
    negative = 0
    for v in y:
        if v != v:  # NaN: not applicable
            continue
        valid += 1
        d = v - shift
        s1 += d
        s2 += d * d
        if v < mn:
            mn = v
        if v > mx:
            mx = v
        if (v <= limit) if upper else (v >= limit):
            ok += 1
        if v < 0.0:
            negative += 1
        t = (v - h_lo) * h_scale
        if t < 0.0:
            hist[0] += 1
        elif t >= nb_bins:
            hist[nb_bins + 1] += 1
        else:
            hist[int(t) + 1] += 1
    return BlockSummary(s1, s2, mn, mx, ok, valid, negative)


@njit(nogil=True, cache=True)
def count_joint(values, limits, upper):
    """Samples (columns of ``values``, one row per output) that meet every output's limit at
    once; NaN counts as meeting it (the output does not apply to that sample)."""
    k, n = values.shape
    count = 0
    for i in range(n):
        ok = True
        for c in range(k):
            v = values[c, i]
            if v != v:
                continue
            if (v > limits[c]) if upper[c] else (v < limits[c]):
                ok = False
                break
        if ok:
            count += 1
    return count
