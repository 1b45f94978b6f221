"""The production run's TE peak-to-peak, sampled at its 8 z_p positions (the figure before schema 9.0) and
refined between them (models.te_refine, the run's figure since), against the converged per-unit figure (issue 36 item 8): prints figures,
asserts nothing.

    .venv/bin/python bench/bench_te_refine.py [--units 40] [--seed 3] [--samples 4000] [--tiny]

For the first ``--units`` units of ``simulate rv80e --model transmission --seed S``: each path's figure
against ``transmission-error``'s (the exact curve at 1024 positions, refined, converged in positions:
bench_te_convergence.py), their mean, lowest and highest relative difference and the units beyond 1 %;
then CPU time (process time: the machine is shared) of each path's evaluation per unit, and of a whole
``simulate rv80e --model transmission -n SAMPLES`` with each, alternated, side by side in this process.
"""

from __future__ import annotations

import argparse
import time


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--units", type=int, default=40)
    ap.add_argument("--seed", type=int, default=3)
    ap.add_argument("--samples", type=int, default=4000)
    ap.add_argument("--tiny", action="store_true", help="tiny sizes: the test suite runs every bench so none rots")
    a = ap.parse_args()
    if a.tiny:
        a.units, a.samples = 2, 64
    import numpy as np

    import rvbacklash as rb
    from rvbacklash.analysis.transmission import transmission_error
    from rvbacklash.sampling import te_source
    from rvbacklash.sampling.te_source import sample_units, te_streams, transmission_source

    p = rb.prepare("rv80e")
    units = sample_units(p, a.seed, a.units)
    converged = np.array([transmission_error(p, u, f"unit {k}", 1024, shares=False).te_peak_to_peak_arcsec
                          for k, u in enumerate(units)])
    print(f"rv80e, seed {a.seed}, first {a.units} units: the production run's TE peak-to-peak against the converged "
          f"figure (transmission-error, 1024 positions, refined; mean {converged.mean():.2f} arcsec)")
    for refine in (False, True):
        src = transmission_source(p, "default", a.seed, refine=refine)
        batch = src._draw(te_streams(a.seed, 0), a.units)
        out = np.empty((3, a.units))
        src._evaluate(batch, out)  # compile / load the kernels
        c = time.process_time()
        src._evaluate(batch, out)
        cpu = (time.process_time() - c) / a.units
        rel = out[1] / converged - 1
        print(f"  {'refined' if refine else 'sampled'}: mean {out[1].mean():.2f} arcsec, difference mean {rel.mean():+.2%}, "
              f"from {rel.min():+.2%} (unit {int(np.argmin(rel))}) to {rel.max():+.2%}, units beyond 1 %: "
              f"{int(np.count_nonzero(np.abs(rel) >= 0.01))} of {a.units}; evaluation {cpu * 1e3:.2f} ms CPU a unit")
    cpu = {False: [], True: []}
    means = {}
    default = te_source.REFINE
    for _ in range(2):
        for refine in (False, True):
            te_source.REFINE = refine
            try:
                c = time.process_time()
                run = rb.simulate(p, samples=a.samples, seed=1, model="transmission")
                cpu[refine].append(time.process_time() - c)
                means[refine] = run.outputs["transmission_error"].mean
            finally:
                te_source.REFINE = default
    for refine in (False, True):
        print(f"simulate rv80e --model transmission -n {a.samples} --seed 1, {'refined' if refine else 'sampled'}: "
              f"TE mean {means[refine]:.2f} arcsec, CPU {min(cpu[refine]):.2f} s (best of 2, both threads)")


if __name__ == "__main__":
    main()
