"""Global sensitivity of any model: first-order and total Sobol indices per input group, with
bootstrap confidence intervals.

Estimators (Saltelli, Annoni, Azzini, Campolongo, Ratto & Tarantola, Comput. Phys. Commun. 181
(2010) 259-270, Table 2 (b) and (f)): with two independent sets A and B of N units, and AB_j the
set A whose group j is taken from B,

    S_j  = mean( f(B) (f(AB_j) - f(A)) ) / V,        S_Tj = mean( (f(A) - f(AB_j))^2 ) / (2 V),

V the variance of f over A and B, f centred by its mean first (Sobol' & Levitan 1999). The
indices are computed by ``scipy.stats.sobol_indices`` (method ``saltelli_2010``) from the outputs
we give it. Cost: N (D + 2) model runs for D random groups. Inputs must be independent.

Groups and random streams. A group is one input of a model: a catalog factor, however many
numbers it draws per unit (per pin, per tooth, per disc), or an extra random input of the model
(e.g. the crank angle of the measurement). Input k of block b of set m (0 = A, 1 = B) draws all
of its numbers from ``Generator(PCG64(SeedSequence(seed, spawn_key=(*stream, m, k, b))))``, so
"group j from B" is "input j reads the stream of set 1": exact group swapping whatever the model
does with its numbers, and the same numbers for any order, thread or worker count. This is the
seam a model provides (``StreamModel``): its inputs, which are random, its outputs and
``block(generators, n) -> (len(outputs), n)``. The linear model is implemented here; the
contact and elastic models plug in through ``STREAM_MODELS``.

Intervals: percentile bootstrap over units (rows of A, B and every AB_j resampled together, the
resampling of scipy's ``SobolResult.bootstrap``), with the statistic written as weighted means
so that all replicates are one matrix product. scipy's own interval is BCa, whose jackknife
costs N statistic evaluations (O(N^2 D): 5 s at N = 4096, about 75 s at 16384 on two cores).

Where the tasks run: one thread per core by default (``ThreadExecutor``; the models' kernels
release the GIL), the same numbers as one after the other (``InlineExecutor``): a task's result
depends on its own streams only.
"""

from __future__ import annotations

import contextvars
import math
import time
from concurrent.futures import FIRST_COMPLETED, ThreadPoolExecutor, wait
from dataclasses import dataclass
from typing import Callable, Protocol, Sequence

import numpy as np
from numpy.random import PCG64, Generator, SeedSequence

from rvbacklash.analysis.executor import cores
from rvbacklash.analysis.sensitivity import rank_descending, variance_shares
from rvbacklash.errors import InputError
from rvbacklash.factors.catalog import CATALOG, FACTOR_KEYS
from rvbacklash.factors.distributions import is_normal
from rvbacklash.interrupt import stop_requested
from rvbacklash.problem import Problem
from rvbacklash.results import Result
from rvbacklash.sampling.engine import Output

BLOCK = 1 << 14  # units per block: a block's numbers depend on (seed, stream, set, input, block) only
MIN_SAMPLES, MAX_SAMPLES = 1 << 6, 1 << 22
DEFAULT_SAMPLES = 1 << 14
DEFAULT_RESAMPLES = 1000
SET_A, SET_B, SET_BOOTSTRAP = 0, 1, 2  # first element of the spawn key
CONFIDENCE = 0.95
METHOD = ("Saltelli 2010 first order, Jansen total (scipy.stats.sobol_indices, saltelli_2010); percentile "
          "bootstrap over units")


# --- the seam ------------------------------------------------------------------------------------

class StreamModel(Protocol):
    """A model whose every input draws from its own random stream.

    ``inputs``: names, catalog keys first (in catalog order) then any extra random input;
    ``random``: which inputs vary (others are never swapped); ``outputs``: what ``block`` returns.
    ``block(generators, n)``: (len(outputs), n) values of n units, input k drawing every random
    number it needs from ``generators[k]`` only (and nothing from anywhere else)."""

    inputs: tuple[str, ...]
    random: tuple[bool, ...]
    outputs: tuple[Output, ...]

    def block(self, generators: Sequence[Generator], n: int) -> np.ndarray: ...


def draw_marginal(problem: Problem, i: int, generator: Generator, n: int) -> np.ndarray:
    """n values [um] of factor i's raw quantity from its own generator: mu + sigma z for a normal
    law, else its inverse cdf at uniform numbers; a fixed factor is its value."""
    if problem.sigmas_um[i] == 0:
        return np.full(n, problem.means_um[i])
    if is_normal(problem.zones[i]):
        return problem.means_um[i] + problem.sigmas_um[i] * generator.standard_normal(n)
    return np.asarray(problem.marginals[i].ppf(generator.random(n)), dtype=float)


@dataclass(frozen=True, eq=False)
class LinearStreams:
    """The linear model, Eq. (2): backlash = sum_i S_i x_i, each factor from its own stream."""

    problem: Problem
    outputs: tuple[Output, ...] = (Output("backlash", "arcmin", "output backlash (rigid lost motion)"),)

    @property
    def inputs(self) -> tuple[str, ...]:
        return FACTOR_KEYS

    @property
    def random(self) -> tuple[bool, ...]:
        return tuple(bool(x) for x in self.problem.random_mask)

    def block(self, generators: Sequence[Generator], n: int) -> np.ndarray:
        p = self.problem
        s = p.sensitivities_arcmin_per_um
        y = np.full(n, float(s[~p.random_mask] @ p.means_um[~p.random_mask]))
        for i in np.flatnonzero(p.random_mask):
            if s[i] != 0:
                y += s[i] * draw_marginal(p, int(i), generators[i], n)
            else:  # no effect on the output, but its stream is drawn all the same
                draw_marginal(p, int(i), generators[i], n)
        return y[None, :]


LIFE_OUTPUTS = ("life", "weakest_bearing_life", "rated_torque", "max_pin_stress")  # = analysis.simulation's


def _contact(problem: Problem) -> StreamModel:
    from rvbacklash.sampling.contact_source import contact_streams

    return contact_streams(problem)


def _elastic(problem: Problem) -> StreamModel:
    from rvbacklash.sampling.elastic_source import elastic_streams

    return elastic_streams(problem)


def _transmission(problem: Problem) -> StreamModel:
    from rvbacklash.sampling.te_source import transmission_streams

    return transmission_streams(problem)


# name -> factory(problem) of the model's StreamModel (one entry per model)
STREAM_MODELS: dict[str, Callable[[Problem], StreamModel]] = {"linear": LinearStreams, "contact": _contact,
                                                              "elastic": _elastic, "transmission": _transmission}


# --- results -------------------------------------------------------------------------------------

@dataclass(frozen=True, repr=False)
class GroupSensitivity(Result):
    """Sobol indices of one input group with their 95 % intervals."""

    input: str  # catalog key (or the name of an extra input)
    id: int | None  # Table 2 id of a catalog factor
    first: float
    first_ci95_low: float
    first_ci95_high: float
    total: float
    total_ci95_low: float
    total_ci95_high: float
    rank: int  # by the total index, 1 = largest
    linear_variance_share: float | None  # S_i^2 sigma_i^2 / sigma^2 of the linear model (closed form)
    linear_rank: int | None

    def summary(self) -> list[str]:
        return [f"{self.input}: first {self.first:.4f} [{self.first_ci95_low:.4f}, {self.first_ci95_high:.4f}], "
                f"total {self.total:.4f} [{self.total_ci95_low:.4f}, {self.total_ci95_high:.4f}]"]


@dataclass(frozen=True, repr=False)
class SensitivityResult(Result):
    """First-order and total Sobol indices of one output of one model, per input group
    (``groups``, largest total index first); ``to_frame()`` indexed by input."""

    design_name: str
    model: str
    output: str
    unit: str
    samples: int  # N units per set
    model_runs: int  # N (D + 2)
    seed: int
    stream: tuple[int, ...]
    resamples: int
    confidence: float
    mean: float  # of the output over A and B [unit]
    sigma: float
    groups: tuple[GroupSensitivity, ...]
    elapsed_s: float
    partial: bool
    method: str = METHOD
    notes: tuple[str, ...] = ()
    _frame_index = "input"

    @property
    def sum_first(self) -> float:
        return float(sum(g.first for g in self.groups))

    def rows(self) -> list[dict]:
        """One row per input, each marked ``partial`` when the run was interrupted."""
        return [{**g.to_dict(), "partial": self.partial} for g in self.groups]

    def summary(self) -> list[str]:
        head = (f"{self.design_name}, {self.model} model, {self.output}: Sobol indices, N = {self.samples:,} "
                f"({self.model_runs:,} runs), seed {self.seed}" + ("  [PARTIAL: interrupted]" if self.partial else ""))
        return [head] + [line for g in self.groups[:5] for line in g.summary()]


# --- the estimator -------------------------------------------------------------------------------

def stream_generator(seed: int, stream: tuple[int, ...], sample_set: int, input_index: int, block: int) -> Generator:
    """The generator of one input of one block of one sample set (module docstring)."""
    return Generator(PCG64(SeedSequence(seed, spawn_key=(*stream, sample_set, input_index, block))))


def _run_task(task: tuple) -> np.ndarray:
    """One column of one block: model outputs with the groups in ``from_b`` drawn from set B."""
    model, seed, stream, out_index, block, n, from_b = task
    gens = [stream_generator(seed, stream, SET_B if k in from_b else SET_A, k, block)
            for k in range(len(model.inputs))]
    return np.asarray(model.block(gens, n), dtype=float)[out_index]


def sobol_point(f_a: np.ndarray, f_b: np.ndarray, f_ab: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(first, total) indices of each group by scipy.stats.sobol_indices (saltelli_2010) from
    outputs f_a, f_b (N,) and f_ab (D, N)."""
    from scipy.stats import sobol_indices

    n, d = f_a.size, f_ab.shape[0]
    ab = f_ab if d > 1 else np.concatenate([f_ab, f_ab])  # scipy squeezes a single group to a scalar
    res = sobol_indices(func={"f_A": f_a[None, :], "f_B": f_b[None, :], "f_AB": ab[:, None, :]}, n=n)
    return (np.atleast_1d(np.asarray(res.first_order, float))[:d],
            np.atleast_1d(np.asarray(res.total_order, float))[:d])


def bootstrap_terms(f_a: np.ndarray, f_b: np.ndarray, f_ab: np.ndarray) -> np.ndarray:
    """(N, 4 + 2D) per-unit terms whose means give the indices (``indices_from_means``): the
    outputs centred by their overall mean m, a = f_A - m, b = f_B - m, d_j = f_AB_j - f_A:
    a, b, a^2, b^2, b d_j (D columns), d_j^2 (D columns)."""
    m = 0.5 * (f_a.mean() + f_b.mean())
    a, b = f_a - m, f_b - m
    d = f_ab - f_a[None, :]
    return np.column_stack([a, b, a * a, b * b, (b[None, :] * d).T, (d * d).T])


def indices_from_means(means: np.ndarray, groups: int) -> tuple[np.ndarray, np.ndarray]:
    """(first, total) from the (R, 4 + 2D) weighted means of ``bootstrap_terms``: V = (mean a^2 +
    mean b^2)/2 - ((mean a + mean b)/2)^2, S_j = mean(b d_j)/V, S_Tj = mean(d_j^2)/(2 V)."""
    means = np.atleast_2d(means)
    var = 0.5 * (means[:, 2] + means[:, 3]) - (0.5 * (means[:, 0] + means[:, 1])) ** 2
    with np.errstate(divide="ignore", invalid="ignore"):
        first = means[:, 4:4 + groups] / var[:, None]
        total = 0.5 * means[:, 4 + groups:4 + 2 * groups] / var[:, None]
    return np.nan_to_num(first, nan=0.0, posinf=0.0, neginf=0.0), np.nan_to_num(total, nan=0.0, posinf=0.0,
                                                                                neginf=0.0)


def bootstrap_intervals(f_a: np.ndarray, f_b: np.ndarray, f_ab: np.ndarray, resamples: int, generator: Generator,
                        confidence: float = CONFIDENCE, chunk: int = 64) -> tuple[np.ndarray, ...]:
    """(first_low, first_high, total_low, total_high): percentile bootstrap intervals, units (rows
    of A, B and AB) resampled with replacement ``resamples`` times."""
    n, groups = f_a.size, f_ab.shape[0]
    terms = bootstrap_terms(f_a, f_b, f_ab)
    firsts, totals = [], []
    for start in range(0, resamples, chunk):
        r = min(chunk, resamples - start)
        counts = np.empty((r, n))
        for k in range(r):
            counts[k] = np.bincount(generator.integers(0, n, n), minlength=n)
        s, t = indices_from_means(counts @ terms / n, groups)
        firsts.append(s)
        totals.append(t)
    s, t = np.vstack(firsts), np.vstack(totals)
    q = 100 * np.array([(1 - confidence) / 2, (1 + confidence) / 2])
    s_lo, s_hi = np.percentile(s, q, axis=0)
    t_lo, t_hi = np.percentile(t, q, axis=0)
    return s_lo, s_hi, t_lo, t_hi


class InlineExecutor:
    """Runs tasks one after the other in this process; the interface of the sweep executor
    (``rvbacklash.analysis.executor``): ``map_unordered(fn, tasks, stop) -> (index, result)``."""

    def map_unordered(self, fn, tasks, stop=None):
        for i, task in enumerate(tasks):
            if stop is not None and stop.is_set():
                return
            yield i, fn(task)


class ThreadExecutor:
    """Runs tasks on ``workers`` threads of this process (default: one per core), at most two per
    thread in flight; the interface of ``InlineExecutor``. After ``stop`` is set, no task starts."""

    def __init__(self, workers: int | None = None):
        self.workers = workers or cores()

    def map_unordered(self, fn, tasks, stop=None):
        if self.workers == 1:
            yield from InlineExecutor().map_unordered(fn, tasks, stop)
            return
        todo = iter(enumerate(tasks))
        with ThreadPoolExecutor(self.workers) as pool:
            running = {}
            try:
                while True:
                    while len(running) < 2 * self.workers and not (stop is not None and stop.is_set()):
                        item = next(todo, None)
                        if item is None:
                            break
                        # a copy of this context each: a stop of the caller's window reaches the task's loops
                        running[pool.submit(contextvars.copy_context().run, fn, item[1])] = item[0]
                    if not running:
                        return
                    done, _ = wait(running, timeout=0.2, return_when=FIRST_COMPLETED)
                    for fut in done:
                        yield running.pop(fut), fut.result()
            finally:
                for fut in running:
                    fut.cancel()


def check_samples(samples) -> int:
    if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)) or \
            not MIN_SAMPLES <= samples <= MAX_SAMPLES or samples & (samples - 1):
        raise InputError("samples", samples, f"allowed: a power of two from {MIN_SAMPLES} to {MAX_SAMPLES} "
                                             f"(units per sample set; the model runs N (D + 2) times), e.g. 16384")
    return int(samples)


def stream_model(problem: Problem, model: str) -> StreamModel:
    """The StreamModel of a model name, or an InputError naming what is allowed."""
    if model in STREAM_MODELS:
        return STREAM_MODELS[model](problem)
    raise InputError("model", model, f"allowed: {', '.join(STREAM_MODELS)}")


def global_sensitivity(problem: Problem, *, model: str | StreamModel = "linear", output: str | None = None,
                       samples: int = DEFAULT_SAMPLES, seed: int = 0, stream: tuple[int, ...] = (),
                       resamples: int = DEFAULT_RESAMPLES, executor=None,
                       progress: Callable[[int], None] | None = None) -> SensitivityResult:
    """First-order and total Sobol indices of ``output`` of ``model`` for every random input group,
    with percentile-bootstrap 95 % intervals. ``samples`` N (a power of two) units per sample set;
    ``executor`` (``map_unordered``) runs the (block, column) tasks, on one thread per core by
    default (``ThreadExecutor``; the same numbers as ``InlineExecutor``); Ctrl-C keeps
    the finished blocks (the largest power of two of units) and marks the result partial."""
    started = time.perf_counter()
    n_units = check_samples(samples)
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise InputError("seed", seed, "allowed: an integer >= 0")
    if isinstance(resamples, bool) or not isinstance(resamples, (int, np.integer)) or not 100 <= resamples <= 100_000:
        raise InputError("resamples", resamples, "allowed: 100 to 100000 bootstrap resamples")
    if problem.correlated:
        listed = ", ".join(problem.design.correlation.factors)
        raise InputError("design", problem.name, f"has correlated factors ({listed}): Sobol indices assume "
                                                 f"independent inputs; allowed: a design without [correlation] "
                                                 f"(analyze's variance shares cover covariances)")
    if model == "elastic" and output in LIFE_OUTPUTS:  # the life outputs (issue 37): the elastic model with its tables
        from rvbacklash.analysis.capacity.production import life_tables
        from rvbacklash.models.elastic import elastic_model
        from rvbacklash.sampling.elastic_source import elastic_streams

        sm = elastic_streams(problem, life_tables(problem, elastic_model(problem)))
    else:
        sm = stream_model(problem, model) if isinstance(model, str) else model
    model_name = model if isinstance(model, str) else getattr(model, "name", type(model).__name__)
    names = [o.name for o in sm.outputs]
    out_name = names[0] if output is None else output
    if out_name not in names:
        raise InputError("output", out_name, f"allowed outputs of the {model_name} model: "
                                             + ", ".join(o.name for o in sm.outputs if not o.conditional))
    out_index = names.index(out_name)
    if sm.outputs[out_index].conditional:
        raise InputError("output", out_name, "is defined for some units only (conditional); Sobol indices need an "
                                             "output of every unit; allowed: " +
                         ", ".join(o.name for o in sm.outputs if not o.conditional))
    groups = [k for k, r in enumerate(sm.random) if r]
    if not groups:
        raise InputError("design", problem.name, "has no random factor; nothing to attribute")
    cols = [frozenset(), frozenset(groups)] + [frozenset({k}) for k in groups]
    sizes = [min(BLOCK, n_units - s) for s in range(0, n_units, BLOCK)]
    tasks = [(sm, int(seed), tuple(int(x) for x in stream), out_index, b, n, c)
             for b, n in enumerate(sizes) for c in cols]
    ex = executor if executor is not None else ThreadExecutor()
    results: dict[int, np.ndarray] = {}
    runs = 0
    with stop_requested() as stop:
        for index, values in ex.map_unordered(_run_task, tasks, stop=stop):
            results[index] = values
            runs += values.size
            if progress is not None:
                progress(runs)
            if stop.is_set():
                break
    per_block = len(cols)
    done = [b for b in range(len(sizes)) if all(b * per_block + c in results for c in range(per_block))]
    done_units = sum(sizes[b] for b in done if all(x in done for x in range(b)))
    partial = done_units < n_units
    if partial:
        if done_units < MIN_SAMPLES:
            raise KeyboardInterrupt
        keep = 1 << int(math.log2(done_units))
    else:
        keep = n_units
    stacked = np.concatenate([np.stack([results[b * per_block + c] for c in range(per_block)])
                              for b in range(len(sizes)) if b * BLOCK < keep], axis=1)[:, :keep]
    if not np.all(np.isfinite(stacked)):
        raise InputError("output", out_name, "is not finite for some units; allowed: an output defined for every unit")
    f_a, f_b, f_ab = stacked[0], stacked[1], stacked[2:]
    first, total = sobol_point(f_a, f_b, f_ab)
    gen = stream_generator(int(seed), tuple(int(x) for x in stream), SET_BOOTSTRAP, 0, 0)
    s_lo, s_hi, t_lo, t_hi = bootstrap_intervals(f_a, f_b, f_ab, int(resamples), gen)
    # the closed-form shares of the linear model, beside any model's indices
    linear = variance_shares(problem.sensitivities_arcmin_per_um, problem.sigmas_um)
    keys = [sm.inputs[k] for k in groups]
    lin = np.array([linear[FACTOR_KEYS.index(k)] if k in FACTOR_KEYS else np.nan for k in keys])
    lin_rank = rank_descending(np.nan_to_num(lin, nan=-1.0))
    ranks = rank_descending(total, first)
    ids = {f.key: f.id for f in CATALOG}
    rows = [GroupSensitivity(k, ids.get(k), float(first[j]), float(s_lo[j]), float(s_hi[j]), float(total[j]),
                             float(t_lo[j]), float(t_hi[j]), int(ranks[j]),
                             None if np.isnan(lin[j]) else float(lin[j]),
                             None if np.isnan(lin[j]) else int(lin_rank[j]))
            for j, k in enumerate(keys)]
    rows.sort(key=lambda g: g.rank)
    both = np.concatenate([f_a, f_b])
    notes = []
    if partial:
        notes.append(f"interrupted: {keep} of {n_units} units per set used (the largest power of two finished)")
    said = getattr(getattr(sm, "source", None), "output_warnings", None) or {}  # e.g. lost motion in a stick band
    if out_name in said:
        notes.append(f"{out_name}: {said[out_name]}")
    return SensitivityResult(problem.name, model_name, out_name, sm.outputs[out_index].unit, keep,
                             keep * (len(groups) + 2), int(seed), tuple(int(x) for x in stream), int(resamples),
                             CONFIDENCE, float(both.mean()), float(both.std()), tuple(rows),
                             time.perf_counter() - started, partial, METHOD, tuple(notes))
