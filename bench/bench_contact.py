"""Contact-model Monte-Carlo benchmark: prints figures, asserts nothing.

    .venv/bin/python bench/bench_contact.py [--samples 4e6]

1. engine samples/s of the contact model on the rv80e example (40 pins, 2 discs, every pin's
   and tooth's errors drawn separately, all cores);
2. numpy alone generating the same random inputs (about 262 draws per sample), in chunks;
3. their ratio.
"""

from __future__ import annotations

import argparse
import time

import numpy as np


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--samples", type=float, default=4e6)
    a = ap.parse_args()
    from rvbacklash import load_design, simulate
    from rvbacklash.analysis.simulation import default_workers

    d = load_design("rv80e")
    s2 = d.second_stage
    draws = 1 + 11 + 2 + 4 * s2.pins + s2.discs * (5 + s2.cycloid_teeth)  # per sample, see contact_source
    simulate(d, samples=1 << 16, seed=0, model="contact")  # compile / load kernels outside the timing
    n = int(a.samples)
    t = time.perf_counter()
    simulate(d, samples=n, seed=1, model="contact", spec_arcmin=3.0)
    eng = n / (time.perf_counter() - t)
    rng = np.random.default_rng(1)
    m = 200_000
    t = time.perf_counter()
    for _ in range(5):
        rng.standard_normal((m // 5, draws))
    raw = m / (time.perf_counter() - t)
    print(f"contact engine (rv80e, {s2.pins} pins, {s2.discs} discs, {default_workers()} threads): {eng / 1e6:6.2f} M samples/s")
    print(f"numpy generate the {draws} random inputs per sample only (1 thread):  {raw / 1e6:6.2f} M samples/s")
    print(f"ratio engine / numpy-generate:                                  {eng / raw:6.1f} x")


if __name__ == "__main__":
    main()
