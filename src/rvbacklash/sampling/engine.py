"""Streaming Monte-Carlo engine: seeded blocks, bounded memory, exact reproducibility.

Reproducibility contract
- The sample stream is cut into blocks of BLOCK_SIZE samples; block b draws from its own
  generator ``PCG64(SeedSequence(seed, spawn_key=(b,)))``, so the samples do not depend on the
  chunk size (blocks per task) or the number of worker threads.
- Each block is reduced to a small summary (shifted sums, min, max, counts) and a fixed-bin
  histogram. Summaries are merged strictly in block order (Chan et al. pairwise update) and
  histograms are integer counts, so statistics are bit-identical for any chunking or threads.
- The histogram range comes from block 0 (the "pilot"), which is part of every run.

Memory: one output buffer per block being worked on and one histogram per worker thread,
whatever the number of samples.
"""

from __future__ import annotations

import math
import threading
import time
import warnings
from concurrent.futures import FIRST_COMPLETED, ThreadPoolExecutor, wait
from dataclasses import dataclass, field
from typing import Callable

import numpy as np
from numpy.random import PCG64, Generator, SeedSequence
from scipy import special
from scipy.stats import qmc

from rvbacklash.sampling import kernels
from rvbacklash.sampling.inputs import InputTransform, linear_fast_plan

BLOCK_SIZE = 1 << 16
HIST_BINS = 1 << 18
METHODS = ("default", "box-muller", "sobol")
MAX_SAMPLES = {"default": 10**12, "box-muller": 10**12, "sobol": 2**30}  # sobol: scipy's 30-bit limit
PILOT_SIGMAS = 12.0  # histogram range: pilot mean +- 12 pilot standard deviations (and its min/max)


def block_generator(seed: int, block: int) -> Generator:
    """The generator of block ``block``: independent of every other block and of the run size."""
    return Generator(PCG64(SeedSequence(seed, spawn_key=(block,))))


def block_sizes(samples: int) -> list[int]:
    full, rest = divmod(samples, BLOCK_SIZE)
    return [BLOCK_SIZE] * full + ([rest] if rest else [])


# --- what produces the output values of one block --------------------------------------------

@dataclass(frozen=True, eq=False)
class BlockSource:
    """Produces the model outputs [arcmin] of block b (size n) for one method."""

    method: str
    seed: int
    transform: InputTransform
    model: Callable[[np.ndarray], np.ndarray]
    fast: tuple[np.ndarray, float] | None  # (weights, offset) of the linear fast path

    def normals(self, b: int, n: int) -> np.ndarray:
        """(n, k) independent standard normals of block b."""
        k = self.transform.dimension
        if self.method == "default":
            return block_generator(self.seed, b).standard_normal((n, k))
        if self.method == "box-muller":
            out = np.empty((n, k))
            kernels.box_muller_normals(block_generator(self.seed, b), n, k, out)
            return out
        # sobol: one scrambled sequence for the whole run, block b starts at point b * BLOCK_SIZE
        eng = qmc.Sobol(d=max(k, 1), scramble=True, seed=Generator(PCG64(SeedSequence(self.seed))))
        if b:
            eng.fast_forward(b * BLOCK_SIZE)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # balance warning for sizes that are not powers of 2
            u = eng.random(n)[:, :k]
        return special.ndtri(np.clip(u, 1e-16, 1.0 - 1e-16))

    def values(self, b: int, n: int) -> np.ndarray:
        if self.fast is not None:
            weights, offset = self.fast
            if self.method == "default":
                out = np.empty(n)
                kernels.linear_normal_block(block_generator(self.seed, b), n, weights, offset, out)
                return out
            if self.method == "box-muller":
                out = np.empty(n)
                kernels.linear_box_muller_block(block_generator(self.seed, b), n, weights, offset, out)
                return out
            z = self.normals(b, n)
            y = np.full(n, offset)
            for j in range(weights.size):  # same summation order as the kernels
                y += z[:, j] * weights[j]
            return y
        return np.asarray(self.model(self.transform(self.normals(b, n))), dtype=float)

    def block(self, b: int, n: int) -> tuple[np.ndarray, int]:
        """Outputs of block b and how many of them interfere (negative lost motion)."""
        y = self.values(b, n)
        return y, int(np.count_nonzero(y < 0))


def make_block_source(method: str, seed: int, transform: InputTransform, model,
                      sensitivities: np.ndarray | None) -> BlockSource:
    """Linear models with normal inputs take the compiled fast path; everything else (other
    marginals, non-linear models) maps normals through the copula and calls ``model``."""
    fast = linear_fast_plan(transform, sensitivities) if sensitivities is not None else None
    return BlockSource(method, seed, transform, model, fast)


# --- merged summaries ------------------------------------------------------------------------

@dataclass
class Moments:
    """Count, mean, M2 (sum of squared deviations), min, max, and spec counts of merged blocks."""

    n: int = 0
    mean: float = 0.0
    m2: float = 0.0
    min: float = math.inf
    max: float = -math.inf
    n_le_spec: int = 0
    n_negative: int = 0

    def merge_block(self, n: int, shift: float, stats: np.ndarray) -> None:
        """Chan, Golub & LeVeque pairwise update with one block's shifted sums."""
        s1, s2 = float(stats[0]), float(stats[1])
        b_mean = shift + s1 / n
        b_m2 = max(s2 - s1 * s1 / n, 0.0)
        tot = self.n + n
        delta = b_mean - self.mean
        self.mean += delta * n / tot
        self.m2 += b_m2 + delta * delta * self.n * n / tot
        self.n = tot
        self.min = min(self.min, float(stats[2]))
        self.max = max(self.max, float(stats[3]))
        self.n_le_spec += int(stats[4])
        self.n_negative += int(stats[5])


@dataclass
class Histogram:
    lo: float
    hi: float
    counts: np.ndarray  # HIST_BINS + 2: underflow, bins, overflow

    @property
    def edges(self) -> np.ndarray:
        return np.linspace(self.lo, self.hi, self.counts.size - 1)


@dataclass
class RawRun:
    """What a run leaves for the statistics (``rvbacklash.analysis.statistics``)."""

    moments: Moments
    histogram: Histogram
    convergence: list[dict] = field(default_factory=list)
    partial: bool = False
    elapsed_s: float = 0.0


def _histogram_range(y: np.ndarray) -> tuple[float, float]:
    m, s = float(np.mean(y)), float(np.std(y))
    lo, hi = min(float(y.min()), m - PILOT_SIGMAS * s), max(float(y.max()), m + PILOT_SIGMAS * s)
    pad = max(0.5 * (hi - lo), 1e-9 * max(1.0, abs(m)))
    if s == 0.0:
        return m - pad, m + pad
    return lo, hi


def run_blocks(source: BlockSource, samples: int, spec: float, workers: int = 2, chunk_blocks: int = 4,
               progress: Callable[[int], None] | None = None,
               snapshot: Callable[[Moments, Histogram], dict] | None = None) -> RawRun:
    """Draw and reduce ``samples`` outputs in blocks; see the module docstring.

    ``progress(n)`` is called with the samples finished so far; ``snapshot(moments, hist)`` at
    every power-of-two number of blocks, for the convergence trace. Ctrl-C stops after the
    blocks being worked on and returns the finished ones with ``partial=True``.
    """
    t0 = time.perf_counter()
    sizes = block_sizes(samples)
    pilot, pilot_interfering = source.block(0, sizes[0])
    lo, hi = _histogram_range(pilot)
    h_scale = HIST_BINS / (hi - lo)
    shift = float(np.mean(pilot))

    local = threading.local()
    hists: list[np.ndarray] = []
    lock = threading.Lock()

    def thread_hist() -> np.ndarray:
        h = getattr(local, "hist", None)
        if h is None:
            h = local.hist = np.zeros(HIST_BINS + 2, dtype=np.int64)
            with lock:
                hists.append(h)
        return h

    def task(blocks: range) -> list[tuple[int, np.ndarray]]:
        out = []
        hist = thread_hist()
        for b in blocks:
            y, interfering = (pilot, pilot_interfering) if b == 0 else source.block(b, sizes[b])
            stats = np.empty(6)
            kernels.accumulate(y, shift, spec, hist, lo, h_scale, stats)
            stats[5] = interfering  # the source knows what interference means for its model
            out.append((b, stats))
        return out

    moments = Moments()
    done: dict[int, np.ndarray] = {}
    next_block = 0
    convergence: list[dict] = []
    partial = False

    def fold() -> None:
        nonlocal next_block
        while next_block in done:
            moments.merge_block(sizes[next_block], shift, done.pop(next_block))
            next_block += 1

    def merged_hist() -> Histogram:
        total = np.zeros(HIST_BINS + 2, dtype=np.int64)
        for h in hists:
            total += h
        return Histogram(lo, hi, total)

    # waves end at 1, 2, 4, 8, ... blocks: a convergence point at each
    ends, e = [], 1
    while e < len(sizes):
        ends.append(e)
        e *= 2
    ends.append(len(sizes))
    start = 0
    finished_samples = 0
    with ThreadPoolExecutor(max_workers=max(1, workers)) as pool:
        try:
            for end in ends:
                # at least one task per worker in every wave (results do not depend on the split)
                step = max(1, min(chunk_blocks, -(-(end - start) // max(1, workers))))
                chunks = [range(a, min(a + step, end)) for a in range(start, end, step)]
                pending = {pool.submit(task, c) for c in chunks}
                try:
                    while pending:
                        finished, pending = wait(pending, timeout=0.2, return_when=FIRST_COMPLETED)
                        for fut in finished:
                            for b, stats in fut.result():
                                done[b] = stats
                                finished_samples += sizes[b]
                        if finished and progress is not None:
                            progress(finished_samples)
                except KeyboardInterrupt:
                    for fut in pending:
                        fut.cancel()
                    for fut in pending:
                        if not fut.cancelled():
                            for b, stats in fut.result():
                                done[b] = stats
                    raise
                fold()
                start = end
                if snapshot is not None:
                    convergence.append(snapshot(moments, merged_hist()))
        except KeyboardInterrupt:
            partial = True
            # blocks finished out of order are folded too, still in block order
            for b in sorted(done):
                moments.merge_block(sizes[b], shift, done.pop(b))
    return RawRun(moments, merged_hist(), convergence, partial, time.perf_counter() - t0)
