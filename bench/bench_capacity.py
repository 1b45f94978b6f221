"""The life outputs' cost in an elastic production run (issue 37): prints figures, asserts nothing.

    .venv/bin/python bench/bench_capacity.py [--units 20000] [--repeats 3] [--samples 1e5]

1. per-unit evaluation of the same pre-drawn units, one thread, CPU time: the elastic model's loop
   alone (``evaluate_batch``) and with the life outputs (``evaluate_batch(..., life=tables)``),
   alternated ``--repeats`` times, side by side (this machine drifts +-10 % between runs);
2. the per-design tables the life reads (``analysis.capacity.production.life_tables``): built once
   per design (then from the disk cache), timed apart;
3. end to end through the engine, all threads: ``simulate --model elastic`` without and with
   ``life=True`` (tables already built), alternated.
The issue's target: the life outputs add at most 30 % to an elastic production run's time.
"""

from __future__ import annotations

import argparse
import time


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--units", type=int, default=20000, help="pre-drawn units of the per-unit comparison")
    ap.add_argument("--repeats", type=int, default=3, help="alternations of the two evaluations")
    ap.add_argument("--samples", type=float, default=1e5, help="units of the end-to-end runs")
    ap.add_argument("--tiny", action="store_true", help="tiny sizes: the test suite runs every bench so none rots")
    a = ap.parse_args()
    if a.tiny:
        a.units, a.repeats, a.samples = 64, 1, 64
    from rvbacklash import prepare, simulate
    from rvbacklash.analysis.capacity.production import _compute, life_tables
    from rvbacklash.models.elastic import elastic_model
    from rvbacklash.sampling.elastic_source import elastic_source, evaluate_batch, sample_units

    problem = prepare("rv80e")
    model = elastic_model(problem)
    tables = life_tables(problem, model)  # compile the kernels it runs (and fill the cache)
    t = time.perf_counter()
    _compute(problem, model)  # what an empty cache costs
    build = time.perf_counter() - t
    source = elastic_source(problem, "default", 1)
    units = sample_units(problem, 1, a.units)
    evaluate_batch(source.design, units.take(slice(0, 8)))  # compile / load both kernels outside the timing
    evaluate_batch(source.design, units.take(slice(0, 8)), tables)
    plain, life = [], []
    for _ in range(a.repeats):
        for runs, tab in ((plain, None), (life, tables)):
            t = time.process_time()
            evaluate_batch(source.design, units, tab)
            runs.append((time.process_time() - t) / a.units * 1e6)
    n = int(a.samples)
    simulate(problem, samples=min(n, 2000), seed=0, model="elastic")
    simulate(problem, samples=min(n, 2000), seed=0, model="elastic", life=True)
    e2e_plain, e2e_life = [], []
    for _ in range(a.repeats):
        for runs, with_life in ((e2e_plain, False), (e2e_life, True)):
            t = time.perf_counter()
            simulate(problem, samples=n, seed=1, model="elastic", life=with_life)
            runs.append(n / (time.perf_counter() - t))
    best_plain, best_life = min(plain), min(life)
    print(f"rv80e, {a.units} pre-drawn units, one thread, CPU time per unit, {a.repeats} alternations:")
    print(f"elastic loop alone:           {' / '.join(f'{v:.2f}' for v in plain)} us (best {best_plain:.2f})")
    print(f"elastic loop + life outputs:  {' / '.join(f'{v:.2f}' for v in life)} us (best {best_life:.2f})")
    print(f"life outputs add:             {100 * (best_life / best_plain - 1):.1f} % per unit (target <= 30 %)")
    print(f"life tables, once per design: {build:.2f} s wall (then from the memory or disk cache: 0)")
    print(f"end to end, {n} units:  elastic {' / '.join(f'{v:,.0f}' for v in e2e_plain)} units/s;  with life "
          f"{' / '.join(f'{v:,.0f}' for v in e2e_life)} units/s")


if __name__ == "__main__":
    main()
