"""Statistics of a Monte-Carlo run with their uncertainty, as typed results.

- quantiles from the fixed-bin histogram (linear inside a bin; the bin width is ~1e-4
  standard deviations), with a distribution-free 95 % interval from order statistics: the
  ranks l, u with Binomial(N, p) probabilities 2.5 % / 97.5 % bracket the p-quantile
  (Hahn & Meeker, Statistical Intervals, 1991, ch. 5). Where a rank falls outside 1..N (N p or
  N (1 - p) too small: an extreme quantile of a small run) no order statistic of the sample
  bounds that side at 95 %: the end is left open ("beyond the sample", None) and the quantile
  says from how many units on both ends are bounded (``samples_to_bound``), instead of the
  sample's min or max posing as a bound (it covered the 99.865 % quantile ~23 % of the time at
  N = 200);
- yield P(value meets the spec) with the Wilson score interval (Wilson 1927; Brown, Cai &
  DasGupta, Stat. Sci. 16 (2001) 101);
- Cp, Cpk against the spec as upper limit and 0 as lower limit (lost motion cannot be
  negative; below 0 the parts interfere).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from statistics import NormalDist

import numpy as np

from rvbacklash.results import Result
from rvbacklash.sampling.engine import Histogram, Moments, RawOutput, histogram_bin

DEFAULT_QUANTILES = (0.00135, 0.5, 0.99865)
Z95 = 1.959963984540054


# --- typed pieces --------------------------------------------------------------------------

BEYOND = "beyond the sample"


@dataclass(frozen=True, repr=False)
class Quantile(Result):
    """The p-quantile of an output [its unit] and its 95 % interval (None outside the histogram).
    ``bounded`` False: the sample is too small for an order statistic to bound one side (or
    both) at 95 %; that end is None (beyond the sample: the interval is open there) and
    ``needs_samples`` is the run size from which both ends are bounded (None when bounded)."""

    probability: float
    value: float | None
    ci95_low: float | None
    ci95_high: float | None
    bounded: bool = True
    needs_samples: int | None = None

    @property
    def open_low(self) -> bool:
        return not self.bounded and self.ci95_low is None

    @property
    def open_high(self) -> bool:
        return not self.bounded and self.ci95_high is None

    def note(self) -> str:
        """Why an end of the interval is open ('' when bounded)."""
        if self.bounded:
            return ""
        side = "both sides" if self.open_low and self.open_high else ("below" if self.open_low else "above")
        needs = f": needs >= {self.needs_samples:,} units" if self.needs_samples else ""
        return f"95 % interval {BEYOND} {side}{needs}"

    def interval_text(self, fmt: str = ".4f", sep: str = ", ", brackets: str = "[]") -> str:
        """The interval as text: '[1.2345, 1.4567]', or '[1.2345, beyond the sample] (needs >= 2,731
        units)' where the sample cannot bound a side; '-' without a value."""
        if self.value is None and self.ci95_low is None and self.ci95_high is None:
            return "-"
        lo = BEYOND if self.open_low else _text(self.ci95_low, fmt)
        hi = BEYOND if self.open_high else _text(self.ci95_high, fmt)
        text = f"{brackets[:1]}{lo}{sep}{hi}{brackets[1:]}"  # brackets "": none
        if not self.bounded and self.needs_samples:
            text += f" (needs >= {self.needs_samples:,} units)"
        return text

    def summary(self) -> list[str]:
        return [f"q({self.probability:g}) = {_num(self.value)} {self.interval_text('.4g')}"]


@dataclass(frozen=True, repr=False)
class Quantiles(Result):
    """A small table of quantiles of one output; ``at(p)`` looks one up."""

    unit: str
    table: tuple[Quantile, ...]

    def at(self, probability: float) -> Quantile:
        for q in self.table:
            if math.isclose(q.probability, probability, rel_tol=1e-12, abs_tol=1e-15):
                return q
        raise KeyError(f"no quantile {probability!r}; computed: {', '.join(f'{q.probability:g}' for q in self.table)}")

    def __iter__(self):
        return iter(self.table)

    def __len__(self) -> int:
        return len(self.table)

    def to_dict(self) -> dict:
        return {"unit": self.unit, "table": [q.to_dict() for q in self.table]}

    def rows(self) -> list[dict]:
        return [{**q.to_dict(), "unit": self.unit} for q in self.table]

    def summary(self) -> list[str]:
        return [line for q in self.table for line in q.summary()]


@dataclass(frozen=True, repr=False)
class Proportion(Result):
    """A fraction with its 95 % (Wilson) interval; ``count`` of ``total`` when sampled."""

    fraction: float
    ci95_low: float
    ci95_high: float
    count: int | None = None
    total: int | None = None

    @classmethod
    def exact(cls, fraction: float) -> "Proportion":
        return cls(fraction, fraction, fraction)

    @classmethod
    def sampled(cls, count: int, total: int) -> "Proportion":
        lo, hi = wilson_interval(count, total)
        return cls(count / total if total else math.nan, lo, hi, int(count), int(total))

    def summary(self) -> list[str]:
        return [f"{self.fraction:.6%} [{self.ci95_low:.6%}, {self.ci95_high:.6%}]"]


@dataclass(frozen=True, repr=False)
class HistogramData(Result):
    """Histogram of an output for plots and files: bin edges [unit], counts (None for an exact
    distribution), density [1/unit], values below / above the range."""

    unit: str
    edges: tuple[float, ...]
    counts: tuple[int, ...] | None
    density: tuple[float, ...]
    underflow: int | None
    overflow: int | None

    def rows(self) -> list[dict]:
        counts = self.counts or (None,) * len(self.density)
        return [{"low": lo, "high": hi, "count": c, "density": d, "unit": self.unit}
                for lo, hi, c, d in zip(self.edges[:-1], self.edges[1:], counts, self.density)]

    def summary(self) -> list[str]:
        return [f"{len(self.density)} bins over [{self.edges[0]:.4g}, {self.edges[-1]:.4g}] {self.unit}"]


@dataclass(frozen=True, repr=False)
class OutputStatistics(Result):
    """Every statistic of one output quantity of a run (values in ``unit``)."""

    quantity: str  # backlash | backlash_free | preload | lost_motion | rigidity ...
    unit: str
    description: str
    samples: int | None  # values counted (a conditional output counts fewer than the run); None: exact
    mean: float
    mean_ci95_low: float
    mean_ci95_high: float
    sigma: float
    min: float | None
    max: float | None
    quantiles: Quantiles
    spec_limit: float | None
    spec_is_upper: bool
    yield_: Proportion | None = field(metadata={"key": "yield"})
    ppm_out: float | None
    cp: float | None
    cpk: float | None
    negative_fraction: float | None  # share of values below 0
    histogram: HistogramData | None  # None: left out (output_statistics(coarse=False))
    warning: str | None = None  # what the figures (and the yield) need said beside them, e.g. a lost
    #                             motion read in friction's stick band (docs/elastic.md); None: nothing

    def rows(self) -> list[dict]:
        def row(name, value, lo=None, hi=None, unit=self.unit, note=""):
            return {"output": self.quantity, "statistic": name, "value": value, "ci95_low": lo, "ci95_high": hi,
                    "unit": unit, "note": note}

        out = [row("samples", self.samples, unit=""), row("mean", self.mean, self.mean_ci95_low, self.mean_ci95_high),
               row("sigma", self.sigma), row("min", self.min), row("max", self.max)]
        out += [row(f"quantile {q.probability:g}", q.value, q.ci95_low, q.ci95_high, note=q.note())
                for q in self.quantiles]
        if self.yield_ is not None:
            side = "<=" if self.spec_is_upper else ">="
            out.append(row(f"yield ({side} {self.spec_limit:g})", self.yield_.fraction, self.yield_.ci95_low,
                           self.yield_.ci95_high, unit="", note=f"warning: {self.warning}" if self.warning else ""))
            out += [row("ppm out of spec", self.ppm_out, unit=""), row("Cp", self.cp, unit=""),
                    row("Cpk", self.cpk, unit="")]
        return out

    def summary(self) -> list[str]:
        top = self.quantiles.table[-1]
        line = (f"{self.quantity} [{self.unit}]: mean {_num(self.mean)}, sigma {_num(self.sigma)}, "
                f"q{top.probability:g} {_num(top.value)}")
        if self.yield_ is not None:
            line += f", yield {self.yield_.fraction:.4%}"
        if self.warning:
            line += " [see warning]"
        return [line]


def _num(x) -> str:
    return "-" if x is None else f"{x:.4g}"


def _text(x, fmt: str) -> str:
    return "-" if x is None else format(x, fmt)


# --- formulas ------------------------------------------------------------------------------

def occupied_cumulative(hist: Histogram, lowest: float, highest: float) -> tuple[int, np.ndarray]:
    """(first bin, cumulative counts from it) of an engine histogram over the bins between its
    lowest and its highest value, one bin of margin each side; every other bin is empty. What
    order_statistic reads, at a fraction of the cost: a cumsum of all 2^18 bins takes ~0.5 ms, and
    a run reads quantiles at every convergence point."""
    scale = (hist.counts.size - 2) / (hist.hi - hist.lo)  # the engine's HIST_BINS / (hi - lo)
    first = max(histogram_bin(lowest, hist.lo, scale) - 1, 0)
    last = min(histogram_bin(highest, hist.lo, scale) + 1, hist.counts.size - 1)
    return first, np.cumsum(hist.counts[first:last + 1])


def order_statistic(hist: Histogram, k: int, cumulative: tuple[int, np.ndarray] | None = None) -> float | None:
    """Value of the k-th smallest sample (1-based), spread evenly inside its bin; None when
    it fell outside the histogram range. ``cumulative``: (first bin, cumulative counts from it)
    covering every non-empty bin (occupied_cumulative), if at hand; else every bin's."""
    start, c = (0, np.cumsum(hist.counts)) if cumulative is None else cumulative
    i = int(np.searchsorted(c, k))  # first index with cumulative count >= k
    j = start + i  # its bin
    if j == 0 or j == hist.counts.size - 1:
        return None
    width = (hist.hi - hist.lo) / (hist.counts.size - 2)
    before = c[i - 1] if i > 0 else 0  # no sample before the first bin of c
    frac = (k - before - 0.5) / hist.counts[j]
    return float(hist.lo + (j - 1 + frac) * width)


def binomial_quantile(q: float, n: int, p: float) -> float:
    """The q-quantile of the binomial distribution B(n, p): the smallest k with P(X <= k) >= q.
    ``scipy.stats.binom.ppf(q, n, p)``, the same function: for 0 < q < 1 scipy.stats.binom calls
    Boost's binomial quantile through ``scipy.special`` (``_binom_ppf``), called here directly
    because importing scipy.stats costs a second of every command's start-up (scipy.special a
    third of it). Elsewhere (q at 0 or 1, or a scipy without that function): scipy.stats itself.
    tests/analysis checks the two agree."""
    if 0.0 < q < 1.0 and 0.0 <= p <= 1.0 and n >= 1:
        try:
            from scipy.special._ufuncs import _binom_ppf
        except ImportError:  # pragma: no cover - a scipy that keeps it elsewhere
            pass
        else:
            return float(_binom_ppf(q, n, p))
    from scipy import stats

    return float(stats.binom.ppf(q, n, p))


def quantile_ranks(n: int, p: float, confidence: float = 0.95) -> tuple[int, int | None, int | None]:
    """(k, l, u): the rank of the p-quantile's estimate among n samples, k = ceil(n p) in 1..n, and
    the ranks of its distribution-free interval [X_(l), X_(u)]: l = F^-1(alpha/2), u = F^-1(1 -
    alpha/2) + 1, F the Binomial(n, p) cdf, alpha = 1 - confidence. P(X_(l) <= xi_p < X_(u)) =
    P(l <= B <= u - 1) >= confidence for any continuous distribution (Hahn & Meeker, Statistical
    Intervals, 1991, sec. 5.2). An end whose rank falls outside 1..n is None: no order statistic of
    the sample bounds the quantile on that side (l < 1 when (1 - p)^n >= alpha/2, u > n when
    p^n > alpha/2)."""
    k = min(max(math.ceil(p * n), 1), n)
    alpha = 1.0 - confidence
    lo = int(binomial_quantile(alpha / 2, n, p))
    hi = int(binomial_quantile(1 - alpha / 2, n, p)) + 1
    return k, (lo if lo >= 1 else None), (hi if hi <= n else None)


def samples_to_bound(p: float, confidence: float = 0.95) -> int | None:
    """The fewest samples n whose order statistics bound the p-quantile on both sides
    (``quantile_ranks`` gives both ranks): n >= ln(alpha/2) / ln p for the upper end and
    n > ln(alpha/2) / ln(1 - p) for the lower one, then checked against ``quantile_ranks`` itself.
    E.g. 2731 for p = 0.99865 or 0.00135, 6 for the median (alpha = 0.05). None for p = 0 or 1
    (the sample's min or max: no sample bounds the distribution's end)."""
    if not 0.0 < p < 1.0:
        return None
    a = (1.0 - confidence) / 2

    def bounded(m: int) -> bool:
        _, lo, hi = quantile_ranks(m, p, confidence)
        return lo is not None and hi is not None

    n = max(1, math.ceil(math.log(a) / math.log(p)), math.floor(math.log(a) / math.log1p(-p)) + 1)
    while not bounded(n):
        n += 1
    while n > 1 and bounded(n - 1):
        n -= 1
    return n


def quantile_with_ci(hist: Histogram, n: int, p: float, confidence: float = 0.95,
                     cumulative: tuple[int, np.ndarray] | None = None) -> Quantile:
    """The p-quantile of n samples summarised in ``hist``, with its order-statistic interval
    (``quantile_ranks``; an end the sample cannot bound is None, ``bounded`` False).
    ``cumulative``: (first bin, cumulative counts from it), if at hand (order_statistic)."""
    if n == 0:
        return Quantile(p, None, None, None, False, samples_to_bound(p, confidence))
    k, lo_rank, hi_rank = quantile_ranks(n, p, confidence)
    c = (0, np.cumsum(hist.counts)) if cumulative is None else cumulative  # once for the three ranks
    bounded = lo_rank is not None and hi_rank is not None
    return Quantile(p, order_statistic(hist, k, c), None if lo_rank is None else order_statistic(hist, lo_rank, c),
                    None if hi_rank is None else order_statistic(hist, hi_rank, c), bounded,
                    None if bounded else samples_to_bound(p, confidence))


def wilson_interval(successes: int, n: int, confidence: float = 0.95) -> tuple[float, float]:
    """Wilson score interval of a binomial proportion [-]:
    (p + z²/2n ± z sqrt(p(1-p)/n + z²/4n²)) / (1 + z²/n), z the normal quantile.
    Source: Wilson, JASA 22 (1927) 209. Parameters: successes <= n, n >= 1."""
    if n <= 0:
        return (math.nan, math.nan)
    z = Z95 if confidence == 0.95 else NormalDist().inv_cdf(0.5 + confidence / 2)
    p = successes / n
    denom = 1 + z * z / n
    centre = (p + z * z / (2 * n)) / denom
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / denom
    return (max(0.0, centre - half), min(1.0, centre + half))


def process_capability(mean: float, std: float, upper: float, lower: float = 0.0) -> tuple[float | None, float | None]:
    """Cp = (USL - LSL) / (6 sigma), Cpk = min(USL - mu, mu - LSL) / (3 sigma).
    Source: ISO 22514-2:2017 (capability indices). Parameters in the output's unit; None when
    sigma = 0 or a limit is missing."""
    if not std > 0 or not math.isfinite(upper):
        return None, None
    return (upper - lower) / (6.0 * std), min(upper - mean, mean - lower) / (3.0 * std)


def coarse_histogram(hist: Histogram, n: int, unit: str, bins: int = 200) -> HistogramData:
    """Re-binned histogram over the observed span of the samples; under/overflow kept apart."""
    fine_edges = hist.edges
    inner = hist.counts[1:-1]
    nz = np.nonzero(inner)[0]
    lo = fine_edges[nz[0]] if nz.size else hist.lo
    hi = fine_edges[nz[-1] + 1] if nz.size else hist.hi
    edges = np.linspace(lo, hi, bins + 1)
    span = slice(nz[0], nz[-1] + 1) if nz.size else slice(0, 0)  # the fine bins between the first and last sample
    centres = 0.5 * (fine_edges[:-1] + fine_edges[1:])[span]
    counts, _ = np.histogram(centres, bins=edges, weights=inner[span])
    width = edges[1] - edges[0]
    density = counts / (n * width) if n and width > 0 else np.zeros(bins)
    return HistogramData(unit, tuple(edges.tolist()), tuple(int(c) for c in counts), tuple(density.tolist()),
                         int(hist.counts[0]), int(hist.counts[-1]))


def _clamped(q: Quantile, lo: float, hi: float) -> Quantile:
    """A quantile read off the histogram (spread inside its bin) kept within the samples' range."""
    c = lambda v: None if v is None else min(max(v, lo), hi)  # noqa: E731
    return Quantile(q.probability, c(q.value), c(q.ci95_low), c(q.ci95_high), q.bounded, q.needs_samples)


def output_statistics(raw: RawOutput, quantiles=DEFAULT_QUANTILES, spec: float | None = None,
                      samples: int | None = None, coarse: bool = True) -> OutputStatistics:
    """Every statistic of one output of a (possibly partial) run. The moments and quantiles are
    those of the samples the output applies to; the yield of a conditional output counts every
    sample (``samples``, the run's total): one it does not apply to meets the spec, as in the joint
    yield (a unit whose cycloid stage is free meets a preload limit). ``coarse`` False leaves out
    the 200-bin histogram (None): a convergence point needs none."""
    m: Moments = raw.moments
    o = raw.output
    n = m.n
    std = math.sqrt(m.m2 / (n - 1)) if n > 1 else 0.0
    half = Z95 * std / math.sqrt(n) if n > 1 else math.nan
    mean = m.mean if n else math.nan
    total = samples if o.conditional and samples is not None else n
    if spec is not None and total:
        passing = m.n_pass + (total - n)
        y = Proportion.sampled(passing, total)
        cp, cpk = process_capability(mean, std, spec) if o.upper_limit and not o.conditional else (None, None)
        ppm = (1.0 - passing / total) * 1e6
    else:
        y, cp, cpk, ppm = None, None, None, None
    # once for every quantile, over the occupied bins only
    cumulative = occupied_cumulative(raw.histogram, m.min, m.max) if quantiles and n else None
    qs = tuple(quantile_with_ci(raw.histogram, n, p, cumulative=cumulative) for p in quantiles)
    if n:
        qs = tuple(_clamped(q, m.min, m.max) for q in qs)
    return OutputStatistics(
        o.name, o.unit, o.description, n, mean, mean - half, mean + half, std,
        m.min if n else None, m.max if n else None,
        Quantiles(o.unit, qs),
        spec, o.upper_limit, y, ppm, cp, cpk, m.n_negative / n if n else None,
        coarse_histogram(raw.histogram, n, o.unit) if coarse else None)
