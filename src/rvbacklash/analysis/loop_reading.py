"""The one reader of a hysteresis loop, model or measured (issue 29): the test bench's figures
read off four branches of (torque [N m], output angle [arcmin]) by the same definitions.

The loop runs 0 -> +T_R -> 0 -> -T_R -> 0 as the branches load+, unload+, load-, unload-, each in
the order run. A branch is read at a torque by linear interpolation along its nodes in running
order: the first node at exactly that torque if there is one (a branch that jumps through the
dead bands has two nodes at one torque: the one the branch arrives from), else the first
segment that spans it. The model's loops hold the definition torques as nodes, so their figures
are reproduced exactly; a measured loop is first averaged onto such a grid (analysis/bench.py).

    lost motion = 1/2 [load+(x T_R) + unload+(x T_R)] - 1/2 [load-(-x T_R) + unload-(-x T_R)]
    backlash    = unload+(0) - unload-(0)
    rigidity    = 2 (h - l) T_R / ([load+(h T_R) - load+(l T_R)] + [load-(-l T_R) - load-(-h T_R)])
    hysteresis loss = | closed integral of T d(theta) | over the four branches

(Nabtesco's catalogue wording for lost motion and "b/a" for rigidity; docs/elastic.md,
docs/bench-data.md). Angles in [arcmin], torques in [N m], the loss in [J] per cycle.
"""

from __future__ import annotations

import math
from typing import Mapping, Sequence

import numpy as np

from rvbacklash.errors import InputError
from rvbacklash.units import ARCMIN_PER_RAD

BRANCHES = ("load+", "unload+", "load-", "unload-")
# The rigidity's secants every loop reports (fractions of T_R, both loading branches): the
# catalogue's "b/a" has no torque points in any text we could read (docs/elastic.md), and makers
# quote stiffness in torque regions, so a comparison says which one it uses (issue 28)
SECANT_INTERVALS = ((0.0, 1.0), (0.03, 1.0), (0.5, 1.0))

Branches = Mapping[str, tuple[np.ndarray, np.ndarray]]


def as_branches(loop) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """{name: (torque [N m], angle [arcmin])} of a loop given as such a mapping, as rows with
    ``branch``, ``torque_nm``, ``angle_arcmin`` keys (the JSON's ``loop``) or as objects with those
    attributes (``HysteresisBranch``)."""
    if isinstance(loop, Mapping):
        return {k: (np.asarray(t, float), np.asarray(a, float)) for k, (t, a) in loop.items()}
    out = {}
    for b in loop:
        get = b.__getitem__ if isinstance(b, Mapping) else lambda k, b=b: getattr(b, k)
        out[get("branch")] = (np.asarray(get("torque_nm"), float), np.asarray(get("angle_arcmin"), float))
    return out


def angle_at(torque_nm: np.ndarray, angle_arcmin: np.ndarray, torque: float, branch: str = "branch") -> float:
    """The angle [arcmin] of a branch at ``torque`` [N m]: linear interpolation along its nodes in
    running order; the first node at exactly that torque wins (the end the branch arrives from).
    A torque the branch does not span is an InputError naming the branch."""
    t, a = np.asarray(torque_nm, float), np.asarray(angle_arcmin, float)
    tol = 1e-12 * max(1.0, float(np.max(np.abs(t))) if t.size else 1.0)
    hit = np.nonzero(np.abs(t - torque) <= tol)[0]
    if hit.size:
        return float(a[hit[0]])
    d = t - torque
    cross = np.nonzero(d[:-1] * d[1:] < 0)[0]
    if cross.size == 0:
        span = f"{t.min():g} to {t.max():g}" if t.size else "no nodes"
        raise InputError(branch, torque, f"the branch spans {span} N m; allowed: a torque it reaches")
    i = int(cross[0])
    w = (torque - t[i]) / (t[i + 1] - t[i])
    return float(a[i] + w * (a[i + 1] - a[i]))


def lost_motion_arcmin(loop: Branches, rated_torque_nm: float, measuring_fraction: float) -> float:
    """Lost motion [arcmin]: the mean of the loading and unloading angles at +x T_R minus the same
    at -x T_R, LM = 1/2 [load+(x T_R) + unload+(x T_R)] - 1/2 [load-(-x T_R) + unload-(-x T_R)]
    (Nabtesco's definition, x = 0.03). Valid for x T_R inside every branch's torque range."""
    x = measuring_fraction * rated_torque_nm
    return 0.5 * (angle_at(*loop["load+"], x, "load+") + angle_at(*loop["unload+"], x, "unload+")) \
        - 0.5 * (angle_at(*loop["load-"], -x, "load-") + angle_at(*loop["unload-"], -x, "unload-"))


def backlash_arcmin(loop: Branches) -> float:
    """Backlash [arcmin]: the loop's width at zero torque, unload+(0) - unload-(0)."""
    return angle_at(*loop["unload+"], 0.0, "unload+") - angle_at(*loop["unload-"], 0.0, "unload-")


def rigidity_nm_per_arcmin(loop: Branches, rated_torque_nm: float, low_fraction: float, high_fraction: float) -> float:
    """Torsional rigidity [N m/arcmin]: the secant of both loading branches over [l, h] T_R,
    K = 2 (h - l) T_R / ([load+(h T_R) - load+(l T_R)] + [load-(-l T_R) - load-(-h T_R)])
    (Nabtesco's "b/a" read as a secant; docs/elastic.md). Infinite for a span <= 0 (rigid)."""
    lo, hi = low_fraction * rated_torque_nm, high_fraction * rated_torque_nm
    span = (angle_at(*loop["load+"], hi, "load+") - angle_at(*loop["load+"], lo, "load+")) \
        + (angle_at(*loop["load-"], -lo, "load-") - angle_at(*loop["load-"], -hi, "load-"))
    return 2.0 * (hi - lo) / span if span > 0 else math.inf


def hysteresis_loss_j(loop: Branches) -> float:
    """Energy lost per cycle [J]: the loop's area |closed integral of T d(theta)| (trapezoids
    along the four branches in running order, theta in rad), W = | sum 1/2 (T_i + T_i+1)
    (theta_i+1 - theta_i) |. Friction and nothing else opens the loop in the model."""
    t = np.concatenate([loop[b][0] for b in BRANCHES])
    a = np.concatenate([loop[b][1] for b in BRANCHES]) / ARCMIN_PER_RAD
    t, a = np.append(t, t[0]), np.append(a, a[0])  # closed
    return float(abs(np.sum(0.5 * (t[1:] + t[:-1]) * np.diff(a))))


def loop_figures(loop, rated_torque_nm: float, measuring_fraction: float, interval: Sequence[float],
                 secants: Sequence[tuple[float, float]] = SECANT_INTERVALS) -> dict[str, float]:
    """Every figure of a loop by the definitions above: lost motion, backlash, rigidity over
    ``interval``, the rigidity over each of ``secants`` (``rigidity_<l>_<h>``, percent of T_R),
    the hysteresis loss."""
    b = as_branches(loop)
    out = {"lost_motion_arcmin": lost_motion_arcmin(b, rated_torque_nm, measuring_fraction),
           "backlash_arcmin": backlash_arcmin(b),
           "torsional_rigidity_nm_per_arcmin": rigidity_nm_per_arcmin(b, rated_torque_nm, *interval)}
    for lo, hi in secants:
        out[secant_key(lo, hi)] = rigidity_nm_per_arcmin(b, rated_torque_nm, lo, hi)
    out["hysteresis_loss_j"] = hysteresis_loss_j(b)
    return out


def secant_key(low_fraction: float, high_fraction: float) -> str:
    return f"rigidity_{low_fraction * 100:g}_{high_fraction * 100:g}"
