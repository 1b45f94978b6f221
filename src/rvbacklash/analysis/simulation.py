"""Monte-Carlo simulation of a prepared design (Sun et al. 2014, section 4, and beyond):
problem -> model's block source -> engine -> statistics with their uncertainty; and the exact
distribution of the linear model as the same kind of result.

Models are block sources over a Problem (``MODELS``: name -> factory(problem, method, seed));
adding a model is one entry. Any callable mapping (n, 21) raw factor values [um] to n outputs
[arcmin] is accepted as well and runs through the generic (copula) path.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field, replace
from typing import Callable, Mapping

import numpy as np

from rvbacklash.analysis import statistics as st
from rvbacklash.analysis.exact import ExactDistribution, exact_distribution
from rvbacklash.analysis.statistics import OutputStatistics, Proportion, Quantile, Quantiles
from rvbacklash.errors import InputError
from rvbacklash.problem import Problem
from rvbacklash.results import EXPORT, Result
from rvbacklash.sampling.engine import MAX_SAMPLES, METHODS, BlockSource, RawRun, linear_source, run_blocks
from rvbacklash.sampling.inputs import build_input_transform

ALL_METHODS = METHODS + ("exact",)
DEFAULT_SAMPLES = 1_000_000
CONVERGENCE_QUANTILE = 0.99865


def default_workers() -> int:
    return max(1, len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1)


# --- models ----------------------------------------------------------------------------------

def _linear(problem: Problem, method: str, seed: int, stream: tuple[int, ...] = (), save_units: int = 0) -> BlockSource:
    from rvbacklash.models.linear import linear_model

    if save_units:
        raise InputError("save_units", save_units, "allowed with the contact, elastic and transmission models "
                                                   "(per-unit errors); "
                                                   "the linear model has no units to save")
    return linear_source(method, seed, build_input_transform(problem), linear_model(problem),
                         problem.sensitivities_arcmin_per_um, stream)


def _contact(problem: Problem, method: str, seed: int, stream: tuple[int, ...] = (), save_units: int = 0) -> BlockSource:
    from rvbacklash.sampling.contact_source import contact_source

    return contact_source(problem, method, seed, stream, save_units=save_units)


def _elastic(problem: Problem, method: str, seed: int, stream: tuple[int, ...] = (), save_units: int = 0) -> BlockSource:
    from rvbacklash.sampling.elastic_source import elastic_source

    return elastic_source(problem, method, seed, stream, save_units=save_units)


def _transmission(problem: Problem, method: str, seed: int, stream: tuple[int, ...] = (),
                  save_units: int = 0) -> BlockSource:
    from rvbacklash.sampling.te_source import transmission_source

    return transmission_source(problem, method, seed, stream, save_units=save_units)


def _elastic_life(problem: Problem, method: str, seed: int, stream: tuple[int, ...] = (),
                  save_units: int = 0) -> BlockSource:
    """The elastic model with the life outputs (issue 37; docs/capacity.md, "Production run")."""
    from rvbacklash.analysis.capacity.production import life_tables
    from rvbacklash.models.elastic import elastic_model
    from rvbacklash.sampling.elastic_source import elastic_source

    if method != "default":
        raise InputError("method", method, "allowed with model 'elastic': default")
    return elastic_source(problem, method, seed, stream, save_units=save_units,
                          life=life_tables(problem, elastic_model(problem)))


LIFE_OUTPUTS = ("life", "weakest_bearing_life", "rated_torque", "max_pin_stress")  # the elastic model's, when asked


# name -> factory(problem, method, seed, stream, save_units=0) of the model's block source
MODELS: dict[str, Callable[..., BlockSource]] = {"linear": _linear, "contact": _contact, "elastic": _elastic,
                                                 "transmission": _transmission}


# --- results ---------------------------------------------------------------------------------

@dataclass(frozen=True, repr=False)
class LinearReference(Result):
    """The linear model's stack-up of the same design, shown beside any sampled model."""

    mean_arcmin: float
    sigma_arcmin: float


@dataclass(frozen=True, repr=False)
class ConvergencePoint(Result):
    """Estimates of the primary output after ``samples`` samples (a power-of-two number of blocks)."""

    samples: int
    mean_arcmin: float
    mean_ci95_low_arcmin: float
    mean_ci95_high_arcmin: float
    q99865_arcmin: float | None
    q99865_ci95_low_arcmin: float | None
    q99865_ci95_high_arcmin: float | None
    yield_fraction: float | None
    yield_ci95_low: float | None
    yield_ci95_high: float | None
    q99865_bounded: bool = True  # False: too few samples to bound the quantile's interval (an end None)


@dataclass(frozen=True, repr=False)
class Curve(Result):
    """The linear model's exact distribution on a grid, drawn beside any histogram."""

    x_arcmin: tuple[float, ...]
    pdf_per_arcmin: tuple[float, ...]
    cdf: tuple[float, ...]

    def rows(self) -> list[dict]:
        return [{"x_arcmin": x, "pdf_per_arcmin": p, "cdf": c} for x, p, c in zip(self.x_arcmin, self.pdf_per_arcmin,
                                                                                 self.cdf)]


@dataclass(frozen=True, repr=False)
class SimulationResult(Result):
    """A Monte-Carlo run (or the exact distribution) of one design and model.

    ``outputs`` holds the statistics of every output quantity, the primary one first
    (``output``): rigid backlash for the linear and contact models.
    """

    design_name: str
    model: str
    method: str
    seed: int | None
    stream: tuple[int, ...]  # spawn-key prefix of the run's generators (e.g. a sweep point); () alone
    samples: int | None  # requested (None: exact)
    samples_done: int | None
    partial: bool  # interrupted (Ctrl-C): the statistics cover samples_done only
    elapsed_s: float
    outputs: dict[str, OutputStatistics]
    joint_yield: Proportion | None  # P(every given spec met at once), for more than one spec
    preload_fraction: float | None  # units whose cycloid stage is preloaded (contact and elastic models)
    linear_reference: LinearReference
    convergence: tuple[ConvergencePoint, ...]
    exact_curve: Curve | None
    # the first units of the run with their errors (save_units): (Realization, linear stages
    # [arcmin], cycloid stage [arcmin] or -preload [um]); not part of to_dict()
    units: tuple = field(default=(), metadata={EXPORT: False})
    warnings: tuple[str, ...] = ()  # what the figures need said beside them (each output's ``warning``)

    @property
    def output(self) -> OutputStatistics:
        return next(iter(self.outputs.values()))

    @property
    def mean_arcmin(self) -> float:
        return self.output.mean

    @property
    def sigma_arcmin(self) -> float:
        return self.output.sigma

    @property
    def quantiles(self) -> Quantiles:
        return self.output.quantiles

    @property
    def yield_(self) -> Proportion | None:
        return self.output.yield_

    @property
    def samples_per_s(self) -> float | None:
        return self.samples_done / self.elapsed_s if self.samples_done and self.elapsed_s > 0 else None

    def rows(self) -> list[dict]:
        """One row per statistic; every row says whether the run was interrupted (``partial``: a
        column, as in compare's CSV, so that a spreadsheet or pandas reads it as data)."""
        out = [r for o in self.outputs.values() for r in o.rows()]
        if self.joint_yield is not None:
            y = self.joint_yield
            out.append({"output": "all", "statistic": "joint yield (every spec)", "value": y.fraction,
                        "ci95_low": y.ci95_low, "ci95_high": y.ci95_high, "unit": ""})
        if self.preload_fraction is not None:
            out.append({"output": "cycloid stage", "statistic": "preloaded fraction", "value": self.preload_fraction,
                        "ci95_low": None, "ci95_high": None, "unit": ""})
        return [{**r, "partial": self.partial} for r in out]

    def summary(self) -> list[str]:
        run = "exact distribution" if self.method == "exact" else \
            f"{self.samples_done:,} samples, seed {self.seed}, method {self.method}"
        head = f"{self.design_name}, {self.model} model: {run}" + ("  [PARTIAL: interrupted]" if self.partial else "")
        lines = [head] + [line for o in self.outputs.values() for line in o.summary()]
        if self.preload_fraction is not None:
            lines.append(f"cycloid stage preloaded in {self.preload_fraction:.2%} of the units")
        return lines + [f"warning: {w}" for w in self.warnings]


# --- parameters ------------------------------------------------------------------------------

def check_run_parameters(samples, seed, method: str, spec_arcmin: float | None, quantiles, workers) -> None:
    """Every run parameter checked, naming the Python parameter."""
    if method not in ALL_METHODS:
        raise InputError("method", method, f"allowed: {', '.join(ALL_METHODS)}")
    if method != "exact":
        if samples is None or isinstance(samples, bool) or not isinstance(samples, (int, np.integer)):
            raise InputError("samples", samples, "allowed: a whole number of samples >= 1")
        if not 1 <= samples <= MAX_SAMPLES[method]:
            raise InputError("samples", samples, f"allowed: 1 <= samples <= {MAX_SAMPLES[method]:.4g} "
                                                 f"for method {method}")
        if seed is None or isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
            raise InputError("seed", seed, "allowed: an integer >= 0")
    if spec_arcmin is not None and (isinstance(spec_arcmin, bool) or not isinstance(spec_arcmin, (int, float))
                                    or not (math.isfinite(spec_arcmin) and spec_arcmin > 0)):
        raise InputError("spec_arcmin", spec_arcmin, "allowed: a finite number > 0 [arcmin]")
    for p in quantiles:
        if isinstance(p, bool) or not isinstance(p, (int, float)) or not (0 < p < 1):
            raise InputError("quantiles", p, "allowed: probabilities 0 < p < 1")
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, (int, np.integer))
                                or workers < 1):
        raise InputError("workers", workers, "allowed: a number of threads >= 1, or None for all cores")


def _quantile_set(quantiles) -> tuple[float, ...]:
    return tuple(sorted(set(float(p) for p in quantiles) | set(st.DEFAULT_QUANTILES)))


def linear_reference(problem: Problem) -> LinearReference:
    s, sd = problem.sensitivities_arcmin_per_um, problem.sigmas_um
    v = s * sd
    return LinearReference(float(s @ problem.means_um), float(math.sqrt(max(v @ problem.correlation @ v, 0.0))))


def _curve(ex: ExactDistribution, lo: float, hi: float, points: int = 400) -> Curve:
    xs = np.linspace(lo, hi, points)
    return Curve(tuple(xs.tolist()), tuple(ex.pdf(xs).tolist()), tuple(ex.cdf(xs).tolist()))


# --- runs ------------------------------------------------------------------------------------

def simulate(problem: Problem, *, samples: int = DEFAULT_SAMPLES, seed: int = 0, method: str = "default",
             spec_arcmin: float | None = None, specs: Mapping[str, float] | None = None,
             quantiles: tuple[float, ...] = (), workers: int | None = None, chunk_blocks: int = 4,
             model: str | Callable = "linear", progress: Callable[[int], None] | None = None,
             stream: tuple[int, ...] = (), error_model: str | None = None, save_units: int = 0,
             life: bool = False, wrap: Callable[[BlockSource], BlockSource] | None = None) -> SimulationResult:
    """Simulate the outputs of a prepared design.

    ``model``: a name of ``MODELS`` ("linear": Eq. (2); "contact": geometric cycloid-pin contact
    with per-pin and per-tooth errors, docs/contact.md; "elastic"; "transmission": the contact
    model's units turned through one output revolution, TE peak-to-peak, docs/transmission-error.md)
    or a callable (n, 21) [um] -> (n,) [arcmin]. ``method``: default (xoshiro256++ and the
    ziggurat for the linear model, numpy PCG64 for the contact, elastic and transmission models),
    box-muller (Eq. (8)), sobol (scrambled QMC),
    exact (the linear model's exact distribution). ``spec_arcmin`` is the upper limit of the
    primary output; ``specs`` gives limits of other outputs by name. Every method is seeded;
    seed 0 is a valid seed; ``stream`` (a tuple of integers >= 0) selects an independent stream of
    the same seed: block b draws from ``SeedSequence(seed, spawn_key=(*stream, b))``. Ctrl-C
    returns the finished blocks with ``partial=True``. ``error_model`` ("long_wave" |
    "independent") overrides the design's ``[contact]`` reading of the per-element errors;
    ``save_units`` keeps the first units with their errors (``result.units``). ``life`` (elastic
    model; implied by a spec on a life output): each unit's life, weakest bearing's life, derived
    rated torque and largest pin stress beside its precision figures (docs/capacity.md). ``wrap``:
    a function of the model's block source returning the one to run (selective assembly,
    analysis.selection).
    """
    from rvbacklash.sampling.engine import BLOCK_SIZE

    if error_model is not None:
        if error_model not in ("long_wave", "independent"):
            raise InputError("error_model", error_model, "allowed: long_wave, independent")
        if model not in ("contact", "elastic", "transmission"):
            raise InputError("error_model", error_model, "allowed with the contact or elastic model only (the "
                                                         "per-element errors it reads)")
        problem = replace(problem, contact_errors=replace(problem.contact_errors, error_model=error_model))

    if not isinstance(stream, tuple) or any(isinstance(x, bool) or not isinstance(x, (int, np.integer)) or x < 0
                                            for x in stream):
        raise InputError("stream", stream, "allowed: a tuple of integers >= 0")
    check_run_parameters(samples, seed, method, spec_arcmin, quantiles, workers)
    if isinstance(save_units, bool) or not isinstance(save_units, (int, np.integer)) or \
            not 0 <= save_units <= min(samples if method != "exact" else 0, BLOCK_SIZE):
        raise InputError("save_units", save_units, f"allowed: 0 <= save_units <= min(samples, {BLOCK_SIZE})")
    qs = _quantile_set(quantiles)
    if isinstance(model, str) and model not in MODELS:
        raise InputError("model", model, f"allowed: {', '.join(MODELS)}, or a callable (n, 21) -> (n,)")
    if method == "exact":
        if model != "linear":
            raise InputError("method", "exact", "allowed with model linear only (the exact distribution of Eq. (2))")
        return exact_result(problem, spec_arcmin=spec_arcmin, quantiles=qs)
    wants_life = life or any(k in LIFE_OUTPUTS for k in (specs or {}))
    if wants_life and model != "elastic":
        raise InputError("life", True, "allowed with model 'elastic' only (the life outputs come from its load solution)")
    if isinstance(model, str):
        factory = _elastic_life if wants_life else MODELS[model]
        source = factory(problem, method, int(seed), tuple(int(x) for x in stream), save_units=int(save_units))
        model_name = model
        if wrap is not None:
            source = wrap(source)
    else:
        source = linear_source(method, int(seed), build_input_transform(problem), model, None, tuple(stream))
        model_name = getattr(model, "__name__", "custom")
    limits = _limits(source, spec_arcmin, specs)
    primary = source.outputs[0]

    def snapshot(run: RawRun) -> ConvergencePoint:
        o = run.outputs[0]
        s = st.output_statistics(o, (CONVERGENCE_QUANTILE,), limits[0] if math.isfinite(limits[0]) else None,
                                 coarse=False)
        q = s.quantiles.table[0]
        y = s.yield_
        return ConvergencePoint(o.moments.n, s.mean, s.mean_ci95_low, s.mean_ci95_high, q.value, q.ci95_low,
                                q.ci95_high, y.fraction if y else None, y.ci95_low if y else None,
                                y.ci95_high if y else None, q.bounded)

    with np.errstate(invalid="ignore", divide="ignore"):
        raw = run_blocks(source, int(samples), limits, workers or default_workers(), chunk_blocks, progress, snapshot)
        outputs = {o.output.name: st.output_statistics(o, qs, lim if math.isfinite(lim) else None, raw.samples)
                   for o, lim in zip(raw.outputs, limits)}
    said = dict(getattr(source, "output_warnings", None) or {})  # e.g. a lost motion read in a stick band
    outputs = {k: replace(o, warning=said[k]) if k in said else o for k, o in outputs.items()}
    n_specs = sum(math.isfinite(x) for x in limits)
    joint = Proportion.sampled(raw.n_joint_pass, raw.samples) if n_specs > 1 and raw.samples else None
    preloaded = outputs.get("preload")  # conditional: its samples are the preloaded units
    preload = preloaded.samples / raw.samples if preloaded is not None and raw.samples else None
    curve = None
    if primary.unit == "arcmin":  # the linear model's exact distribution, drawn beside any sampled model
        try:
            hist = outputs[primary.name].histogram
            curve = _curve(exact_distribution(problem), hist.edges[0], hist.edges[-1])
        except InputError:  # correlated non-normal inputs: no exact curve
            pass
    return SimulationResult(problem.name, model_name, method, int(seed), tuple(int(x) for x in stream), int(samples),
                            raw.samples, raw.partial,
                            raw.elapsed_s, outputs, joint, preload, linear_reference(problem),
                            tuple(raw.convergence), curve,
                            tuple(source.saved_units()) if save_units else (),
                            tuple(dict.fromkeys(said.values())))


def _limits(source: BlockSource, spec_arcmin: float | None, specs: Mapping[str, float] | None) -> tuple[float, ...]:
    names = [o.name for o in source.outputs]
    given = dict(specs or {})
    for name, value in given.items():
        if name not in names:
            raise InputError("specs", name, f"allowed outputs of this model: {', '.join(names)}")
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise InputError(f"specs[{name!r}]", value, "allowed: a finite number")
    if spec_arcmin is not None:
        given[names[0]] = spec_arcmin
    return tuple(float(given[o.name]) if o.name in given else (math.inf if o.upper_limit else -math.inf)
                 for o in source.outputs)


def exact_result(problem: Problem, *, spec_arcmin: float | None = None,
                 quantiles: tuple[float, ...] = ()) -> SimulationResult:
    """The linear model's exact output distribution as a SimulationResult (method "exact")."""
    check_run_parameters(None, None, "exact", spec_arcmin, quantiles, None)
    ex = exact_distribution(problem)
    qs = _quantile_set(quantiles)
    values = ex.ppf(np.array(qs))
    table = tuple(Quantile(p, float(v), float(v), float(v)) for p, v in zip(qs, values))
    y = cp = cpk = ppm = None
    if spec_arcmin is not None:
        frac = float(ex.cdf(spec_arcmin))
        y = Proportion.exact(frac)
        cp, cpk = st.process_capability(ex.mean, ex.std, spec_arcmin)
        ppm = (1 - frac) * 1e6
    lo, hi = (float(v) for v in ex.ppf(np.array([1e-6, 1 - 1e-6])))
    if not hi > lo:
        lo, hi = ex.mean - 1.0, ex.mean + 1.0
    edges = np.linspace(lo, hi, 201)
    centres = 0.5 * (edges[1:] + edges[:-1])
    hist = st.HistogramData("arcmin", tuple(edges.tolist()), None, tuple(ex.pdf(centres).tolist()), None, None)
    out = OutputStatistics("backlash", "arcmin", "output backlash (rigid lost motion)", None, ex.mean, ex.mean,
                           ex.mean, ex.std, None, None, Quantiles("arcmin", table), spec_arcmin, True, y, ppm, cp,
                           cpk, float(ex.cdf(0.0)), hist)
    return SimulationResult(problem.name, "linear", "exact", None, (), None, None, False, 0.0, {"backlash": out}, None,
                            None, LinearReference(ex.mean, ex.std), (), _curve(ex, lo, hi))
