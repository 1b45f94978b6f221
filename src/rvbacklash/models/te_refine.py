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
at points between the positions with the mesh placed there (``contact.mesh_column_at``, the pins' angles
computed once), less the error-free unit's flank read on its points solved once per design
(REFERENCE_POINTS a step, linear between: its ripple is 0.07 arcsec), only where an extreme can lie:

- about the sampled curve's best local extremes (WINDOW_EXTREMES of them, for the maximum and the
  minimum): WINDOW_POINTS points a step over the step either side;
- the steps whose screened flank passes the best so far less SCREEN_MARGIN_RAD (screen_steps: every pin's
  gap and lever interpolated at SCREEN_POINTS - 1 points of every step, the first contact or an estimate of
  the balanced rotation; at most SCREEN_CANDIDATES steps, best estimate first): at SCREEN_OFFSETS about the
  estimate (a preloaded stage's hump or dip inside a step: seed 3 units 2 and 8);
- the cusps of a free stage where the first contact switches pins between two positions;
- every swing the recorded gaps cannot rule out - a pin near contact (a recorded gap below SWING_GAP_UM at
  either end of the step) whose lever changes sign in the step - whose reach (the rotation the other pins
  leave, kinematics.swing_reach: at the step's ends, free_ends, then on the gaps interpolated at the cubic's
  lever zero) passes the best less SWING_PREFILTER_RAD, then SWING_MARGIN_RAD: the pin's lever zero is
  found on the solved points (regula falsi, LEVER_ITERATIONS) and the curve solved about it (SWING_OFFSETS);
- each window's, candidate's and swing's best point searched about (LOCAL_LEVELS halvings), then a
  pattern search about the extreme found (ZOOM_LEVELS halvings from 1 / WINDOW_POINTS of a step).

Every figure is the unit's solved (linearised) flank at a point less the error-free unit's there (read within
~0.02 arcsec), never an interpolated value of the unit's.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from rvbacklash._numba import njit
from rvbacklash.models.contact import N_COEF, free_interval_bounds, mesh_column_at, mesh_pin_angles, pin_gaps
from rvbacklash.models.kinematics import (ARCSEC_PER_RAD, FlankCurve, PositionTable, cubic_weights, curve_scratch,
                                          illinois_update, lever_zero, swing_reach, te_curve)

WINDOW_EXTREMES = 2  # sampled local extremes refined by a window, for the maximum and for the minimum
WINDOW_POINTS = 4  # points a step in a window (the step either side of the extreme)
ZOOM_LEVELS = 6  # pattern-search halvings about each extreme, from 1 / WINDOW_POINTS of a step
SWING_GAP_UM = 1.0  # a pin whose lever changes sign in a step is read if its recorded gap at either end is below
LEVER_ITERATIONS, LEVER_TOL = 10, 1e-4  # regula falsi (Illinois) on the solved lever of a swing's pin: at most; [steps]
SWING_OFFSETS = (-1e-3, -1e-4, 0.0, 1e-4, 1e-3)  # of a step, about a swing's solved lever zero
SWING_SOLVED_GAP_UM = 0.05  # a swing's pin whose solved gap near its lever's zero is above this does not interfere
CUSP_OFFSETS = (-0.03, 0.0, 0.03)  # of a step, about a cusp's estimate
CUSP_POINTS = 8  # a cusp's estimate is read at the points s / CUSP_POINTS of its step
SCREEN_POINTS = 4  # the flank interpolated at the points s / SCREEN_POINTS of every step (screen_steps)
SCREEN_CANDIDATES = 12  # steps solved about their estimate at most
SCREEN_MARGIN_RAD = 2.0 / ARCSEC_PER_RAD  # a step is solved if its estimate passes the best so far less this (2 arcsec)
SCREEN_OFFSETS = (-0.0625, 0.0, 0.0625)  # of a step, about a step's estimate
SWING_PREFILTER_RAD = 10.0 / ARCSEC_PER_RAD  # a swing is read further if its reach at the step's ends passes the best
#                                             so far less this (10 arcsec)
SWING_MARGIN_RAD = 2.0 / ARCSEC_PER_RAD  # a swing is solved if its reach passes the best so far less this (2 arcsec)
LOCAL_LEVELS = 2  # pattern-search halvings about each window's, candidate's and swing's best point
SWING_ZOOM = 1.0 / 32  # of a step: the first step of a swing's pattern search (the bowl after a swing: unit 11)
REFERENCE_POINTS = 32  # the error-free unit solved at this many points a step (reference_between), linear between


class TEReference(NamedTuple):
    """The error-free unit as the production run reads it: its ccw flank at the run's positions [rad], its
    UnitErrors, whether the run refines each unit's peak-to-peak between its positions (refined_extreme) or
    reads it at the positions (sampled), and (refined) its ccw flank [rad] at REFERENCE_POINTS points of every
    step (reference_between; (rows, points), point 0 the position; (0, 0) when sampled)."""

    ccw_rad: np.ndarray
    unit: object  # UnitErrors
    refine: bool
    between_rad: np.ndarray


class PointWork(NamedTuple):
    """Scratch of one solved point (point_te): a one-position table, the unit's recorded curve there
    (its gaps and levers), the pins' angles of the mesh (mesh_pin_angles), the pins' gaps interpolated for
    a swing's reach."""

    table: PositionTable
    curve: FlankCurve
    pins: np.ndarray  # (4, z_p)
    gaps: object  # PinGaps
    estimate: np.ndarray  # (2, rows) screen_steps' estimate of each step: TE, -TE
    estimate_at: np.ndarray
    ends: np.ndarray  # (4, rows) at each position: the least and second least g / l of the pins with l > 0, the
    #                   largest and second largest with l < 0 (the free interval's ends with and without one pin)
    end_pins: np.ndarray  # (2, rows) the pin (d z_p + j) of the least and of the largest
    points: np.ndarray  # points solved so far: windows, cusps, swings, pattern search (the bench reads them)


@njit(nogil=True, cache=True)
def point_work(stage, planets, rows):
    discs, zp = stage.discs, stage.zp
    table = PositionTable(np.zeros(1), np.zeros(1), np.empty((1, N_COEF, discs, zp)))
    curve = FlankCurve(np.empty(1), np.empty(1), np.empty(1), np.empty((1, discs, zp), np.float32),
                       np.empty((1, discs, zp), np.float32))
    pins = np.empty((4, zp))
    mesh_pin_angles(stage, pins)
    return PointWork(table, curve, pins, pin_gaps(discs, zp), np.empty((2, rows)), np.empty((2, rows)), np.empty((4, rows)), np.empty((2, rows), np.int64),
                     np.zeros(4, np.int64))


@njit(nogil=True, cache=True)
def point_te(stage, kin, unit, ref, scratch, work, x, with_ref):
    """The ccw flank's TE [rad] of ``unit`` at the point x (in steps of a revolution of rows = ref.ccw_rad.size
    positions from the reference position): the mesh placed there (mesh_column_at), the unit's curve solved
    (te_curve, linearised; its gaps and levers recorded in work.curve), less the error-free unit's there
    (when ``with_ref``: reference_at; else the unit's flank position alone)."""
    rows = ref.ccw_rad.size
    theta = (x % rows) * 2.0 * math.pi / rows
    chi = -stage.zc * theta
    work.table.theta_rad[0] = theta
    work.table.chi_rad[0] = chi
    mesh_column_at(stage, chi, work.pins, work.table.coef[0])
    linearised = rows < 0  # False, not as a literal: te_curve compiled once for every caller
    te_curve(stage, kin, work.table, unit, 0.0, scratch, work.curve, linearised)
    if not with_ref:
        return work.curve.ccw_rad[0]
    return work.curve.ccw_rad[0] - reference_at(ref, x)


@njit(nogil=True, cache=True)
def reference_at(ref, x):
    """The error-free unit's ccw flank [rad] at the point x (in steps): linear between its solved points
    (TEReference.between_rad, REFERENCE_POINTS a step). Its ripple is 0.07 arcsec for rv80e (order z_c z_p, ~5
    periods a step of 320 positions, with cusps): read at 32 points a step, the line between them is within
    ~0.02 arcsec of it (tested); the unit's own flank is solved at x."""
    rows, points = ref.between_rad.shape
    u = (x % rows) * points
    k = int(math.floor(u))
    t = u - k
    k0, k1 = k % (rows * points), (k + 1) % (rows * points)
    a = ref.between_rad[k0 // points, k0 % points]
    b = ref.between_rad[k1 // points, k1 % points]
    return (1.0 - t) * a + t * b


@njit(nogil=True, cache=True)
def reference_between(stage, kin, ref, out):
    """The error-free unit's (ref.unit) ccw flank [rad] at the points s / points of every step n of the run's
    revolution into out (rows, points): solved there (point_te); s = 0 the run's own position (ref.ccw_rad)."""
    rows, points = out.shape
    scratch = curve_scratch(stage.zp, stage.zc, stage.discs, kin.planets)
    work = point_work(stage, kin.planets, rows)
    for n in range(rows):
        out[n, 0] = ref.ccw_rad[n]
        for s in range(1, points):
            out[n, s] = point_te(stage, kin, ref.unit, ref, scratch, work, n + s / points, False)


@njit(nogil=True, cache=True)
def refined_peak_to_peak(stage, kin, unit, ref, scratch, work, curve):
    """The ccw flank's TE peak-to-peak [rad] of ``unit`` over the revolution: its recorded FlankCurve ``curve``
    at the run's positions, refined between them (screen_steps, then refined_extreme for its largest and its
    least value)."""
    screen_steps(curve, ref, stage.pitch_radius_um, work.gaps, work.estimate, work.estimate_at)
    free_ends(curve, stage.pitch_radius_um, work.ends, work.end_pins)
    return refined_extreme(stage, kin, unit, ref, scratch, work, curve, 1.0) + \
        refined_extreme(stage, kin, unit, ref, scratch, work, curve, -1.0)


@njit(nogil=True, cache=True)
def refined_extreme(stage, kin, unit, ref, scratch, work, curve, sign):
    """The largest sign x TE [rad] of the ccw flank of ``unit`` over the revolution: its recorded
    FlankCurve ``curve`` at the run's positions (gaps and levers recorded), refined between them (module
    docstring)."""
    rows = curve.ccw_rad.size
    ref_ccw = ref.ccw_rad
    solver = PointSolver(stage, kin, unit, ref, scratch, work)
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
        lb, lx = top, float(at)
        for m in range(-WINDOW_POINTS, WINDOW_POINTS + 1):
            if m == 0:
                continue
            x = at + m / WINDOW_POINTS
            work.points[0] += 1
            v = sign * point_te(stage, kin, unit, ref, scratch, work, x, True)
            if v > lb:
                lb, lx = v, x
        lx, lb = zoom(solver, sign, lx, lb, 1.0 / WINDOW_POINTS, LOCAL_LEVELS)
        if lb > best:
            best, where = lb, lx
    gap, lever = curve.gap_um, curve.lever_um_per_rad
    discs, zp = gap.shape[1], gap.shape[2]
    tol = 1e-9 * stage.pitch_radius_um
    # the steps whose interpolated flank passes the best so far (screen_steps), best estimate first
    est, at_ = work.estimate[0 if sign > 0.0 else 1], work.estimate_at[0 if sign > 0.0 else 1]
    for c in range(SCREEN_CANDIDATES):
        k = np.argmax(est)
        if not est[k] + SCREEN_MARGIN_RAD > best:
            break
        est[k] = -np.inf
        lb, lx = -np.inf, 0.0
        for o in SCREEN_OFFSETS:
            x = k + min(max(at_[k] + o, 0.0), 1.0)
            work.points[1] += 1
            v = sign * point_te(stage, kin, unit, ref, scratch, work, x, True)
            if v > lb:
                lb, lx = v, x
        lx, lb = zoom(solver, sign, lx, lb, SCREEN_OFFSETS[-1], LOCAL_LEVELS)
        if lb > best:
            best, where = lb, lx
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
                # what the swing can reach at the step's ends (O(1): free_ends), then, if that comes within
                # SWING_PREFILTER_RAD of the best, at the cubic's lever zero (the cubic's zero may lie a tenth of a
                # step from the solved one where the pin passes a tooth tip, and the reach between the ends pass
                # both: seed 3 unit 11)
                pin = d * zp + j
                reach = -np.inf
                for k in (n, n1):
                    if sign > 0.0:
                        e = (work.ends[1, k] if work.end_pins[0, k] == pin else work.ends[0, k]) - ref_ccw[k]
                    else:
                        e = ref_ccw[k] - (work.ends[3, k] if work.end_pins[1, k] == pin else work.ends[2, k])
                    reach = max(reach, e)
                if not (math.isfinite(reach) and reach + SWING_PREFILTER_RAD > best):
                    continue
                f0 = lever_zero(curve, n, d, j)  # the cubic's (kinematics.interpolated_flanks)
                w0, w1, w2, w3 = cubic_weights(f0)
                k0, k3 = (n - 1) % rows, (n + 2) % rows
                for dd in range(discs):
                    for jj in range(zp):
                        gi[dd, jj] = w0 * gap[k0, dd, jj] + w1 * gap[n, dd, jj] + w2 * gap[n1, dd, jj] + \
                            w3 * gap[k3, dd, jj]
                        li[dd, jj] = w0 * lever[k0, dd, jj] + w1 * lever[n, dd, jj] + w2 * lever[n1, dd, jj] + \
                            w3 * lever[k3, dd, jj]
                lo, hi = swing_reach(work.gaps, d, j, stage.pitch_radius_um)
                r0 = reference_at(ref, n + f0)
                reach = max(reach, hi - r0 if sign > 0.0 else r0 - lo)
                if not (math.isfinite(reach) and reach + SWING_MARGIN_RAD > best):
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
                    xa, la, xb, lb, kept = illinois_update(xa, la, xb, lb, kept, x, lx)
                if work.curve.gap_um[0, d, j] > SWING_SOLVED_GAP_UM:
                    continue
                z = xa if xa == xb else x  # the last estimate (an Illinois bracket need not close on both sides)
                lb, lx = -np.inf, z
                for o in SWING_OFFSETS:
                    work.points[2] += 1
                    v = sign * point_te(stage, kin, unit, ref, scratch, work, z + o, True)
                    if v > lb:
                        lb, lx = v, z + o
                lx, lb = zoom(solver, sign, lx, lb, SWING_ZOOM, LOCAL_LEVELS)
                if lb > best:
                    best, where = lb, lx
    # a pattern search about the extreme found
    where, best = zoom(solver, sign, where, best, 1.0 / WINDOW_POINTS, ZOOM_LEVELS)
    return best


class PointSolver(NamedTuple):
    """What point_te solves a unit's point with (zoom's record): the design's StageGeometry and Kinematics, the
    unit's UnitErrors, the TEReference, te_curve's scratch and the PointWork."""

    stage: object
    kin: object
    unit: object
    ref: TEReference
    scratch: object
    work: PointWork


@njit(nogil=True, cache=True)
def zoom(p, sign, x, v, h, levels):
    """A pattern search of sign x TE about the point x (value v) of the unit of PointSolver ``p``: ``levels``
    halvings of h, each trying x - h and x + h and moving to the better; returns (x, v)."""
    for _ in range(levels):
        h *= 0.5
        for y in (x - h, x + h):
            p.work.points[3] += 1
            w = sign * point_te(p.stage, p.kin, p.unit, p.ref, p.scratch, p.work, y, True)
            if w > v:
                x, v = y, w
    return x, v


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


@njit(nogil=True, cache=True)
def screen_steps(curve, ref, azc_um, gaps, est, at):
    """For each step n -> n + 1 of the recorded FlankCurve ``curve`` the largest TE [rad] of the ccw flank
    (est[0, n]) and the largest -TE (est[1, n]) estimated at the points s / SCREEN_POINTS, and where (at[:, n],
    the fraction of the step): every pin's gap and lever interpolated (kinematics.cubic_weights), the first
    contact of the free interval, or where pins interfere the balanced rotation on them (two Newton steps
    from the line between the step's ends: an estimate, not the solve), less the error-free unit's there
    (reference_at)."""
    rows, discs, zp = curve.gap_um.shape
    g, lv = gaps.gap_um, gaps.lever_um_per_rad
    for n in range(rows):
        for i in range(2):
            est[i, n] = -np.inf
            at[i, n] = 0.5
        k0, k1, k2, k3 = (n - 1) % rows, n, (n + 1) % rows, (n + 2) % rows
        for s in range(1, SCREEN_POINTS):
            f = s / SCREEN_POINTS
            w0, w1, w2, w3 = cubic_weights(f)
            for d in range(discs):
                g0, g1, g2, g3 = curve.gap_um[k0, d], curve.gap_um[k1, d], curve.gap_um[k2, d], curve.gap_um[k3, d]
                l0, l1, l2, l3 = curve.lever_um_per_rad[k0, d], curve.lever_um_per_rad[k1, d], \
                    curve.lever_um_per_rad[k2, d], curve.lever_um_per_rad[k3, d]
                gd, ld = g[d], lv[d]
                for j in range(zp):  # one pass the compiler runs several pins at a time
                    gd[j] = w0 * g0[j] + w1 * g1[j] + w2 * g2[j] + w3 * g3[j]
                    ld[j] = w0 * l0[j] + w1 * l1[j] + w2 * l2[j] + w3 * l3[j]
            lo, hi, flat = free_interval_bounds(gaps, azc_um)
            if hi < lo or flat < 0.0:
                beta = (1.0 - f) * curve.ccw_rad[n] + f * curve.ccw_rad[k2]
                for _ in range(2):
                    fb, slope = 0.0, 0.0
                    for d in range(discs):
                        for j in range(zp):
                            p = lv[d, j] * beta - g[d, j]
                            if p > 0.0:
                                fb += lv[d, j] * p
                                slope += lv[d, j] * lv[d, j]
                    if slope > 0.0:
                        beta -= fb / slope
                flank = beta
            else:
                flank = hi
            v = flank - reference_at(ref, n + f)
            if v > est[0, n]:
                est[0, n] = v
                at[0, n] = f
            if -v > est[1, n]:
                est[1, n] = -v
                at[1, n] = f


@njit(nogil=True, cache=True)
def free_ends(curve, azc_um, ends, end_pins):
    """At each recorded position of ``curve`` the ends of the free interval with and without the pin that sets
    each (PointWork.ends, end_pins): what a swing of any one pin can reach there (swing_reach, in O(1))."""
    rows, discs, zp = curve.gap_um.shape
    tol = 1e-9 * azc_um
    for n in range(rows):
        h1, h2, l1, l2, hp, lp = np.inf, np.inf, -np.inf, -np.inf, -1, -1
        for d in range(discs):
            for j in range(zp):
                g, lv = curve.gap_um[n, d, j], curve.lever_um_per_rad[n, d, j]
                if lv > tol:
                    r = g / lv
                    if r < h1:
                        h1, h2, hp = r, h1, d * zp + j
                    elif r < h2:
                        h2 = r
                elif lv < -tol:
                    r = g / lv
                    if r > l1:
                        l1, l2, lp = r, l1, d * zp + j
                    elif r > l2:
                        l2 = r
        ends[0, n], ends[1, n], ends[2, n], ends[3, n] = h1, h2, l1, l2
        end_pins[0, n], end_pins[1, n] = hp, lp
