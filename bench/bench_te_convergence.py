"""TE peak-to-peak against the number of output positions (issue 36 item 8): prints figures, asserts
nothing.

    .venv/bin/python bench/bench_te_convergence.py [--units 40] [--seed 3] [--coarse 1024]
                                                   [--fine 16384] [--tiny]

For the first ``--units`` units of ``simulate rv80e --model transmission --seed S`` (the units the run
draws, at its reference position), the TE peak-to-peak of the ccw flank (``transmission-error``'s
figure: the exact curve, refined between positions, kinematics.curve_extremes) at ``--coarse`` and at
``--fine`` positions, and the sampled curve's peak-to-peak at ``--coarse`` (what the figure was before
the refinement) and the production run's own figure of the unit (``simulate --model transmission``:
the linearised curve at 8 z_p = 320 positions, refined between them since schema 9.0), one row per unit, then the mean and
largest relative change and the units beyond 1 % (the issue's done-when: < 1 % from 1024 to 16 384
positions for 40 units of seed 3), and the production run's figure against the converged one. CPU time
per unit of the coarse figure (refined, and the sampled curve alone) is printed with it.
"""

from __future__ import annotations

import argparse
import time


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--units", type=int, default=40)
    ap.add_argument("--seed", type=int, default=3)
    ap.add_argument("--coarse", type=int, default=1024)
    ap.add_argument("--fine", type=int, default=16384)
    ap.add_argument("--tiny", action="store_true", help="tiny sizes: the test suite runs every bench so none rots")
    a = ap.parse_args()
    if a.tiny:
        a.units, a.fine = 2, 2048
    import numpy as np

    import rvbacklash as rb
    from rvbacklash.analysis.transmission import transmission_error
    from rvbacklash.models.kinematics import ARCSEC_PER_RAD, reference_revolution, revolution
    from rvbacklash.sampling.te_source import sample_units, te_streams, transmission_source

    p = rb.prepare("rv80e")
    units = sample_units(p, a.seed, a.units)
    src = transmission_source(p, "default", a.seed)  # the production run's figures of the same units
    produced = np.empty((3, a.units))
    src._evaluate(src._draw(te_streams(a.seed, 0), a.units), produced)
    transmission_error(p, units[0], "warm-up", a.coarse, shares=False)  # compile / load the kernels, the reference
    reference_revolution(p, a.fine, record=True)
    ref = reference_revolution(p, a.coarse)
    rows, cpu_refined, cpu_sampled = [], 0.0, 0.0
    print(f"rv80e, seed {a.seed}: TE peak-to-peak (ccw flank) [arcsec] of the run's first {a.units} units")
    print(f"{'unit':>4} {'run (320)':>10} {'sampled ' + str(a.coarse):>13} {'refined ' + str(a.coarse):>13} "
          f"{'refined ' + str(a.fine):>14} {'change':>8}")
    for k, u in enumerate(units):
        c = time.process_time()
        run = revolution(p, u, a.coarse)
        sampled = float(np.ptp(run.ccw_rad - ref.ccw_rad)) * ARCSEC_PER_RAD
        cpu_sampled += time.process_time() - c
        c = time.process_time()
        coarse = transmission_error(p, u, f"unit {k}", a.coarse, shares=False).te_peak_to_peak_arcsec
        cpu_refined += time.process_time() - c
        fine = transmission_error(p, u, f"unit {k}", a.fine, shares=False).te_peak_to_peak_arcsec
        change = coarse / fine - 1.0
        rows.append((sampled, coarse, fine, change, produced[1, k]))
        print(f"{k:4d} {produced[1, k]:10.2f} {sampled:13.2f} {coarse:13.2f} {fine:14.2f} {change:+8.2%}", flush=True)
    x = np.array(rows)
    beyond = int(np.count_nonzero(np.abs(x[:, 3]) >= 0.01))
    print(f"mean {x[:, 4].mean():10.2f} {x[:, 0].mean():13.2f} {x[:, 1].mean():13.2f} {x[:, 2].mean():14.2f}")
    print(f"change {a.coarse} -> {a.fine} positions: mean {x[:, 3].mean():+.2%}, largest |change| "
          f"{np.abs(x[:, 3]).max():.2%} (unit {int(np.argmax(np.abs(x[:, 3])))}), units beyond 1 %: {beyond} of {a.units}")
    print(f"sampled at {a.coarse} against refined at {a.fine}: mean {(x[:, 0] / x[:, 2] - 1).mean():+.2%}, "
          f"largest |change| {np.abs(x[:, 0] / x[:, 2] - 1).max():.2%}")
    run = x[:, 4] / x[:, 2] - 1
    print(f"production run's figure (320 positions, linearised, refined between them) against refined at {a.fine}: mean "
          f"{run.mean():+.2%}, from {run.min():+.2%} to {run.max():+.2%}")
    print(f"CPU per unit at {a.coarse} positions: sampled curve {cpu_sampled / a.units * 1e3:.1f} ms, "
          f"refined figure (transmission-error without the group shares) {cpu_refined / a.units * 1e3:.1f} ms")
    # the hardest unit found (issue 36 item 8): a swing 1/200 of a step wide (kinematics.solved_lever_zero)
    hard = sample_units(p, 0, 84)[83]
    coarse, fine = (transmission_error(p, hard, "seed 0 unit 83", n, shares=False).te_peak_to_peak_arcsec
                    for n in (a.coarse, 4096))
    print(f"seed 0, unit 83 (a swing 1/200 of a step wide): {coarse:.2f} at {a.coarse} against {fine:.2f} at 4096 "
          f"positions ({coarse / fine - 1:+.2%}; before the solved lever zero: 45.14 against 49.79)")


if __name__ == "__main__":
    main()
