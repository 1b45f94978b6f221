"""Streaming Monte-Carlo engine: seeded blocks, bounded memory, exact reproducibility.

Reproducibility contract
- The sample stream is cut into blocks of BLOCK_SIZE samples (or the source's ``block_size``:
  the contact, elastic and transmission-error sources cut finer); block b draws from its own
  generator seeded by ``SeedSequence(seed, spawn_key=(*stream, b))``, so the samples do not depend
  on the chunk size (blocks per task) or the number of worker threads. The linear source's
  default method draws its normals inside compiled kernels (xoshiro256++ and the ziggurat,
  ``sampling.fast_normals``); the other sources and methods draw from ``block_generator``
  (numpy PCG64).
- A block source turns block b into the values of its outputs, one row per output (``Output``);
  NaN marks a sample an output does not apply to. Each block is reduced to a small summary per
  output (shifted sums, min, max, counts) and a fixed-bin histogram. Summaries are merged strictly
  in block order (Chan et al. pairwise update) and histograms are integer counts, so statistics
  are bit-identical for any chunking or threads.
- The histogram ranges come from block 0 (the "pilot"), which is part of every run.

Memory: the output buffers of the blocks being worked on and one histogram per output per task
in flight, whatever the number of samples.

Ctrl-C (``rvbacklash.interrupt``): the run stops after the blocks being worked on and returns
the finished ones, marked partial; every statistic (moments, histograms, counts) covers exactly
the same blocks.
"""

from __future__ import annotations

import contextvars
import math
import threading
import time
import warnings
from concurrent.futures import FIRST_COMPLETED, Future, ThreadPoolExecutor, wait
from dataclasses import dataclass, field
from typing import Callable, Protocol

import numpy as np
from numpy.random import PCG64, Generator, SeedSequence

from rvbacklash.interrupt import check_abandoned, stop_requested
from rvbacklash.sampling import fast_normals, kernels
from rvbacklash.sampling.inputs import InputTransform, linear_fast_plan

BLOCK_SIZE = 1 << 16
HIST_BINS = 1 << 18
METHODS = ("default", "box-muller", "sobol")
MAX_SAMPLES = {"default": 10**12, "box-muller": 10**12, "sobol": 2**30}  # sobol: scipy's 30-bit limit
PILOT_SIGMAS = 12.0  # histogram range: pilot mean +- 12 pilot standard deviations (and its min/max)


def block_generator(seed: int, block: int, stream: tuple[int, ...] = ()) -> Generator:
    """The generator of block ``block``: independent of every other block and of the run size.
    ``stream`` prefixes the spawn key, e.g. (point,) for the points of a sweep: one seed, many
    independent runs, ``SeedSequence(seed, spawn_key=(*stream, block))``."""
    return Generator(PCG64(SeedSequence(seed, spawn_key=(*stream, block))))


def block_sizes(samples: int, block_size: int = BLOCK_SIZE) -> list[int]:
    full, rest = divmod(samples, block_size)
    return [block_size] * full + ([rest] if rest else [])


def source_block_size(source) -> int:
    """A source's block size: its ``block_size`` if it has one (the costly models cut their runs
    finer, so that both cores work from the first blocks on), else BLOCK_SIZE."""
    return int(getattr(source, "block_size", BLOCK_SIZE))


@dataclass(frozen=True)
class Output:
    """One quantity a block source produces per sample."""

    name: str  # e.g. "backlash", "lost_motion", "preload"
    unit: str  # "arcmin", "um", "nm_per_arcmin"
    description: str
    upper_limit: bool = True  # a spec on it is an upper limit (lost motion) or a lower one (rigidity)
    conditional: bool = False  # applies to some samples only (NaN elsewhere)
    hint_range: tuple[float, float] | None = None  # histogram range if the pilot block has no value


class BlockSource(Protocol):
    """What the engine runs. A source may also set ``block_size`` (samples per block, default
    BLOCK_SIZE): part of its numbers' contract, like the seed."""

    outputs: tuple[Output, ...]

    def block(self, b: int, n: int) -> np.ndarray:
        """(len(outputs), n) values of block b [units of the outputs]."""


# --- the linear model (and any vectorised model of the 21 raw factor values) ------------------

@dataclass(frozen=True, eq=False)
class LinearSource:
    """Outputs [arcmin] of a model of the 21 raw factor values, block by block, for one method."""

    method: str
    seed: int
    stream: tuple[int, ...]
    transform: InputTransform
    model: Callable[[np.ndarray], np.ndarray]
    fast: tuple[np.ndarray, float] | None  # (weights, offset) of the linear fast path
    outputs: tuple[Output, ...] = (Output("backlash", "arcmin", "output backlash (rigid lost motion)"),)

    def normals(self, b: int, n: int) -> np.ndarray:
        """(n, k) independent standard normals of block b."""
        k = self.transform.dimension
        if self.method == "default":
            out = np.empty((n, k))
            fast_normals.standard_normals(fast_normals.block_state(self.seed, b, self.stream), out)
            return out
        if self.method == "box-muller":
            out = np.empty((n, k))
            kernels.box_muller_normals(block_generator(self.seed, b, self.stream), n, k, out)
            return out
        # sobol: one scrambled sequence for the whole run, block b starts at point b * BLOCK_SIZE
        from scipy import special
        from scipy.stats import qmc

        eng = qmc.Sobol(d=max(k, 1), scramble=True,
                        seed=Generator(PCG64(SeedSequence(self.seed, spawn_key=self.stream))))
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
                fast_normals.linear_normal_block(fast_normals.block_state(self.seed, b, self.stream), n, weights,
                                                 offset, out)
                return out
            if self.method == "box-muller":
                out = np.empty(n)
                kernels.linear_box_muller_block(block_generator(self.seed, b, self.stream), n, weights, offset, out)
                return out
            z = self.normals(b, n)
            y = np.full(n, offset)
            for j in range(weights.size):  # same summation order as the kernels
                y += z[:, j] * weights[j]
            return y
        return np.asarray(self.model(self.transform(self.normals(b, n))), dtype=float)

    def block(self, b: int, n: int) -> np.ndarray:
        return self.values(b, n)[None, :]


def linear_source(method: str, seed: int, transform: InputTransform, model,
                  sensitivities: np.ndarray | None, stream: tuple[int, ...] = ()) -> LinearSource:
    """Linear models with normal inputs (correlated or not) take the compiled fast path;
    everything else (other marginals, non-linear models) maps the same method's normals through
    the copula and calls ``model``."""
    fast = linear_fast_plan(transform, sensitivities) if sensitivities is not None else None
    return LinearSource(method, seed, tuple(stream), transform, model, fast)


# --- merged summaries ------------------------------------------------------------------------

@dataclass
class Moments:
    """Count, mean, M2 (sum of squared deviations), min, max and counts of merged blocks."""

    n: int = 0  # valid values
    mean: float = 0.0
    m2: float = 0.0
    min: float = math.inf
    max: float = -math.inf
    n_pass: int = 0  # values meeting the limit
    n_negative: int = 0

    def merge_block(self, shift: float, stats: kernels.BlockSummary) -> None:
        """Chan, Golub & LeVeque pairwise update with one block's shifted sums."""
        n = int(stats.valid)
        if n == 0:
            return
        s1, s2 = float(stats.shifted_sum), float(stats.shifted_sum_sq)
        b_mean = shift + s1 / n
        b_m2 = max(s2 - s1 * s1 / n, 0.0)
        tot = self.n + n
        delta = b_mean - self.mean
        self.mean += delta * n / tot
        self.m2 += b_m2 + delta * delta * self.n * n / tot
        self.n = tot
        self.min = min(self.min, float(stats.min))
        self.max = max(self.max, float(stats.max))
        self.n_pass += int(stats.passing)
        self.n_negative += int(stats.negative)


@dataclass
class Histogram:
    lo: float
    hi: float
    counts: np.ndarray  # HIST_BINS + 2: underflow, bins, overflow

    @property
    def edges(self) -> np.ndarray:
        return np.linspace(self.lo, self.hi, self.counts.size - 1)


@dataclass
class RawOutput:
    """What a run leaves of one output for the statistics (``rvbacklash.analysis.statistics``)."""

    output: Output
    limit: float
    moments: Moments
    histogram: Histogram


@dataclass
class RawRun:
    outputs: list[RawOutput]
    samples: int  # samples finished (every output saw these, valid or NaN)
    n_joint_pass: int  # samples meeting every limit at once
    convergence: list[dict] = field(default_factory=list)
    partial: bool = False
    elapsed_s: float = 0.0


def _histogram_range(y: np.ndarray, hint: tuple[float, float] | None) -> tuple[float, float]:
    y = y[np.isfinite(y)]  # an infinite value (a rigid unit's rigidity) goes to the under/overflow bin
    if y.size == 0:
        return hint if hint is not None else (0.0, 1.0)
    m, s = float(np.mean(y)), float(np.std(y))
    lo, hi = min(float(y.min()), m - PILOT_SIGMAS * s), max(float(y.max()), m + PILOT_SIGMAS * s)
    if hint is not None:
        lo, hi = min(lo, hint[0]), max(hi, hint[1])
    pad = max(0.5 * (hi - lo), 1e-9 * max(1.0, abs(m)))
    if hi - lo <= 0:
        return m - pad, m + pad
    return lo, hi


def run_blocks(source: BlockSource, samples: int, limits: tuple[float, ...] | None = None, workers: int = 2,
               chunk_blocks: int = 4, progress: Callable[[int], None] | None = None,
               snapshot: Callable[[RawRun], dict] | None = None) -> RawRun:
    """Draw and reduce ``samples`` samples of every output of ``source`` in blocks (module docstring).

    ``limits``: one spec limit per output (+-inf for none; the side is the output's). ``progress(n)``
    is called with the samples finished so far; ``snapshot(run)`` at every power-of-two number of
    blocks, for the convergence trace.
    """
    t0 = time.perf_counter()
    outs = source.outputs
    limits_a = np.array(limits if limits is not None else [math.inf if o.upper_limit else -math.inf for o in outs],
                        dtype=float)
    upper = np.array([o.upper_limit for o in outs])
    sizes = block_sizes(samples, source_block_size(source))
    with stop_requested() as stop:  # from here on, Ctrl-C stops the run after the blocks under way
        run = _run(source, sizes, limits_a, upper, workers, chunk_blocks, progress, snapshot, stop, t0)
    if run.partial:
        check_abandoned()  # a stop_on stop (a workbench job): nobody reads the partial run, nor what follows it
    return run


def histogram_bin(value: float, lo: float, scale: float) -> int:
    """The histogram bin that ``kernels.accumulate`` puts a (valid) value in: 0 underflow,
    HIST_BINS + 1 overflow."""
    t = (value - lo) * scale
    return 0 if t < 0.0 else (HIST_BINS + 1 if t >= HIST_BINS else int(t) + 1)


def _task_ranges(n_blocks: int, workers: int, chunk_blocks: int) -> tuple[list[range], list[int]]:
    """The blocks of each task, and the convergence points (blocks folded) they end on.

    The points are 1, 2, 4, 8, ... blocks and the last; every task lies inside one stretch between
    two points, with at least two tasks per worker in each where it has the blocks (the threads
    then finish a stretch together; results do not depend on the split)."""
    ends, e = [], 1
    while e < n_blocks:
        ends.append(e)
        e *= 2
    ends.append(n_blocks)
    tasks, start = [], 0
    for end in ends:
        step = max(1, min(chunk_blocks, -(-(end - start) // (2 * max(1, workers)))))
        tasks += [range(a, min(a + step, end)) for a in range(start, end, step)]
        start = end
    return tasks, ends


def _run(source, sizes, limits_a, upper, workers, chunk_blocks, progress, snapshot, stop, t0) -> RawRun:
    """No barrier anywhere: every thread draws its blocks while block 0 (the pilot, which fixes the
    histogram ranges and the shifts) is drawn; a task histograms its blocks once the pilot is in.
    Finished tasks are folded (moments and histograms) strictly in block order, a convergence
    point is taken whenever the folded blocks reach one of its ends, and at most 2 x workers tasks
    are in flight (memory)."""
    outs = source.outputs
    k = len(outs)
    tasks, ends = _task_ranges(len(sizes), workers, chunk_blocks)
    pilot_in = threading.Event()
    frame: dict = {}  # ranges, scales, shifts: set once from the pilot

    def set_frame(pilot: np.ndarray) -> None:
        ranges = [_histogram_range(pilot[c], outs[c].hint_range) for c in range(k)]
        shifts = []
        for c in range(k):
            valid = pilot[c][~np.isnan(pilot[c])]
            shifts.append(float(np.mean(valid)) if valid.size else 0.5 * sum(ranges[c]))
        frame.update(ranges=ranges, scales=[HIST_BINS / (hi - lo) for lo, hi in ranges], shifts=shifts)

    def task(blocks: range):
        """(its blocks, per block: each output's BlockSummary and the joint count; histograms (k, bins))
        of some blocks."""
        ys = []
        try:
            for b in blocks:
                if b > blocks.start and stop.is_set():  # a stop: the blocks drawn are kept, the rest not drawn
                    blocks = range(blocks.start, b)
                    break
                y = source.block(b, sizes[b])
                if b == 0:
                    set_frame(y)
                ys.append(y)
        finally:
            if blocks.start == 0:
                pilot_in.set()  # also on failure (of the pilot, or a dropped block): no task waits forever
        pilot_in.wait()
        if not frame:
            raise RuntimeError("the pilot block failed")
        ranges, scales, shifts = frame["ranges"], frame["scales"], frame["shifts"]
        hist = np.zeros((k, HIST_BINS + 2), dtype=np.int64)
        per_block = []
        for b, y in zip(blocks, ys):
            stats = [kernels.accumulate(y[c], shifts[c], limits_a[c], upper[c], hist[c], ranges[c][0], scales[c])
                     for c in range(k)]
            joint = kernels.count_joint(y, limits_a, upper) if k > 1 else int(stats[0].passing)
            per_block.append((stats, joint))
        return blocks, per_block, hist

    moments = [Moments() for _ in range(k)]
    hist_total = np.zeros((k, HIST_BINS + 2), dtype=np.int64)
    done: dict[int, tuple] = {}  # first block of a finished task -> (blocks, per_block, hist)
    run: RawRun | None = None  # made once the histogram ranges are known (the pilot)

    def new_run(ranges) -> RawRun:
        return RawRun([RawOutput(outs[c], float(limits_a[c]), moments[c], Histogram(*ranges[c], hist_total[c]))
                       for c in range(k)], 0, 0)
    next_block = 0
    finished_samples = 0

    def fold_task(blocks: range, per_block, hist) -> None:
        nonlocal next_block
        for b, (stats, joint) in zip(blocks, per_block):
            for c in range(k):
                moments[c].merge_block(frame["shifts"][c], stats[c])
            run.samples += sizes[b]
            run.n_joint_pass += joint
        for c in range(k):  # only the bins between the task's least and greatest value (a few MB less each)
            valid = [stats[c] for stats, _ in per_block if stats[c].valid > 0]
            if valid:
                lo = histogram_bin(min(s.min for s in valid), frame["ranges"][c][0], frame["scales"][c])
                hi = histogram_bin(max(s.max for s in valid), frame["ranges"][c][0], frame["scales"][c]) + 1
                np.add(hist_total[c, lo:hi], hist[c, lo:hi], out=hist_total[c, lo:hi])
        next_block = blocks.stop

    def fold() -> None:
        """Merge the finished tasks in block order; a convergence point at each end reached."""
        nonlocal run
        while next_block in done:
            if run is None:  # the frame is known once block 0's task is done
                run = new_run(frame["ranges"])
            fold_task(*done.pop(next_block))
            if snapshot is not None and next_block in ends:
                run.convergence.append(snapshot(run))

    def collect(fut: Future) -> None:
        nonlocal finished_samples
        blocks, per_block, hist = fut.result()
        done[blocks.start] = (blocks, per_block, hist)
        finished_samples += sum(sizes[b] for b in blocks)

    pending: set[Future] = set()
    queue = iter(tasks)
    in_flight = 2 * max(1, workers)
    with ThreadPoolExecutor(max_workers=max(1, workers)) as pool:
        try:
            for blocks in queue:  # (none when a stop came before the run: it does not start its work)
                if stop.is_set():
                    break
                # a copy of this context each: a workbench job's stop reaches a block's chunks
                pending.add(pool.submit(contextvars.copy_context().run, task, blocks))
                if len(pending) >= in_flight:
                    break
            while pending and not stop.is_set():
                finished, _ = wait(pending, timeout=0.2, return_when=FIRST_COMPLETED)
                for fut in finished:
                    collect(fut)
                    pending.discard(fut)
                    nxt = next(queue, None)
                    if nxt is not None and not stop.is_set():
                        pending.add(pool.submit(contextvars.copy_context().run, task, nxt))
                if finished:
                    fold()
                    if progress is not None:
                        progress(finished_samples)
        except KeyboardInterrupt:  # raised by a callback, or outside the main thread
            stop.set()
        except BaseException:  # a callback's own exception (a cancelled job): no queued task starts
            for fut in pending:
                fut.cancel()
            raise
        if stop.is_set():
            for fut in pending:
                fut.cancel()
            for fut in pending:
                if not fut.cancelled():
                    collect(fut)  # blocks already being worked on are finished and kept
            pending.clear()
            fold()
            if done and run is None:  # any finished task waited for the pilot: the frame is known
                run = new_run(frame["ranges"])
            for first in sorted(done):  # tasks finished out of order are folded too, in block order
                fold_task(*done.pop(first))
    if run is None:  # stopped before block 0 was in: nothing finished
        run = new_run([(0.0, 1.0)] * k)
    run.partial = run.samples < sum(sizes)
    run.elapsed_s = time.perf_counter() - t0
    return run
