"""Finite inventories (issue 39 item 2): the optimal assignment of classes to a batch equals a brute
force over every assignment; the greedy rule never beats it and sometimes loses units."""

import itertools

import numpy as np
import pytest

from rvbacklash.analysis.selection.inventory import assign_greedy, assign_optimal, pair_distances
from rvbacklash.errors import InputError


def _brute_force(d, pin_sets, roller_sets, tol=1e-12):
    n_u, n_p, n_r = d.shape
    options = [None] + [(p, r) for p in range(n_p) for r in range(n_r)]
    best = None
    for choice in itertools.product(options, repeat=n_u):
        used_p, used_r = np.zeros(n_p, int), np.zeros(n_r, int)
        ok = built = 0
        dist = 0.0
        for u, c in enumerate(choice):
            if c is None:
                continue
            used_p[c[0]] += 1
            used_r[c[1]] += 1
            built += 1
            ok += d[u, c[0], c[1]] <= tol
            dist += d[u, c[0], c[1]]
        if np.any(used_p > pin_sets) or np.any(used_r > roller_sets):
            continue
        key = (ok, built, -dist)
        if best is None or key[:2] > best[:2] or (key[:2] == best[:2] and key[2] > best[2] + 1e-12):
            best = key
    return best


def _instance(rng, n_u, n_p, n_r):
    d = rng.uniform(0.0, 0.3, (n_u, n_p, n_r))
    d[rng.random(d.shape) < 0.35] = 0.0  # pairs in window
    return d, rng.integers(0, 3, n_p), rng.integers(1, 4, n_r)


@pytest.mark.parametrize("n_r", [1, 2])
def test_optimal_assignment_equals_brute_force_on_six_units_three_classes(n_r):
    rng = np.random.default_rng(39)
    greedy_lost = 0
    for _ in range(12 if n_r == 1 else 4):
        d, s, r = _instance(rng, 6, 3, n_r)
        best = _brute_force(d, s, r)
        opt = assign_optimal(d, s, r)
        assert opt.objective[:2] == best[:2] and opt.objective[2] == pytest.approx(best[2], abs=1e-9)
        assert all(x >= 0 for x in opt.pin_sets_left + opt.roller_sets_left)
        g = assign_greedy(d, s, r)
        assert g.objective[:2] <= opt.objective[:2]
        greedy_lost += g.objective[:2] < opt.objective[:2]
    if n_r == 1:
        assert greedy_lost > 0  # the greedy rule loses units the optimum keeps


def test_greedy_takes_the_scarce_class_first_the_optimum_does_not():
    # unit 0 is in window with class 0 or 1, unit 1 with class 0 only; one set of each
    d = np.array([[[0.0], [0.0]], [[0.0], [0.2]]])
    g, o = assign_greedy(d, [1, 1], [2]), assign_optimal(d, [1, 1], [2])
    assert g.units_in_window == 1 and o.units_in_window == 2 and o.pin_class == (1, 0)


def test_pair_distances_closed_form():
    d = pair_distances(np.array([[0.3, -0.1]]), np.array([6.0, 2.0]), 0.1, (-np.inf, 0.0), 0.45)
    # class 0 leaves a play of 0.3 (0.3 from the window), then 0.3 + 0.6 - 0.45 or 0.3 + 0.2 - 0.45
    assert d[0, 0] == pytest.approx([0.3 + 0.45, 0.3 + 0.05])
    assert d[0, 1] == pytest.approx([0.15, 0.0])
    with pytest.raises(InputError):
        assign_optimal(np.zeros((2, 2, 1)), [1], [1])
