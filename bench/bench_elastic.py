"""Elastic-model Monte-Carlo benchmark beside the rigid contact model: prints figures, asserts nothing.

    .venv/bin/python bench/bench_elastic.py [--samples 1e5] [--units 20000]

1. per-unit evaluation (``models.elastic.evaluate_units``: each unit's loop at the ten torques the
   definitions read) on pre-drawn units, all cores (numba, nogil, one thread per core);
2. the elastic model end to end through the engine (the contact model's compiled drawing + evaluation);
3. the rigid contact model through the engine in the same run.
Each is timed after a warm-up run (compilation or cache load outside the timing).
"""

from __future__ import annotations

import argparse
import time
from concurrent.futures import ThreadPoolExecutor

import numpy as np


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--samples", type=float, default=1e5, help="units of the end-to-end runs")
    ap.add_argument("--units", type=int, default=20000, help="pre-drawn units of the evaluation benchmark")
    ap.add_argument("--tiny", action="store_true", help="tiny sizes: the test suite runs every bench so none rots")
    a = ap.parse_args()
    if a.tiny:
        a.samples, a.units = 64, 64
    from rvbacklash import prepare, simulate
    from rvbacklash.analysis.simulation import default_workers
    from rvbacklash.models.elastic import elastic_model, loop_design
    from rvbacklash.sampling.elastic_source import design_pin_laws, evaluate_batch, sample_units

    problem = prepare("rv80e")
    model = elastic_model(problem)
    workers = default_workers()
    n = int(a.samples)

    sample_units(problem, 1, 10)  # compile / load the drawing kernel
    t = time.perf_counter()
    units = sample_units(problem, 1, a.units)
    draw = a.units / (time.perf_counter() - t)
    rigid = elastic_model(prepare(problem.design.model_copy(update={"structure": None})))
    designs = {id(model): loop_design(model, design_pin_laws(model)),  # as the engine's source has them
               id(rigid): loop_design(rigid, design_pin_laws(rigid))}
    evaluate_batch(designs[id(model)], units.take(slice(0, 10)))  # compile / load
    parts = np.array_split(np.arange(a.units), workers)

    def run(idx, m=model):
        return evaluate_batch(designs[id(m)], units.take(idx))

    t = time.perf_counter()
    with ThreadPoolExecutor(workers) as pool:
        list(pool.map(run, parts))
    evaluation = a.units / (time.perf_counter() - t)
    t = time.process_time()
    run(np.arange(min(a.units, 5000)))
    cpu = min(a.units, 5000) / (time.process_time() - t)
    t = time.process_time()
    run(np.arange(min(a.units, 5000)), rigid)
    cpu_rigid = min(a.units, 5000) / (time.process_time() - t)

    simulate(problem, samples=min(n, 2000), seed=0, model="elastic")
    t = time.perf_counter()
    simulate(problem, samples=n, seed=1, model="elastic")
    elastic = n / (time.perf_counter() - t)
    simulate(problem, samples=min(n, 1 << 16), seed=0, model="contact")
    t = time.perf_counter()
    simulate(problem, samples=n, seed=1, model="contact")
    contact = n / (time.perf_counter() - t)

    print(f"rv80e, {problem.cycloid.zp} pins x {problem.cycloid.discs} discs, {workers} threads")
    print(f"elastic, per-unit evaluation ({a.units} pre-drawn units):     {evaluation:10,.0f} units/s "
          f"({cpu:,.0f} units/s per core of CPU time)")
    print(f"elastic, structure rigid (no [structure]), per core of CPU time: {cpu_rigid:10,.0f} units/s")
    print(f"elastic, drawing only (compiled, with the gaps, 1 thread):    {draw:10,.0f} units/s")
    print(f"elastic, end to end through the engine ({n} units):       {elastic:10,.0f} units/s")
    print(f"contact (rigid), end to end through the engine ({n} units): {contact:10,.0f} units/s")


if __name__ == "__main__":
    main()
