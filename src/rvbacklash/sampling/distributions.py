"""Statistical reading of a tolerance zone: each factor's raw quantity as a scipy.stats
distribution (or a fixed value).

Default (Sun et al. 2014, Eq. (4)-(5)): normal, mean = zone centre, sigma = zone width / 6.
The other readings and how a zone maps to their parameters are in docs/distributions.md.
"""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np
from scipy import stats

from rvbacklash.design.derived import ResolvedZone

# 99.73 % of a normal lies within +-3 sigma; the zone covers the same share of every reading.
ZONE_COVERAGE = 0.9973002039367398  # = erf(3 / sqrt(2))


def zone_mean_um(lower_um: float, upper_um: float) -> float:
    """Mean of a zone read as normal, mu = (upper + lower) / 2.

    Source: Sun et al. 2014, Eq. (4) (before the 1/cos(alpha) transfer).
    Parameters: lower_um, upper_um [um]. Returns [um].
    """
    return 0.5 * (lower_um + upper_um)


def zone_sigma_um(lower_um: float, upper_um: float, sigmas_in_half_zone: float = 3.0) -> float:
    """Standard deviation of a zone read as normal, sigma = (upper - lower) / 6.

    The half-zone is ``sigmas_in_half_zone`` (3) standard deviations: 99.73 % of parts
    inside the zone. Source: Sun et al. 2014, Eq. (5) (read with the difference of the
    limits; the paper prints a sum, see docs/paper-errata.md).
    Parameters: lower_um <= upper_um [um]. Returns [um] >= 0.
    """
    return (upper_um - lower_um) / (2.0 * sigmas_in_half_zone)


def rayleigh_scale_um(magnitude_limit_um: float, coverage: float = ZONE_COVERAGE) -> float:
    """Rayleigh scale s with P(R <= limit) = coverage: s = limit / sqrt(-2 ln(1 - coverage)).

    With the default coverage 0.9973 (the normal's +-3 sigma), s = limit / 3.4393.
    Source: Rayleigh cdf F(r) = 1 - exp(-r^2 / (2 s^2)).
    Parameters: magnitude_limit_um [um] > 0. Returns s [um].
    """
    return magnitude_limit_um / math.sqrt(-2.0 * math.log1p(-coverage))


def marginal(z: ResolvedZone):
    """The scipy.stats frozen distribution of a factor's raw quantity [um], None if fixed.

    ``rayleigh`` on a phase-weighted quantity (run-out, eccentricity: x = R cos(theta)) is a
    Rayleigh magnitude R with a uniform phase; then x is exactly normal with sigma = the
    Rayleigh scale (the two components of an isotropic 2-D normal), and that is what is
    returned. On a magnitude quantity, x = lower + R.
    """
    lo, hi = z.lower_um, z.upper_um
    d = z.distribution
    if d == "fixed":
        return None
    if d == "uniform":
        return stats.uniform(loc=lo, scale=hi - lo)
    if d == "rayleigh":
        if z.kind == "phase":
            scale = z.scale_um if z.scale_um is not None else rayleigh_scale_um(max(abs(lo), abs(hi)))
            return stats.norm(loc=0.0, scale=scale)
        scale = z.scale_um if z.scale_um is not None else rayleigh_scale_um(hi - lo)
        return stats.rayleigh(loc=lo, scale=scale)
    mean = z.mean_um if z.mean_um is not None else zone_mean_um(lo, hi)
    sigma = z.sigma_um if z.sigma_um is not None else zone_sigma_um(lo, hi)
    if d == "normal":
        return stats.norm(loc=mean, scale=sigma) if sigma > 0 else None
    if d == "truncated_normal":
        return stats.truncnorm((lo - mean) / sigma, (hi - mean) / sigma, loc=mean, scale=sigma)
    raise ValueError(f"unknown distribution {d!r}")


def fixed_value_um(z: ResolvedZone) -> float:
    """The value of a factor without variance (fixed, or a zero-width normal zone)."""
    if z.value_um is not None:
        return z.value_um
    if z.mean_um is not None:
        return z.mean_um
    return zone_mean_um(z.lower_um, z.upper_um)


def is_normal(dist) -> bool:
    return dist is not None and dist.dist.name == "norm"


def input_moments(zones: Sequence[ResolvedZone]) -> tuple[np.ndarray, np.ndarray]:
    """(mean, sigma) arrays [um] of the raw quantities, in catalog order."""
    means, sigmas = [], []
    for z in zones:
        d = marginal(z)
        if d is None:
            means.append(fixed_value_um(z))
            sigmas.append(0.0)
        else:
            means.append(float(d.mean()))
            sigmas.append(float(d.std()))
    return np.array(means), np.array(sigmas)


def correlation_matrix(correlation, keys: Sequence[str]) -> np.ndarray:
    """Full (k, k) correlation matrix in catalog order from a design's ``correlation`` table
    (identity where nothing is given). Parameters: correlation (schema.Correlation or None),
    keys: the catalog keys."""
    r = np.eye(len(keys))
    if correlation is not None:
        idx = [list(keys).index(k) for k in correlation.factors]
        r[np.ix_(idx, idx)] = np.array(correlation.matrix, dtype=float)
    return r
