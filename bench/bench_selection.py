"""Selective assembly's added time on a production run (issue 39: at most 20 %), side by side in one
run: prints figures, asserts nothing.

    .venv/bin/python bench/bench_selection.py [--samples 20000] [--repeats 3]

The elastic model's run of rv80e at random and with ``pins=5x2um,rollers=3x2um,noise=0.5um`` (the
same units), alternated ``repeats`` times after a warm-up of both (compilation or cache load outside
the timing); CPU time (user + sys of this process: the machine's wall time drifts under other work)
and wall time, the best of the repeats. The drawing alone (where selection's work is: one more
``unit_gaps`` per unit and the rules) is timed the same way.
"""

from __future__ import annotations

import argparse
import os
import time


def cpu() -> float:
    t = os.times()
    return t.user + t.system


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--samples", type=float, default=20000)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--tiny", action="store_true", help="tiny sizes: the test suite runs every bench so none rots")
    a = ap.parse_args()
    if a.tiny:
        a.samples, a.repeats = 64, 1
    import numpy as np

    from rvbacklash import prepare
    from rvbacklash.analysis.selection.classes import parse_selection
    from rvbacklash.analysis.selection.source import (draw_selected_kernel, empty_record, measurement_errors,
                                                      selected_source, selection_tables)
    from rvbacklash.analysis.simulation import simulate
    from rvbacklash.sampling.contact_source import block_streams, saved_units
    from rvbacklash.sampling.elastic_source import draw_units, elastic_source, empty_batch

    problem = prepare("rv80e")
    n = int(a.samples)
    selection = parse_selection("pins=5x2um,rollers=3x2um,noise=0.5um")
    spec = {"lost_motion": 1.0}

    def random_run():
        return simulate(problem, samples=n, seed=1, model="elastic", specs=spec)

    def selected_run():
        return simulate(problem, samples=n, seed=1, model="elastic", specs=spec, wrap=selected_source(selection))

    src = elastic_source(problem, "default", 1)
    c, g = src.contact, src.contact.geometry
    tables = selection_tables(src, selection)

    def draw_random():
        draw_units(c, block_streams(c.seed, 0, c.stream), n)

    def draw_selected():
        record = empty_record(measurement_errors(1, (), 0, n, selection.noise_um))
        draw_selected_kernel(block_streams(c.seed, 0, c.stream), c.laws, g.stage_geometry, c.coef,
                             empty_batch(n, g.discs, g.zp), saved_units(0, g), tables, record)

    for f in (random_run, selected_run, draw_random, draw_selected):  # warm-up: compile or load
        f() if f in (draw_random, draw_selected) else simulate(problem, samples=min(n, 256), seed=0, model="elastic",
                                                                 specs=spec, wrap=selected_source(selection)
                                                                 if f is selected_run else None)
    best = {}
    for _ in range(a.repeats):
        for name, f in (("random", random_run), ("selected", selected_run), ("draw random", draw_random),
                        ("draw selected", draw_selected)):
            c0, w0 = cpu(), time.perf_counter()
            f()
            c1, w1 = cpu() - c0, time.perf_counter() - w0
            b = best.get(name, (np.inf, np.inf))
            best[name] = (min(b[0], c1), min(b[1], w1))
    print(f"rv80e, elastic model, {n} units, best of {a.repeats} alternated runs; selection {selection}")
    for name in ("random", "selected", "draw random", "draw selected"):
        print(f"{name:14s} CPU {best[name][0]:8.2f} s   wall {best[name][1]:8.2f} s")
    for what, r, s in (("production run", "random", "selected"), ("drawing", "draw random", "draw selected")):
        added = best[s][0] / best[r][0] - 1 if best[r][0] > 0 else float("nan")
        print(f"selection adds to the {what}: {added * 100:+.1f} % CPU "
              f"({best[s][1] / best[r][1] * 100 - 100:+.1f} % wall)")


if __name__ == "__main__":
    main()
