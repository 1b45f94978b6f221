"""Contact-model Monte-Carlo benchmark: prints figures, asserts nothing.

    .venv/bin/python bench/bench_contact.py [--samples 1e6]

1. engine units/s of the contact model on the rv80e example (40 pins, 2 discs, every part with its
   own errors, all cores), under both readings of the per-element errors;
2. numpy alone generating the same number of random inputs per unit (independent reading: about
   262 draws), in chunks, one thread;
3. the exact play (scipy root finding on the compiled exact gaps) per unit, for scale.
"""

from __future__ import annotations

import argparse
import time

import numpy as np


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--samples", type=float, default=1e6)
    ap.add_argument("--tiny", action="store_true", help="tiny sizes: the test suite runs every bench so none rots")
    a = ap.parse_args()
    m, exact_units = 200_000, 200
    if a.tiny:
        a.samples, m, exact_units = 256, 1000, 5
    import rvbacklash as rb
    from rvbacklash.analysis.simulation import default_workers
    from rvbacklash.models.contact import exact_play

    p = rb.prepare("rv80e")
    g = p.cycloid
    draws = 1 + 11 + 2 + 4 * g.zp + g.discs * (5 + g.zc)
    n = int(a.samples)
    for em in ("long_wave", "independent"):
        rb.simulate(p, samples=min(n, 1 << 16), seed=0, model="contact", error_model=em)  # compile / load the kernels
        t = time.perf_counter()
        r = rb.simulate(p, samples=n, seed=1, model="contact", spec_arcmin=3.0, error_model=em)
        rate = n / (time.perf_counter() - t)
        print(f"contact engine, {em:11s} (rv80e, {g.zp} pins, {g.discs} discs, {default_workers()} threads): "
              f"{rate / 1e3:8.1f} k units/s  (preloaded {r.preload_fraction * 100:.1f} %)")
    rng = np.random.default_rng(1)
    t = time.perf_counter()
    for _ in range(5):
        rng.standard_normal((m // 5, draws))
    raw = m / (time.perf_counter() - t)
    print(f"numpy generating the {draws} random inputs per unit only (1 thread): {raw / 1e3:8.1f} k units/s")
    units = rb.simulate(p, samples=exact_units, seed=2, model="contact", save_units=exact_units, workers=1).units
    t = time.perf_counter()
    for u, _, _ in units:
        exact_play(g, u)
    print(f"exact play (root finding on the exact geometry), one unit:        {(time.perf_counter() - t) / exact_units * 1e3:8.2f} ms")


if __name__ == "__main__":
    main()
