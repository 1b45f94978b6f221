"""Monte-Carlo engine benchmark: prints figures, asserts nothing.

    .venv/bin/python bench/bench_montecarlo.py [--samples 1e8] [--rss-samples 1e8]

1. engine samples/s on the sun2014 example (linear model, 21 normal inputs, all cores);
2. numpy alone generating the same random inputs (N x 21 standard normals, in chunks);
3. their ratio;
4. peak resident memory of a whole `rvbacklash simulate` process for --rss-samples.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import time

import numpy as np


def engine_rate(samples: int, warm: int = 1 << 16) -> tuple[float, float]:
    from rvbacklash import load_design
    from rvbacklash import simulate
    from rvbacklash.analysis.simulation import default_workers

    d = load_design("sun2014")
    simulate(d, samples=warm, seed=0)  # compile / load the kernels outside the timing
    t = time.perf_counter()
    simulate(d, samples=samples, seed=1, spec_arcmin=3.0)
    dt = time.perf_counter() - t
    return samples / dt, default_workers()


def numpy_rate(samples: int, chunk: int = 1 << 16) -> float:
    rng = np.random.default_rng(1)
    t = time.perf_counter()
    done = 0
    while done < samples:
        n = min(chunk, samples - done)
        rng.standard_normal((n, 21))
        done += n
    return samples / (time.perf_counter() - t)


def peak_rss_mb(samples: int) -> float:
    code = ("import resource, sys\n"
            "from rvbacklash.cli import main\n"
            f"argv = ['simulate', 'sun2014', '--samples', '{samples}', '--seed', '1', '--spec-arcmin', '3', '--quiet']\n"
            "try:\n    main(argv)\nexcept SystemExit:\n    pass\n"
            "print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return int(out.stdout.strip().splitlines()[-1]) / 1024.0


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--samples", type=float, default=1e8)
    ap.add_argument("--numpy-samples", type=float, default=2e7)
    ap.add_argument("--rss-samples", type=float, default=1e8)
    ap.add_argument("--tiny", action="store_true", help="tiny sizes: the test suite runs every bench so none rots")
    a = ap.parse_args()
    if a.tiny:
        a.samples = a.numpy_samples = a.rss_samples = 4096
    eng, workers = engine_rate(int(a.samples), min(int(a.samples), 1 << 16))
    raw = numpy_rate(int(a.numpy_samples))
    print(f"engine (sun2014, linear, 21 normals, {workers} threads): {eng / 1e6:8.1f} M samples/s")
    print(f"numpy generate N x 21 normals only (1 thread):          {raw / 1e6:8.1f} M samples/s")
    print(f"ratio engine / numpy-generate:                          {eng / raw:8.1f} x")
    rss = peak_rss_mb(int(a.rss_samples))
    print(f"peak RSS of `simulate` with {a.rss_samples:.0e} samples:             {rss:8.0f} MB")


if __name__ == "__main__":
    main()
