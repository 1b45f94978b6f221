"""Local sensitivity and the two ways of ranking factors (Sun et al. 2014, Eq. (6)-(7)).

- S_i, Eq. (6): d(dphi)/dx_i [arcmin per um of the raw quantity]. Says how much one um of
  error costs; ignores how large the tolerance is.
- g_i, Eq. (7): |S_i| / sum |S_j|, the paper's normalised weight. Sums to 1 (the paper's
  Table 3 does not, see docs/paper-errata.md). Same blind spot as S_i.
- variance share, S_i^2 sigma_i^2 / sigma^2: the fraction of the output variance due to
  factor i. Sums to 1; for a linear model it equals the first-order Sobol index. This is
  the one that says which tolerance to tighten.
"""

from __future__ import annotations

from typing import Callable

import numpy as np


def normalised_weights(sensitivities: np.ndarray) -> np.ndarray:
    """g_i = |S_i| / sum_j |S_j| (Sun et al. 2014, Eq. (7), with magnitudes so that signs of
    S_i do not cancel). Parameters: sensitivities [arcmin/um]. Returns [-], sums to 1."""
    s = np.abs(np.asarray(sensitivities, dtype=float))
    total = s.sum()
    return s / total if total > 0 else np.zeros_like(s)


def variance_shares(sensitivities: np.ndarray, sigmas_um: np.ndarray) -> np.ndarray:
    """S_i^2 sigma_i^2 / sum_j S_j^2 sigma_j^2 for independent inputs [-], sums to 1
    (all zero when the output has no variance). Parameters: sensitivities [arcmin/um],
    sigmas_um [um]."""
    v = (np.asarray(sensitivities, float) * np.asarray(sigmas_um, float)) ** 2
    total = v.sum()
    return v / total if total > 0 else np.zeros_like(v)


def finite_difference_sensitivities(model: Callable[[np.ndarray], np.ndarray], x0_um: np.ndarray,
                                    step_um: float = 1.0) -> np.ndarray:
    """Central finite differences of any vectorised model at x0 [arcmin/um] (Eq. (6)).

    One batched call of 2k points; for the linear model the result is exact, for a
    non-linear model it is the local slope over +-step_um.
    """
    x0 = np.asarray(x0_um, dtype=float)
    k = x0.size
    pts = np.repeat(x0[None, :], 2 * k, axis=0)
    idx = np.arange(k)
    pts[idx, idx] += step_um
    pts[k + idx, idx] -= step_um
    y = model(pts)
    return (y[:k] - y[k:]) / (2.0 * step_um)


def rank_descending(values: np.ndarray, tiebreak: np.ndarray | None = None) -> np.ndarray:
    """1-based rank of each entry, largest first (ties broken by ``tiebreak``, larger first)."""
    values = np.asarray(values, float)
    keys = (values,) if tiebreak is None else (np.asarray(tiebreak, float), values)
    order = np.lexsort(tuple(-k for k in keys))
    ranks = np.empty(values.size, dtype=int)
    ranks[order] = np.arange(1, values.size + 1)
    return ranks
