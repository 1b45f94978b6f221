"""The rv80e transmission-error figures that docs/transmission-error.md sets beside Yang et al. (2021):
prints them, asserts nothing.

    .venv/bin/python tools/te_yang_table.py [--samples 10000] [--seed 0] [--exact-units 120]

1. the production run, the docs' command ``simulate rv80e --model contact -n 1e4 --seed 0
   --spec-te-arcsec 60 --spec-arcmin 3`` (the contact model's units turned through a revolution:
   the transmission model): TE peak-to-peak mean [95 % CI], median and the 0.135 / 99.865 %
   quantiles, sigma, the TE yield at 60 arcsec [95 % CI] and the joint yield with backlash <= 3
   arcmin; where Yang's two prototypes (60.1 and 64.6 arcsec) fall in the run (each unit's figure,
   drawn by the run's own block source);
2. the first ``--exact-units`` units of the same run on the exact geometry (``transmission-error``:
   1024 positions, the figure refined between them, converged in positions): their mean against the
   run's own figure of the same units (the run reads the linearised curve at 8 z_p = 320 positions,
   refined between them), the mean amplitude spectrum by order (ccw flank) and the median variance share of
   each error group (each switched off in turn);
3. the spectrum checks (``--spectrum-units``, 40: the first units of the same seed, exact geometry, 1024
   positions, ccw flank): the mean amplitude at orders 1, z_c and z_p with every error, with the pins'
   errors switched off, and with the disc run-out and crank eccentricity switched off
   (``--only-spectrum-checks``: this part alone).
"""

from __future__ import annotations

import argparse


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--samples", type=int, default=10_000)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--exact-units", type=int, default=120)
    ap.add_argument("--spectrum-units", type=int, default=40)
    ap.add_argument("--only-spectrum-checks", action="store_true")
    a = ap.parse_args()
    if a.only_spectrum_checks:
        spectrum_checks(a.seed, a.spectrum_units)
        return
    import numpy as np

    import rvbacklash as rb
    from rvbacklash.analysis.transmission import transmission_error
    from rvbacklash.sampling.te_source import sample_units_with_stages, transmission_source

    p = rb.prepare("rv80e")
    run = rb.simulate(p, samples=a.samples, seed=a.seed, model="transmission",
                      specs={"transmission_error": 60.0, "backlash": 3.0})
    te = run.outputs["transmission_error"]
    q = te.quantiles
    print(f"rv80e production run, {a.samples} units, seed {a.seed}: TE peak-to-peak [arcsec]")
    print(f"  mean {te.mean:.1f} [{te.mean_ci95_low:.1f}, {te.mean_ci95_high:.1f}], sigma {te.sigma:.1f}")
    print(f"  median / 0.135 % / 99.865 %: {q.at(0.5).value:.1f} / {q.at(0.00135).value:.1f} / {q.at(0.99865).value:.1f}")
    y = te.yield_
    print(f"  yield P(TE <= 60) {y.fraction:.1%} [{y.ci95_low:.1%}, {y.ci95_high:.1%}]; joint with backlash <= 3 arcmin "
          f"{run.joint_yield.fraction:.1%}")
    src = transmission_source(p, "default", a.seed)
    values = np.concatenate([src.block(b, min(src.block_size, a.samples - b * src.block_size))[1]
                             for b in range(-(-a.samples // src.block_size))])
    print(f"  (each unit's figure from the run's block source: mean {values.mean():.1f})")
    for name, x in (("prototype 1", 60.1), ("prototype 2", 64.6)):
        print(f"  Yang {name}, {x} arcsec: at the {np.mean(values <= x):.0%} point of the run")

    m = a.exact_units
    units, stages = sample_units_with_stages(p, a.seed, m)
    exact = [transmission_error(p, u, f"unit {k}", 1024, shares=True, other_stages_arcmin=float(stages[k]))
             for k, u in enumerate(units)]
    pp = np.array([e.te_peak_to_peak_arcsec for e in exact])
    print(f"first {m} units on the exact geometry (1024 positions, refined): TE p-p mean {pp.mean():.1f} against the "
          f"run's {values[:m].mean():.1f} for the same units ({values[:m].mean() / pp.mean() - 1:+.1%}; per unit "
          f"{np.min(values[:m] / pp - 1):+.1%} .. {np.max(values[:m] / pp - 1):+.1%})")
    spectrum = np.mean([e.spectrum_amplitude_arcsec for e in exact], axis=0)
    lead = np.argsort(spectrum[1:])[::-1][:12] + 1
    print("  mean amplitude by order [arcsec]: " + ", ".join(f"{k}: {spectrum[k]:.1f}" for k in lead))
    groups = {}
    for e in exact:
        for s in e.group_shares:
            groups.setdefault(s.group, []).append(s.variance_share)
    print("  median variance share by group: " + ", ".join(f"{g} {np.median(v):.2f}" for g, v in groups.items()))
    spectrum_checks(a.seed, a.spectrum_units)


def spectrum_checks(seed: int, count: int) -> None:
    """The mean amplitude [arcsec] at orders 1, z_c and z_p (ccw flank, exact geometry, 1024 positions)
    of the first ``count`` units of the seed's run: with every error, without the pins' errors, and
    without the disc run-out and crank eccentricity (analysis.transmission.GROUPS)."""
    import numpy as np

    import rvbacklash as rb
    from rvbacklash.analysis.transmission import _without, perfect_unit, transmission_error
    from rvbacklash.sampling.te_source import sample_units

    p = rb.prepare("rv80e")
    zc, zp = p.cycloid.zc, p.cycloid.zp
    units = sample_units(p, seed, count)
    cases = {"every error": None, "pins off": "pins (position, radius, hole clearance)",
             "run-out and crank eccentricity off": "disc run-out and crank eccentricity"}
    print(f"spectrum checks, first {count} units of seed {seed} (mean amplitude [arcsec], ccw flank, 1024 positions):")
    for name, group in cases.items():
        amp = np.mean([transmission_error(p, u if group is None else _without(u, perfect_unit(p, u.chi_rad), group),
                                          f"unit {k}", 1024, shares=False).spectrum_amplitude_arcsec
                       for k, u in enumerate(units)], axis=0)
        print(f"  {name}: order 1 {amp[1]:.2f}, order {zc} {amp[zc]:.2f}, order {zp} {amp[zp]:.2f}")


if __name__ == "__main__":
    main()
