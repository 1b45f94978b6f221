"""Transmission-error benchmark: prints figures, asserts nothing.

    .venv/bin/python bench/bench_te.py [--samples 1e4] [--tiny]

Rates are given in wall time and in CPU time (units per CPU-second): on a shared machine the wall
time measures the load, the CPU time the code.

1. the production run end to end (``simulate --model transmission``: draw, turn every unit through
   one output revolution at 8 z_p positions, reduce), units/s on all cores, rv80e;
2. the evaluation kernel alone on one thread, per unit and per output position;
3. one unit's curve on the exact geometry (``transmission-error``: 1024 positions, both flanks and
   the error-free reference), ms.
"""

from __future__ import annotations

import argparse
import time


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--samples", type=float, default=1e4)
    ap.add_argument("--tiny", action="store_true", help="tiny sizes: the test suite runs every bench so none rots")
    a = ap.parse_args()
    if a.tiny:
        a.samples = 64
    import numpy as np

    import rvbacklash as rb
    from rvbacklash.analysis.simulation import default_workers
    from rvbacklash.analysis.transmission import perfect_unit, revolution, transmission_error
    from rvbacklash.sampling.te_source import te_streams, transmission_source

    p = rb.prepare("rv80e")
    n = int(a.samples)
    rb.simulate(p, samples=16, seed=0, model="transmission")  # compile / load the kernels
    t, c = time.perf_counter(), time.process_time()
    r = rb.simulate(p, samples=n, seed=1, model="transmission", specs={"transmission_error": 60.0})
    rate = n / (time.perf_counter() - t)
    cpu_rate = n / max(time.process_time() - c, 1e-9)
    te = r.outputs["transmission_error"]
    print(f"TE production run end to end (rv80e, {default_workers()} threads): {rate:8.0f} units/s "
          f"({cpu_rate:.0f} units per CPU-second; TE p-p mean {te.mean:.1f} arcsec, yield at 60 arcsec {te.yield_.fraction:.1%})")
    src = transmission_source(p, "default", 2)
    m = max(16, min(n, 512))
    batch = src._draw(te_streams(2, 0), m)
    out = np.empty((3, m))
    t = time.perf_counter()
    src._evaluate(batch, out)
    dt = (time.perf_counter() - t) / m
    positions = src.table.theta_rad.size
    print(f"evaluation kernel, one thread: {dt * 1e3:8.3f} ms/unit, {dt / positions * 1e6:6.2f} us/position "
          f"({positions} positions)")
    unit = perfect_unit(p)
    revolution(p, unit, 1024)
    t = time.perf_counter()
    revolution(p, unit, 1024)
    curve = time.perf_counter() - t
    transmission_error(p, unit, "nominal", 1024, shares=False)  # the design's reference: computed once, cached
    t = time.perf_counter()
    transmission_error(p, unit, "nominal", 1024, shares=False)
    print(f"one unit's curve, exact geometry, 1024 positions: {curve * 1e3:8.1f} ms (kernel); "
          f"{(time.perf_counter() - t) * 1e3:8.1f} ms through the API (the design's reference cached, the figures)")


if __name__ == "__main__":
    main()
