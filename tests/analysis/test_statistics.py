"""Statistics of a run: the Wilson interval, order-statistic quantile intervals, capability."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import stats

from rvbacklash.analysis.statistics import (Proportion, binomial_quantile, occupied_cumulative, process_capability, quantile_with_ci,
                                           wilson_interval)
from rvbacklash.sampling import kernels
from rvbacklash.sampling.engine import HIST_BINS, Histogram


@settings(max_examples=200, deadline=None)
@given(st.integers(1, 10 ** 9), st.floats(0, 1))
def test_wilson_interval_is_scipys(n, frac):
    k = int(round(frac * n))
    ref = stats.binomtest(k, n).proportion_ci(confidence_level=0.95, method="wilson")
    lo, hi = wilson_interval(k, n)
    assert (lo, hi) == pytest.approx((ref.low, ref.high), rel=1e-9, abs=1e-12)


@settings(max_examples=300, deadline=None)
@given(st.integers(1, 10 ** 10), st.floats(0, 1), st.sampled_from([0.0, 0.005, 0.025, 0.05, 0.5, 0.95, 0.975, 0.995, 1.0])
       | st.floats(0, 1))
def test_binomial_quantile_is_scipy_stats(n, p, q):
    """The quantile intervals' ranks come from scipy.special's Boost binomial quantile, not
    scipy.stats (a second of start-up): the same numbers as scipy.stats.binom.ppf, bit for bit."""
    assert binomial_quantile(q, n, p) == stats.binom.ppf(q, n, p)


def test_wilson_by_hand():
    """Wilson (1927) for 9 of 10 at 95 %: centre (0.9 + 1.92/10)/(1.384) = 0.789, half
    1.96 sqrt(0.009 + 0.0096)/1.384 = 0.193 -> [0.596, 0.982]."""
    lo, hi = wilson_interval(9, 10)
    assert (lo, hi) == pytest.approx((0.5958, 0.9821), abs=1e-4)
    assert Proportion.sampled(9, 10).fraction == 0.9


def test_quantile_interval_from_order_statistics():
    """10^5 uniform values on a fine histogram: the median's 95 % interval is +-1.96 sqrt(p(1-p)/n)
    in probability, i.e. +-0.0031 around 0.5."""
    x = np.random.default_rng(1).random(100_000)
    counts = np.zeros((1 << 16) + 2, dtype=np.int64)
    idx = (x * (1 << 16)).astype(int) + 1
    np.add.at(counts, idx, 1)
    q = quantile_with_ci(Histogram(0.0, 1.0, counts), x.size, 0.5)
    assert q.value == pytest.approx(np.median(x), abs=2e-5)
    assert q.ci95_high - q.ci95_low == pytest.approx(2 * 1.96 * math.sqrt(0.25 / 1e5), rel=0.1)


@settings(max_examples=40, deadline=None)
@given(st.floats(-3.0, 3.0), st.floats(0.01, 2.0), st.integers(1, 3000), st.integers(0, 2 ** 32 - 1))
def test_quantiles_from_the_occupied_bins_are_the_full_cumsums(centre, spread, n, seed):
    """The engine's quantiles read a cumulative sum over the bins between the least and the
    greatest value only (occupied_cumulative): the same order statistics as the cumsum of all
    2^18 bins, values beyond the histogram's range (under/overflow, infinite) included."""
    y = centre + spread * np.random.default_rng(seed).standard_normal(n)
    y[:: 7] *= 3.0  # some beyond the range [-2, 2]
    if n > 5:
        y[3] = math.inf
    lo, hi = -2.0, 2.0
    hist = np.zeros(HIST_BINS + 2, dtype=np.int64)
    summary = kernels.accumulate(y, 0.0, math.inf, True, hist, lo, HIST_BINS / (hi - lo))
    assert summary.valid == n and summary.max == y.max() and summary.min == y.min()
    h = Histogram(lo, hi, hist)
    c = occupied_cumulative(h, float(y.min()), float(y.max()))
    assert c[1].size <= HIST_BINS + 2 and c[1][-1] == n
    for p in (0.0, 0.01, 0.5, 0.9, 0.99999, 1.0):
        assert quantile_with_ci(h, n, p, cumulative=c) == quantile_with_ci(h, n, p)


def test_process_capability_by_hand():
    # mean 1, sigma 0.5, USL 3, LSL 0: Cp = 3/3 = 1, Cpk = min(2, 1)/1.5 = 0.667
    assert process_capability(1.0, 0.5, 3.0) == pytest.approx((1.0, 2 / 3))
    assert process_capability(1.0, 0.0, 3.0) == (None, None)
