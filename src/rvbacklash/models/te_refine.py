"""The production run's TE peak-to-peak refined between its positions, compiled (issue 36 item 8;
docs/transmission-error.md, "The production run").

The run turns each unit through 8 z_p positions (320 for rv80e), each flank's first contact
linearised there (``kinematics.te_curve`` with exact=False). Sampled there, the ccw flank's
peak-to-peak read 8 % low on average (up to 31 % for a unit) against the converged figure of
``transmission-error``: the extremes are features narrower than a step - the first contact's cusps
and the balanced rotation's swings and dips where a pin with almost no lever interferes
(kinematics.balanced_rotation) - that the positions straddle. ``transmission-error`` finds them by
interpolating every pin's gap and lever at 7 points of every step and solving the exact curve where
the estimates pass the sampled extremes (~45 ms a unit). Here the same curve (linearised) is solved
at points between the positions with the mesh placed there (``contact.mesh_column``), only where an
extreme can lie:

- about the sampled curve's best local extremes (WINDOW_EXTREMES of them, for the maximum and the
  minimum): WINDOW_POINTS points a step over the step either side;
- at every swing the recorded gaps cannot rule out - a pin near contact (a recorded gap below
  SWING_GAP_UM at either end of the step) whose lever changes sign in the step - whose reach (the
  rotation the other pins leave, kinematics.swing_reach, on the gaps interpolated linearly there)
  passes the extreme found so far: the pin's lever zero is found on the solved points (regula falsi,
  LEVER_ITERATIONS) and the curve solved about it (kinematics.SWING_OFFSETS);
- then a pattern search about each extreme (ZOOM_LEVELS halvings from 1 / WINDOW_POINTS of a step).

Every figure is a point of the solved (linearised) curve, never an interpolated value.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from rvbacklash._numba import njit
from rvbacklash.models.contact import N_COEF, mesh_column, pin_gaps
from rvbacklash.models.kinematics import FlankCurve, PositionTable, cubic_weights, curve_scratch, swing_reach, te_curve

WINDOW_EXTREMES = 2  # sampled local extremes refined by a window, for the maximum and for the minimum
WINDOW_POINTS = 8  # points a step in a window (the step either side of the extreme)
ZOOM_LEVELS = 6  # pattern-search halvings about each extreme, from 1 / WINDOW_POINTS of a step
SWING_GAP_UM = 1.0  # a pin whose lever changes sign in a step is read if its recorded gap at either end is below
LEVER_ITERATIONS, LEVER_TOL = 10, 1e-4  # regula falsi (Illinois) on the solved lever of a swing's pin: at most; [steps]
SWING_OFFSETS = (-1e-3, -1e-4, 0.0, 1e-4, 1e-3)  # of a step, about a swing's solved lever zero
SWING_SOLVED_GAP_UM = 0.05  # a swing's pin whose solved gap near its lever's zero is above this does not interfere
CUSP_OFFSETS = (-0.03, 0.0, 0.03)  # of a step, about a cusp's estimate
CUSP_POINTS = 8  # a cusp's estimate is read at the points s / CUSP_POINTS of its step


class TEReference(NamedTuple):
    """The error-free unit as the production run reads it: its ccw flank at the run's positions [rad] and
    its UnitErrors (solved at the points between them), and whether the run refines each unit's
    peak-to-peak between its positions (refined_extreme) or reads it at the positions (sampled)."""

    ccw_rad: np.ndarray
    unit: object  # UnitErrors
    refine: bool


class PointWork(NamedTuple):
    """Scratch of one solved point (point_te): a one-position table, the unit's recorded curve there
    (its gaps and levers), the error-free unit's, the pins' gaps interpolated for a swing's reach."""

    table: PositionTable
    curve: FlankCurve
    ref_curve: FlankCurve
    ref_scratch: object  # CurveScratch of the error-free unit
    gaps: object  # PinGaps
    points: np.ndarray  # points solved so far: windows, cusps, swings, pattern search (the bench reads them)


@njit(nogil=True, cache=True)
def point_work(stage, planets):
    discs, zp = stage.discs, stage.zp
    table = PositionTable(np.zeros(1), np.zeros(1), np.empty((1, N_COEF, discs, zp)))
    curve = FlankCurve(np.empty(1), np.empty(1), np.empty(1), np.empty((1, discs, zp), np.float32),
                       np.empty((1, discs, zp), np.float32))
    ref_curve = FlankCurve(np.empty(1), np.empty(1), np.empty(1), np.empty((0, discs, zp), np.float32),
                           np.empty((0, discs, zp), np.float32))
    return PointWork(table, curve, ref_curve, curve_scratch(zp, stage.zc, discs, planets), pin_gaps(discs, zp),
                     np.zeros(4, np.int64))


@njit(nogil=True, cache=True)
def point_te(stage, kin, unit, ref, scratch, work, x, with_ref):
    """The ccw flank's TE [rad] of ``unit`` at the point x (in steps of a revolution of rows = ref.ccw_rad.size
    positions from the reference position): the mesh placed there (mesh_column), the unit's curve solved
    (te_curve, linearised; its gaps and levers recorded in work.curve), less the error-free unit's there
    (when ``with_ref``; else the unit's flank position alone)."""
    rows = ref.ccw_rad.size
    theta = (x % rows) * 2.0 * math.pi / rows
    chi = -stage.zc * theta
    work.table.theta_rad[0] = theta
    work.table.chi_rad[0] = chi
    mesh_column(stage, chi, work.table.coef[0])
    linearised = rows < 0  # False, not as a literal: te_curve compiled once for every caller
    te_curve(stage, kin, work.table, unit, 0.0, scratch, work.curve, linearised)
    if not with_ref:
        return work.curve.ccw_rad[0]
    te_curve(stage, kin, work.table, ref.unit, 0.0, work.ref_scratch, work.ref_curve, linearised)
    return work.curve.ccw_rad[0] - work.ref_curve.ccw_rad[0]


@njit(nogil=True, cache=True)
def refined_extreme(stage, kin, unit, ref, scratch, work, curve, sign):
    """The largest sign x TE [rad] of the ccw flank of ``unit`` over the revolution: its recorded
    FlankCurve ``curve`` at the run's positions (gaps and levers recorded), refined between them (module
    docstring)."""
    rows = curve.ccw_rad.size
    ref_ccw = ref.ccw_rad
    best, where = -np.inf, 0.0
    for n in range(rows):
        v = sign * (curve.ccw_rad[n] - ref_ccw[n])
        if v > best:
            best, where = v, float(n)
    # windows about the best sampled local extremes
    taken = np.full(WINDOW_EXTREMES, -1)
    for e in range(WINDOW_EXTREMES):
        top, at = -np.inf, -1
        for n in range(rows):
            v = sign * (curve.ccw_rad[n] - ref_ccw[n])
            if v < sign * (curve.ccw_rad[n - 1] - ref_ccw[n - 1]) or \
                    v < sign * (curve.ccw_rad[(n + 1) % rows] - ref_ccw[(n + 1) % rows]):
                continue
            seen = False
            for t in range(e):
                seen = seen or taken[t] == n
            if not seen and v > top:
                top, at = v, n
        if at < 0:
            break
        taken[e] = at
        for m in range(-WINDOW_POINTS, WINDOW_POINTS + 1):
            if m == 0:
                continue
            x = at + m / WINDOW_POINTS
            work.points[0] += 1
            v = sign * point_te(stage, kin, unit, ref, scratch, work, x, True)
            if v > best:
                best, where = v, x
    gap, lever = curve.gap_um, curve.lever_um_per_rad
    discs, zp = gap.shape[1], gap.shape[2]
    tol = 1e-9 * stage.pitch_radius_um
    # cusps of a free stage's ccw flank (the least of the pins' contact rotations g / l, l > 0: it peaks
    # where the first contact switches pins): the pin first in contact at n and the one at n + 1, each
    # extrapolated linearly from its other neighbour, meet at the cusp's estimate
    if sign > 0.0:
        for n in range(rows):
            n1 = (n + 1) % rows
            if curve.ccw_rad[n] == curve.cw_rad[n] or curve.ccw_rad[n1] == curve.cw_rad[n1]:
                continue  # preloaded at an end: the balanced rotation (swings, below)
            a, b = first_contact(gap, lever, n, tol), first_contact(gap, lever, n1, tol)
            if a < 0 or b < 0 or a == b:
                continue
            est, f = -np.inf, 0.5
            for s_ in range(1, CUSP_POINTS):
                ff = s_ / CUSP_POINTS
                c = min(interpolated_rotation(curve, n, ff, a, tol), interpolated_rotation(curve, n, ff, b, tol))
                v = c - ((1.0 - ff) * ref_ccw[n] + ff * ref_ccw[n1])
                if v > est:
                    est, f = v, ff
            if est > best:
                for o in CUSP_OFFSETS:
                    x = n + min(max(f + o, 0.0), 1.0)
                    work.points[1] += 1
                    v = point_te(stage, kin, unit, ref, scratch, work, x, True)
                    if v > best:
                        best, where = v, x
    # swings the recorded gaps cannot rule out, whose reach passes the best so far
    gi, li = work.gaps.gap_um, work.gaps.lever_um_per_rad
    for n in range(rows):
        n1 = (n + 1) % rows
        for d in range(discs):
            for j in range(zp):
                l0, l1 = lever[n, d, j], lever[n1, d, j]
                if not (l0 * l1 < 0.0 and min(gap[n, d, j], gap[n1, d, j]) < SWING_GAP_UM):
                    continue
                f0 = l0 / (l0 - l1)
                for dd in range(discs):
                    for jj in range(zp):
                        gi[dd, jj] = (1.0 - f0) * gap[n, dd, jj] + f0 * gap[n1, dd, jj]
                        li[dd, jj] = (1.0 - f0) * lever[n, dd, jj] + f0 * lever[n1, dd, jj]
                lo, hi = swing_reach(work.gaps, d, j, stage.pitch_radius_um)
                r0 = (1.0 - f0) * ref_ccw[n] + f0 * ref_ccw[n1]
                reach = hi - r0 if sign > 0.0 else r0 - lo
                if not (math.isfinite(reach) and reach > best):
                    continue
                xa, xb, la, lb = float(n), float(n + 1), float(l0), float(l1)
                kept = 0
                last = -1.0
                for it in range(LEVER_ITERATIONS):
                    x = xa - la * (xb - xa) / (lb - la)
                    if abs(x - last) < LEVER_TOL:
                        break
                    last = x
                    work.points[2] += 1
                    point_te(stage, kin, unit, ref, scratch, work, x, False)
                    lx = float(work.curve.lever_um_per_rad[0, d, j])
                    if lx == 0.0:
                        xa = xb = x
                        break
                    if (lx > 0.0) == (la > 0.0):
                        xa, la = x, lx
                        if kept == 1:
                            lb *= 0.5  # Illinois: an end kept twice in a row is halved
                        kept = 1
                    else:
                        xb, lb = x, lx
                        if kept == -1:
                            la *= 0.5
                        kept = -1
                if work.curve.gap_um[0, d, j] > SWING_SOLVED_GAP_UM:
                    continue
                z = xa if xa == xb else x  # the last estimate (an Illinois bracket need not close on both sides)
                for o in SWING_OFFSETS:
                    work.points[2] += 1
                    v = sign * point_te(stage, kin, unit, ref, scratch, work, z + o, True)
                    if v > best:
                        best, where = v, z + o
    # a pattern search about the extreme found
    h = 1.0 / WINDOW_POINTS
    for _ in range(ZOOM_LEVELS):
        h *= 0.5
        for x in (where - h, where + h):
            work.points[3] += 1
            v = sign * point_te(stage, kin, unit, ref, scratch, work, x, True)
            if v > best:
                best, where = v, x
    return best


@njit(nogil=True, cache=True)
def interpolated_rotation(curve, n, f, pin, tol):
    """Where [rad] the pin (d z_p + j) stops the ccw flank (g / l; inf without a lever that closes it) at
    the point f of step n -> n + 1, its gap and lever interpolated (kinematics.cubic_weights) on the
    recorded FlankCurve ``curve``."""
    rows, zp = curve.gap_um.shape[0], curve.gap_um.shape[2]
    d, j = pin // zp, pin % zp
    w = cubic_weights(f)
    g, lv = 0.0, 0.0
    for i in range(4):
        k = (n - 1 + i) % rows
        g += w[i] * curve.gap_um[k, d, j]
        lv += w[i] * curve.lever_um_per_rad[k, d, j]
    return g / lv if lv > tol else np.inf


@njit(nogil=True, cache=True)
def first_contact(gap, lever, n, tol):
    """The pin (d z_p + j) that stops the ccw flank first at recorded position n (-1: none)."""
    discs, zp = gap.shape[1], gap.shape[2]
    best, pin = np.inf, -1
    for d in range(discs):
        for j in range(zp):
            lv = lever[n, d, j]
            if lv > tol:
                r = gap[n, d, j] / lv
                if r < best:
                    best, pin = r, d * zp + j
    return pin
