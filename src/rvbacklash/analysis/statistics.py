"""Statistics of a Monte-Carlo run with their uncertainty.

- quantiles from the fixed-bin histogram (linear inside a bin; the bin width is ~1e-4
  standard deviations), with a distribution-free 95 % interval from order statistics: the
  ranks l, u with Binomial(N, p) probabilities 2.5 % / 97.5 % bracket the p-quantile
  (Hahn & Meeker, Statistical Intervals, 1991, ch. 5);
- yield P(backlash <= spec) with the Wilson score interval (scipy.stats.binomtest);
- Cp, Cpk against the spec as upper limit and 0 arcmin as lower limit (lost motion cannot be
  negative; below 0 the parts interfere).
"""

from __future__ import annotations

import math

import numpy as np
from scipy import stats

from rvbacklash.sampling.engine import Histogram, Moments

DEFAULT_QUANTILES = (0.00135, 0.5, 0.99865)
Z95 = 1.959963984540054


def order_statistic(hist: Histogram, k: int) -> float | None:
    """Value of the k-th smallest sample (1-based), spread evenly inside its bin; None when
    it fell outside the histogram range."""
    c = np.cumsum(hist.counts)
    j = int(np.searchsorted(c, k))  # first index with cumulative count >= k
    if j == 0 or j == hist.counts.size - 1:
        return None
    width = (hist.hi - hist.lo) / (hist.counts.size - 2)
    before = c[j - 1]
    frac = (k - before - 0.5) / hist.counts[j]
    return float(hist.lo + (j - 1 + frac) * width)


def quantile_with_ci(hist: Histogram, n: int, p: float, confidence: float = 0.95) -> dict:
    """{"value", "ci95"} of the p-quantile of n samples summarised in ``hist``."""
    k = min(max(math.ceil(p * n), 1), n)
    alpha = 1.0 - confidence
    lo_rank = int(stats.binom.ppf(alpha / 2, n, p))
    hi_rank = int(stats.binom.ppf(1 - alpha / 2, n, p)) + 1
    lo_rank, hi_rank = min(max(lo_rank, 1), n), min(max(hi_rank, 1), n)
    return {"value": order_statistic(hist, k),
            "ci95": [order_statistic(hist, lo_rank), order_statistic(hist, hi_rank)]}


def wilson_interval(successes: int, n: int, confidence: float = 0.95) -> list[float]:
    """Wilson score interval of a binomial proportion (scipy.stats.binomtest)."""
    ci = stats.binomtest(int(successes), int(n)).proportion_ci(confidence_level=confidence, method="wilson")
    return [float(ci.low), float(ci.high)]


def process_capability(mean: float, std: float, upper: float, lower: float = 0.0) -> tuple[float | None, float | None]:
    """Cp = (USL - LSL) / (6 sigma), Cpk = min(USL - mu, mu - LSL) / (3 sigma).
    Parameters in [arcmin]; None when sigma = 0."""
    if std <= 0:
        return None, None
    return (upper - lower) / (6.0 * std), min(upper - mean, mean - lower) / (3.0 * std)


def summary(m: Moments, hist: Histogram, spec: float, quantiles=DEFAULT_QUANTILES) -> dict:
    """Every statistic of a (possibly partial) run as plain numbers."""
    n = m.n
    std = math.sqrt(m.m2 / (n - 1)) if n > 1 else 0.0
    half = Z95 * std / math.sqrt(n) if n > 0 else math.nan
    cp, cpk = process_capability(m.mean, std, spec)
    frac = m.n_le_spec / n
    return {
        "samples_done": n,
        "mean_arcmin": m.mean,
        "mean_ci95": [m.mean - half, m.mean + half],
        "std_arcmin": std,
        "min_arcmin": m.min,
        "max_arcmin": m.max,
        "quantiles": {f"{p:g}": quantile_with_ci(hist, n, p) for p in quantiles},
        "spec_arcmin": spec,
        "yield": {"fraction": frac, "ci95": wilson_interval(m.n_le_spec, n), "count": m.n_le_spec},
        "ppm_out": (1.0 - frac) * 1e6,
        "cp": cp,
        "cpk": cpk,
        "interference_fraction": m.n_negative / n,
    }


def coarse_histogram(hist: Histogram, n: int, bins: int = 200, lo: float | None = None,
                     hi: float | None = None) -> dict:
    """Re-binned histogram for plots and JSON: edges [arcmin], counts, density [1/arcmin].
    Default range: the observed span of the samples; under/overflow reported separately."""
    fine_edges = hist.edges
    inner = hist.counts[1:-1]
    nz = np.nonzero(inner)[0]
    if lo is None or hi is None:
        lo = fine_edges[nz[0]] if nz.size else hist.lo
        hi = fine_edges[nz[-1] + 1] if nz.size else hist.hi
    edges = np.linspace(lo, hi, bins + 1)
    centres = 0.5 * (fine_edges[:-1] + fine_edges[1:])
    counts, _ = np.histogram(centres, bins=edges, weights=inner)
    width = edges[1] - edges[0]
    return {"edges": edges.tolist(), "counts": counts.astype(np.int64).tolist(),
            "density": (counts / (n * width)).tolist() if n else None,
            "underflow": int(hist.counts[0]), "overflow": int(hist.counts[-1])}
