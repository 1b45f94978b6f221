"""The production run over the service life (docs/service-life.md): every unit of a seeded run of the
elastic model, read at each time of the nominal unit's trajectory with its wear added to its own gaps
(at its own pins' phases) and to its crank bearings' clearance, gives its lost motion over the hours,
its accuracy life (the hours until its lost motion exceeds the spec, linear between the trajectory's
times) and the run's yield against the spec at every time.

Each unit's own wear (``own_wear``, the default): the nominal unit's wear corrected, step by step, by
the unit's own loads re-solved on its own worn gaps (``units``: what the correction reads and leaves
out). ``own_wear=False``: every unit wears as the nominal unit does (the capacity production run's
shortcut).
"""

from __future__ import annotations

import math
from typing import Callable

import numpy as np

from rvbacklash.analysis.service_life.results import ProductionLife
from rvbacklash.analysis.service_life.stepping import Trajectory
from rvbacklash.analysis.service_life.units import NominalAtAngles, worn_units
from rvbacklash.analysis.service_life.worn import worn_model
from rvbacklash.analysis.statistics import Proportion
from rvbacklash.errors import InputError
from rvbacklash.interrupt import mark_progress, stop_requested
from rvbacklash.models.elastic import ElasticModel, elastic_model, evaluate_units, loop_design
from rvbacklash.problem import Problem
from rvbacklash.sampling.elastic_source import design_pin_laws, sample_units

MAX_UNITS = 10_000_000
CHUNK = 4096  # units evaluated at a time (bounded memory)
QUANTILES = (0.05, 0.5, 0.95)


def accuracy_life_h(hours: np.ndarray, lost_motion: np.ndarray, spec: float) -> np.ndarray:
    """Each unit's accuracy life [h]: the first time its lost motion exceeds ``spec``, linear between
    the times ``hours`` (T,) of ``lost_motion`` (T, n); 0 when out at the first time, inf when in at
    the last."""
    out = np.full(lost_motion.shape[1], math.inf)
    over = lost_motion > spec
    first = np.where(over.any(axis=0), over.argmax(axis=0), -1)
    for i in np.nonzero(first >= 0)[0]:
        k = first[i]
        if k == 0:
            out[i] = hours[0]
            continue
        a, b = lost_motion[k - 1, i], lost_motion[k, i]
        frac = (spec - a) / (b - a) if b != a else 1.0
        out[i] = hours[k - 1] + frac * (hours[k] - hours[k - 1])
    return out


def step_designs(problem: Problem, trajectory: Trajectory, model: ElasticModel) -> list:
    """Each time's LoopDesign: the worn flank's curvature in the pins' laws (``worn.worn_model``)."""
    designs = []
    for wear in trajectory.wear:
        m = worn_model(problem, model, wear)
        designs.append(loop_design(m, design_pin_laws(m)) if m is not model or not designs else designs[0])
    return designs


def units_lost_motion(problem: Problem, trajectory: Trajectory, *, samples: int, seed: int,
                      model: ElasticModel | None = None, own_wear: bool = True, stream: tuple[int, ...] = (1,),
                      progress: Callable[[int], None] | None = None) -> tuple[np.ndarray, int, bool]:
    """(lost motion (T, units done) [arcmin] of ``samples`` units of the elastic model (seed ``seed``,
    ``stream``: the spawn key of their draws) at every time of the nominal ``trajectory``, units done,
    partial): each unit with its own wear (``own_wear``) or the nominal unit's (module docstring);
    ``progress`` receives the units done (each unit counts once all its times are read)."""
    if not (isinstance(samples, int) and 1 <= samples <= MAX_UNITS):
        raise InputError("samples", samples, f"allowed: an integer from 1 to {MAX_UNITS:,}")
    model = model or elastic_model(problem)
    designs = step_designs(problem, trajectory, model)
    nominal = NominalAtAngles(problem) if own_wear else None
    lm = np.empty((len(trajectory.hours), samples))
    done = 0
    partial = False
    with stop_requested() as stop:
        units = sample_units(problem, seed, samples, stream)
        for start in range(0, samples, CHUNK):
            if stop.is_set():
                partial = True
                break
            chunk = units.take(slice(start, start + CHUNK))
            out = np.empty((3, chunk.chi_rad.size))
            for k, worn in worn_units(chunk, trajectory, designs, nominal):
                evaluate_units(worn, designs[k], out)
                lm[k, start:start + chunk.chi_rad.size] = out[0]
            done = start + chunk.chi_rad.size
            mark_progress()
            if progress is not None:
                progress(done)
    return lm[:, :done], done, partial


def production_life(problem: Problem, trajectory: Trajectory, hours, *, samples: int, seed: int,
                    spec_lost_motion_arcmin: float, model: ElasticModel | None = None, own_wear: bool = True,
                    progress: Callable[[int], None] | None = None) -> ProductionLife:
    """The ProductionLife of ``samples`` units of the elastic model (seed ``seed``) along the
    nominal trajectory, each with its own wear (``own_wear``) or the nominal unit's (module
    docstring); ``hours``: the hours to report (times of the trajectory); ``progress`` receives the
    units done (each unit counts once all its times are read)."""
    if not (isinstance(samples, int) and 1 <= samples <= MAX_UNITS):
        raise InputError("samples", samples, f"allowed: an integer from 1 to {MAX_UNITS:,}")
    if not (math.isfinite(spec_lost_motion_arcmin) and spec_lost_motion_arcmin > 0.0):
        raise InputError("spec_lost_motion_arcmin", spec_lost_motion_arcmin, "allowed: a number > 0")
    times = np.array(trajectory.hours)
    lm, done, partial = units_lost_motion(problem, trajectory, samples=samples, seed=seed, model=model,
                                          own_wear=own_wear, progress=progress)
    spec = float(spec_lost_motion_arcmin)
    life = accuracy_life_h(times, lm, spec)
    n = max(done, 1)
    grid_yield = tuple(float((lm[k] <= spec).sum() / n) for k in range(times.size))
    grid_q = tuple(tuple(float(v) for v in np.quantile(lm[k], QUANTILES)) if done else (math.nan,) * 3
                   for k in range(times.size))
    index = [int(np.argmin(np.abs(times - h))) for h in hours]
    yields = tuple(Proportion.sampled(int((lm[k] <= spec).sum()), done) for k in index)
    life_q = {f"{q:.0%}": float(np.quantile(life, q, method="inverted_cdf")) if done else math.nan
              for q in QUANTILES}
    return ProductionLife(done, int(seed), "own" if own_wear else "nominal", spec, tuple(float(h) for h in hours), yields,
                          tuple(grid_q[k] for k in index), life_q, int((lm[0] > spec).sum()) if done else 0,
                          int((lm[-1] <= spec).sum()) if done else 0, tuple(float(t) for t in times), grid_yield,
                          grid_q, partial, Proportion.sampled(int(np.isinf(life).sum()), done) if done else None)
