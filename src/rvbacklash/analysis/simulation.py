"""Monte-Carlo simulation of a design's output backlash (Sun et al. 2014, section 4, and
beyond): design -> factor distributions -> engine -> statistics with their uncertainty."""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from rvbacklash.analysis import statistics as st
from rvbacklash.analysis.exact import exact_distribution
from rvbacklash.analysis.stackup import analyze
from rvbacklash.design.derived import resolve_zones
from rvbacklash.design.schema import Design
from rvbacklash.errors import InputError
from rvbacklash.factors.catalog import FACTOR_KEYS
from rvbacklash.model.contact import ContactGeometry
from rvbacklash.model.linear import build_linear_model
from rvbacklash.sampling.contact_source import make_contact_source
from rvbacklash.sampling.distributions import correlation_matrix
from rvbacklash.sampling.engine import MAX_SAMPLES, METHODS, make_block_source, run_blocks
from rvbacklash.sampling.inputs import build_input_transform

ALL_METHODS = METHODS + ("exact",)


def default_workers() -> int:
    return max(1, len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1)


@dataclass
class SimulationResult:
    design_name: str
    method: str
    seed: int | None
    samples: int | None
    model: str
    stats: dict
    histogram: dict
    analytic: dict
    convergence: list[dict] = field(default_factory=list)
    partial: bool = False
    elapsed_s: float = 0.0
    exact_curve: dict | None = None  # x, pdf, cdf of the exact distribution (linear model)

    def to_dict(self) -> dict:
        s = self.stats
        return {
            "design": self.design_name, "model": self.model, "method": self.method,
            "samples": self.samples, "seed": self.seed, "partial": self.partial,
            **{k: v for k, v in s.items()},
            "histogram": self.histogram, "convergence": self.convergence,
            "analytic": self.analytic, "elapsed_s": self.elapsed_s,
            "samples_per_s": (s.get("samples_done") or 0) / self.elapsed_s if self.elapsed_s > 0 else None,
        }

    def rows(self) -> list[dict]:
        """The statistics as table rows: statistic, value, 95 % interval."""
        s = self.stats

        def row(name, value, ci=(None, None)):
            return {"statistic": name, "value": value, "ci95_low": ci[0], "ci95_high": ci[1]}

        out = [row("mean_arcmin", s["mean_arcmin"], s["mean_ci95"]), row("std_arcmin", s["std_arcmin"])]
        out += [row(f"quantile_{p}_arcmin", q["value"], q["ci95"]) for p, q in s["quantiles"].items()]
        if s.get("yield") is not None:
            out.append(row("yield", s["yield"]["fraction"], s["yield"]["ci95"]))
            out += [row(k, s[k]) for k in ("ppm_out", "cp", "cpk")]
        out.append(row("interference_fraction", s["interference_fraction"]))
        return out

    def to_frame(self):
        """The statistics as a pandas DataFrame indexed by statistic (needs pandas)."""
        from rvbacklash.frames import to_frame

        return to_frame(self.rows(), index="statistic")


def check_run_parameters(samples: int | None, seed: int | None, method: str, spec_arcmin: float | None,
                         quantiles: tuple[float, ...]) -> None:
    if method not in ALL_METHODS:
        raise InputError("--method", method, f"allowed: {', '.join(ALL_METHODS)}")
    if method != "exact":
        if samples is None or isinstance(samples, bool) or not isinstance(samples, (int, np.integer)):
            raise InputError("--samples", samples, "allowed: a whole number of samples >= 1")
        if not 1 <= samples <= MAX_SAMPLES[method]:
            raise InputError("--samples", samples, f"allowed: 1 <= samples <= {MAX_SAMPLES[method]:.4g} "
                                                   f"for method {method}")
        if seed is None or isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
            raise InputError("--seed", seed, "allowed: an integer >= 0")
    if spec_arcmin is not None and not (math.isfinite(spec_arcmin) and spec_arcmin > 0):
        raise InputError("--spec-arcmin", spec_arcmin, "allowed: a finite number > 0 [arcmin]")
    for p in quantiles:
        if not (0 < p < 1):
            raise InputError("--quantile", p, "allowed: 0 < p < 1")


MODELS = ("linear", "contact")


def simulate(design: Design, samples: int | None = None, seed: int | None = None, method: str = "default",
             spec_arcmin: float | None = None, quantiles: tuple[float, ...] = st.DEFAULT_QUANTILES,
             workers: int | None = None, chunk_blocks: int = 4, model: str | Callable = "linear",
             progress: Callable[[int], None] | None = None) -> SimulationResult:
    """Simulate the output backlash [arcmin] of ``design``.

    ``model``: "linear" (Eq. (2)), "contact" (geometric cycloid-pin contact with per-pin and
    per-tooth errors, docs/contact.md), or any callable mapping (n, 21) raw factor values [um]
    to n outputs [arcmin]. ``method``: default (numpy PCG64), box-muller (Eq. (8)), sobol
    (scrambled QMC), exact (convolution, linear model only). Every method is seeded; seed 0
    is a valid seed.
    """
    quantiles = tuple(sorted(set(quantiles) | set(st.DEFAULT_QUANTILES)))
    if isinstance(model, str) and model not in MODELS:
        raise InputError("--model", model, f"allowed: {', '.join(MODELS)}")
    check_run_parameters(samples, seed, method, spec_arcmin, quantiles)
    linear = build_linear_model(design)
    model_name = model if isinstance(model, str) else getattr(model, "__name__", "custom")
    stack = analyze(design, linear)
    analytic = {"model": "linear", "mean_arcmin": stack.total.mean_arcmin, "sigma_arcmin": stack.total.sigma_arcmin}
    zones = resolve_zones(design)
    corr = correlation_matrix(design.correlation, FACTOR_KEYS)
    spec_or_inf = spec_arcmin if spec_arcmin is not None else math.inf

    if method == "exact":
        if model != "linear":
            raise InputError("--method", "exact", "the exact distribution exists for the linear model only")
        return _exact_result(design.name, linear, zones, corr, spec_arcmin, quantiles, analytic)

    if model == "contact":
        source = make_contact_source(method, int(seed), ContactGeometry.from_design(design), zones,
                                     linear.sensitivities_arcmin_per_um, not np.allclose(corr, np.eye(len(corr))))
    else:
        fn = linear if model == "linear" else model
        source = make_block_source(method, int(seed), build_input_transform(zones, corr), fn,
                                   linear.sensitivities_arcmin_per_um if model == "linear" else None)

    def snapshot(m, hist) -> dict:
        s = st.summary(m, hist, spec_or_inf, (0.99865,))
        q = s["quantiles"]["0.99865"]
        return {"samples": m.n, "mean_arcmin": s["mean_arcmin"], "mean_ci95": s["mean_ci95"],
                "q99865_arcmin": q["value"], "q99865_ci95": q["ci95"],
                "yield": s["yield"]["fraction"] if spec_arcmin is not None else None,
                "yield_ci95": s["yield"]["ci95"] if spec_arcmin is not None else None}

    raw = run_blocks(source, int(samples), spec_or_inf, workers or default_workers(), chunk_blocks,
                     progress, snapshot)
    stats = st.summary(raw.moments, raw.histogram, spec_or_inf, quantiles)
    if spec_arcmin is None:
        stats.update({"spec_arcmin": None, "yield": None, "ppm_out": None, "cp": None, "cpk": None})
    hist = st.coarse_histogram(raw.histogram, raw.moments.n)
    curve = None  # the linear model's exact distribution, drawn beside any sampled model
    try:
        ex = exact_distribution(linear.sensitivities_arcmin_per_um, zones, corr)
        xs = np.linspace(hist["edges"][0], hist["edges"][-1], 400)
        curve = {"x": xs.tolist(), "pdf": ex.pdf(xs).tolist(), "cdf": ex.cdf(xs).tolist()}
    except InputError:  # correlated non-normal inputs: no exact curve
        pass
    return SimulationResult(design.name, method, int(seed), int(samples), model_name, stats, hist, analytic,
                            raw.convergence, raw.partial, raw.elapsed_s, curve)


def _exact_result(name, linear, zones, corr, spec, quantiles, analytic) -> SimulationResult:
    ex = exact_distribution(linear.sensitivities_arcmin_per_um, zones, corr)
    qs = {f"{p:g}": {"value": float(ex.ppf(p)), "ci95": [float(ex.ppf(p))] * 2} for p in quantiles}
    stats = {"samples_done": None, "mean_arcmin": ex.mean, "mean_ci95": [ex.mean, ex.mean], "std_arcmin": ex.std,
             "min_arcmin": None, "max_arcmin": None, "quantiles": qs, "spec_arcmin": spec,
             "yield": None, "ppm_out": None, "cp": None, "cpk": None,
             "interference_fraction": float(ex.cdf(0.0))}
    if spec is not None:
        frac = float(ex.cdf(spec))
        cp, cpk = st.process_capability(ex.mean, ex.std, spec)
        stats.update({"yield": {"fraction": frac, "ci95": [frac, frac], "count": None},
                      "ppm_out": (1 - frac) * 1e6, "cp": cp, "cpk": cpk})
    lo, hi = float(ex.ppf(1e-6)), float(ex.ppf(1 - 1e-6))
    if hi <= lo:
        lo, hi = ex.mean - 1.0, ex.mean + 1.0
    edges = np.linspace(lo, hi, 201)
    centres = 0.5 * (edges[1:] + edges[:-1])
    hist = {"edges": edges.tolist(), "counts": None, "density": ex.pdf(centres).tolist(),
            "underflow": None, "overflow": None}
    xs = np.linspace(lo, hi, 400)
    curve = {"x": xs.tolist(), "pdf": ex.pdf(xs).tolist(), "cdf": ex.cdf(xs).tolist()}
    return SimulationResult(name, "exact", None, None, "linear", stats, hist, analytic, [], False, 0.0, curve)
