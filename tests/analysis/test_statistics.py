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


# --- extreme quantiles of small runs (issue 36 item 3) --------------------------------------------

REPLICATIONS = 2000


def rank_histogram(n: int) -> Histogram:
    """A histogram of n samples, one per bin of width 1 from 0: its k-th order statistic reads
    k - 1/2 (spread inside its bin), so a quantile's interval reads the ranks the statistics chose."""
    counts = np.zeros(n + 2, dtype=np.int64)
    counts[1:n + 1] = 1
    return Histogram(0.0, float(n), counts)


def stated_ranks(n: int, p: float) -> tuple[int | None, int | None]:
    q = quantile_with_ci(rank_histogram(n), n, p)
    return tuple(None if v is None else int(round(v + 0.5)) for v in (q.ci95_low, q.ci95_high))


@pytest.mark.parametrize("n", [200, 1000, 2000, 5000])
@pytest.mark.parametrize("p", [0.00135, 0.5, 0.99865])
def test_quantile_intervals_cover_the_true_quantile(n, p):
    """The 95 % interval of a quantile covers the true one in >= 93 % of 2000 samples of a known
    distribution (standard normal; fixed seed), at every n — also where n p or n (1 - p) is too
    small for the order statistics to bound it: there the open end is stated (None), where it used to
    be the sample's max or min (coverage of the 99.865 % quantile then: 0.23 at n = 200, 0.73 at
    1000, 0.91 at 2000). The observed coverage agrees with the exact one, P(l <= B <= u - 1) for B ~
    Binomial(n, p), within 5 binomial standard deviations; the exact one is >= 95 % by construction.
    Margin: at a true coverage of 0.95, 2000 replications fall below 0.93 with probability ~2e-5."""
    lo, hi = stated_ranks(n, p)
    x = np.random.default_rng([36, n, int(p * 1e5)]).standard_normal((REPLICATIONS, n))
    kth = [r - 1 for r in (lo, hi) if r is not None]
    part = np.partition(x, kth, axis=1)
    xi = stats.norm.ppf(p)
    covered = np.ones(REPLICATIONS, dtype=bool)
    if lo is not None:
        covered &= part[:, lo - 1] <= xi
    if hi is not None:
        covered &= xi <= part[:, hi - 1]
    observed = covered.mean()
    binom = stats.binom(n, p)
    exact = binom.cdf((n + 1 if hi is None else hi) - 1) - binom.cdf((0 if lo is None else lo) - 1)
    assert observed >= 0.93, (n, p, lo, hi, observed)
    assert exact >= 0.95
    assert abs(observed - exact) <= 5 * math.sqrt(exact * (1 - exact) / REPLICATIONS) + 1e-12
    q = quantile_with_ci(rank_histogram(n), n, p)
    if p == 0.5 or n >= 2731:
        assert q.bounded and q.needs_samples is None and q.note() == ""
    else:  # the far end lies beyond the sample: said, with the run size that would bound it
        assert not q.bounded and q.needs_samples == 2731
        assert (q.ci95_high is None) == (p > 0.5) and (q.ci95_low is None) == (p < 0.5)
        assert "beyond the sample" in q.interval_text() and "needs >= 2,731 units" in q.interval_text()


def test_samples_to_bound_is_where_both_ranks_enter_the_sample():
    from rvbacklash.analysis.statistics import quantile_ranks, samples_to_bound

    for p in (0.00135, 0.01, 0.05, 0.5, 0.9, 0.99865, 0.99999):
        n = samples_to_bound(p)
        assert None not in quantile_ranks(n, p) and None in quantile_ranks(n - 1, p)
    assert samples_to_bound(0.99865) == samples_to_bound(0.00135) == 2731  # ln(0.025) / ln(0.99865) = 2730.6
    assert samples_to_bound(0.5) == 6


def test_a_small_run_says_its_extreme_quantiles_reach_beyond_it():
    """End to end: a 200-sample run's 99.865 % quantile has an open upper end in the JSON (null,
    ``bounded`` false, ``needs_samples``), the table and the CSV; its median is bounded."""
    import json

    from helpers import run_cli

    p = run_cli("simulate", "sun2014", "-n", "200", "--format", "json")
    assert p.returncode == 0, p.stderr
    table = {q["probability"]: q for q in json.loads(p.stdout)["outputs"]["backlash"]["quantiles"]["table"]}
    top, mid, low = table[0.99865], table[0.5], table[0.00135]
    assert top["ci95_high"] is None and top["bounded"] is False and top["needs_samples"] == 2731
    assert top["ci95_low"] is not None and top["ci95_low"] <= top["value"]
    assert low["ci95_low"] is None and low["bounded"] is False
    assert mid["bounded"] is True and mid["needs_samples"] is None and mid["ci95_low"] < mid["ci95_high"]
    text = " ".join(run_cli("simulate", "sun2014", "-n", "200").stdout.split())
    assert "beyond the sample] (needs >= 2,731 units)" in text
    csv_text = run_cli("simulate", "sun2014", "-n", "200", "--format", "csv").stdout
    assert "95 % interval beyond the sample above: needs >= 2,731 units" in csv_text
