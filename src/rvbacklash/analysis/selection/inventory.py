"""Finite inventories: which class of pins and of rollers goes into which unit of a batch
(docs/selective-assembly.md, "A batch").

A unit is scored on every pair (pin class p, roller class r) by the rules' distances (``rules``): the
predicted play of the cycloid stage from the pin window, plus the predicted play and crank bearings'
share from the target; a pair at distance 0 puts the unit *in window*. The batch has S_p sets of
pins in class p and R_r sets of rollers in class r (a set: what one unit takes). The assignment
maximises, in this order, the units in window, the units built (= the fewest parts left over), and
the closeness sum -sum d: a 0/1 programme

    max sum_{u,p,r} x_upr [(U+1)^2 ok_upr + (U+1) - d_upr / (d_max + 1)]
    s.t. sum_{p,r} x_upr <= 1 (u),  sum_{u,r} x_upr <= S_p (p),  sum_{u,p} x_upr <= R_r (r),

whose weights make the order strict (U units). With one part kind it is a transportation problem
(``scipy.optimize.linear_sum_assignment`` on units x class slots would do); with two kinds each
unit takes one pin class *and* one roller class from two stocks, a three-index assignment that no
bipartite matching holds, so it goes to ``scipy.optimize.milp`` (HiGHS, exact branch and bound;
small: units x classes x classes binaries). The greedy rule beside it takes the units in serial
order, each the best pair still in stock.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rvbacklash.errors import InputError
from rvbacklash.results import Result


@dataclass(frozen=True, repr=False)
class Assignment(Result):
    """Classes given to the units of a batch (-1: not built), with what it achieves."""

    method: str  # "milp" | "greedy"
    pin_class: tuple[int, ...]
    roller_class: tuple[int, ...]
    in_window: tuple[bool, ...]
    units_in_window: int
    units_built: int
    distance_arcmin: float  # sum of the built units' distances to their windows
    pin_sets_left: tuple[int, ...]
    roller_sets_left: tuple[int, ...]

    def rows(self) -> list[dict]:
        return [{"unit": u, "pin_class": p, "roller_class": r, "in_window": ok}
                for u, (p, r, ok) in enumerate(zip(self.pin_class, self.roller_class, self.in_window))]

    @property
    def objective(self) -> tuple[int, int, float]:
        """What the assignment maximises, in order: units in window, units built, -distance."""
        return self.units_in_window, self.units_built, -self.distance_arcmin


def pair_distances(play_arcmin: np.ndarray, roller_mean_um: np.ndarray, crank_sens_arcmin_per_um: float,
                   play_window_arcmin: tuple[float, float], target_arcmin: float) -> np.ndarray:
    """(units, pin classes, roller classes): each pair's distance to the unit's windows [arcmin]
    (``rules.window_distance`` of the pin rule plus that of the roller rule); ``play_arcmin`` (units,
    pin classes): the predicted play with each pin class; ``roller_mean_um``: each roller class's mean
    clearance (roller classes,) or each unit's with each roller class (units, roller classes)."""
    p = np.asarray(play_arcmin, float)[:, :, None]
    lo, hi = play_window_arcmin
    d_pin = np.maximum(p - hi, 0.0) + np.maximum(lo - p, 0.0)
    m = np.asarray(roller_mean_um, float)
    m = m[None, None, :] if m.ndim == 1 else m[:, None, :]  # one per class, or per unit and class
    crank = np.maximum(p, 0.0) + crank_sens_arcmin_per_um * m
    return d_pin + np.maximum(crank - target_arcmin, 0.0)


def _check(distance: np.ndarray, pin_sets, roller_sets) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    d = np.asarray(distance, float)
    s, r = np.asarray(pin_sets), np.asarray(roller_sets)
    if d.ndim != 3 or d.shape[1] != s.size or d.shape[2] != r.size:
        raise InputError("distance", d.shape, "allowed: (units, pin classes, roller classes) matching the stocks")
    if np.any(s < 0) or np.any(r < 0) or not np.all(np.isfinite(d)):
        raise InputError("stock", (s.tolist(), r.tolist()), "allowed: sets >= 0 per class and finite distances")
    return d, s.astype(np.int64), r.astype(np.int64)


def _result(method: str, d: np.ndarray, pins: np.ndarray, rollers: np.ndarray, s: np.ndarray, r: np.ndarray,
            tol: float) -> Assignment:
    built = pins >= 0
    dist = np.array([d[u, pins[u], rollers[u]] if built[u] else math.inf for u in range(d.shape[0])])
    ok = built & (dist <= tol)
    left_p = s - np.bincount(pins[built], minlength=s.size)
    left_r = r - np.bincount(rollers[built], minlength=r.size)
    return Assignment(method, tuple(int(x) for x in pins), tuple(int(x) for x in rollers), tuple(bool(x) for x in ok),
                      int(ok.sum()), int(built.sum()), float(dist[built].sum()), tuple(int(x) for x in left_p),
                      tuple(int(x) for x in left_r))


def assign_optimal(distance: np.ndarray, pin_sets, roller_sets, tol: float = 1e-12) -> Assignment:
    """The assignment of the module docstring by ``scipy.optimize.milp``."""
    from scipy.optimize import Bounds, LinearConstraint, milp
    from scipy.sparse import coo_matrix

    d, s, r = _check(distance, pin_sets, roller_sets)
    n_u, n_p, n_r = d.shape
    ok = d <= tol
    value = (n_u + 1) ** 2 * ok + (n_u + 1) - d / (d.max(initial=0.0) + 1.0)
    idx = np.arange(d.size).reshape(d.shape)
    u_of, p_of, r_of = np.unravel_index(np.arange(d.size), d.shape)
    rows = np.concatenate([u_of, n_u + p_of, n_u + n_p + r_of])
    cols = np.concatenate([idx.ravel()] * 3)
    a = coo_matrix((np.ones(rows.size), (rows, cols)), shape=(n_u + n_p + n_r, d.size)).tocsr()
    ub = np.concatenate([np.ones(n_u), s, r]).astype(float)
    res = milp(-value.ravel(), constraints=LinearConstraint(a, -np.inf, ub), integrality=np.ones(d.size),
               bounds=Bounds(0, 1))
    if res.x is None:  # pragma: no cover - the empty assignment is always feasible
        raise RuntimeError(f"milp found no assignment: {res.message}")
    x = np.round(res.x).reshape(d.shape).astype(bool)
    pins, rollers = np.full(n_u, -1), np.full(n_u, -1)
    for u, p, q in zip(*np.nonzero(x)):
        pins[u], rollers[u] = p, q
    return _result("milp", d, pins, rollers, s, r, tol)


def assign_greedy(distance: np.ndarray, pin_sets, roller_sets, tol: float = 1e-12) -> Assignment:
    """Units in serial order, each the pair nearest its windows still in stock (ties: the middle
    classes, the most abundant; the rules' tie-break)."""
    d, s, r = _check(distance, pin_sets, roller_sets)
    n_u, n_p, n_r = d.shape
    left_p, left_r = s.copy(), r.copy()
    pins, rollers = np.full(n_u, -1), np.full(n_u, -1)
    mid = np.abs(2 * np.arange(n_p)[:, None] - (n_p - 1)) + np.abs(2 * np.arange(n_r)[None, :] - (n_r - 1))
    for u in range(n_u):
        avail = (left_p[:, None] > 0) & (left_r[None, :] > 0)
        if not avail.any():
            continue
        cost = np.where(avail, d[u], np.inf)
        best = cost.min()
        choice = np.where(cost <= best + 1e-12, mid, np.iinfo(np.int64).max)
        p, q = np.unravel_index(int(np.argmin(choice)), choice.shape)
        pins[u], rollers[u] = p, q
        left_p[p] -= 1
        left_r[q] -= 1
    return _result("greedy", d, pins, rollers, s, r, tol)
