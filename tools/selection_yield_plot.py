"""Yield versus pin classes (count, width, measurement noise) for docs/selective-assembly.md:

    .venv/bin/python tools/selection_yield_plot.py [--samples 4000] [--out docs/img/selection-yield.svg]

Prints the table and writes the SVG (report.selection.class_sweep_svg)."""

from __future__ import annotations

import argparse
from pathlib import Path


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--samples", type=int, default=4000)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out", default="docs/img/selection-yield.svg")
    ap.add_argument("--tiny", action="store_true")
    a = ap.parse_args()
    from rvbacklash import prepare
    from rvbacklash.analysis.selection.run import class_sweep
    from rvbacklash.atomic import atomic_write
    from rvbacklash.report.selection import class_sweep_svg

    kw = dict(counts=(1, 3), widths=(2.0,), samples=64) if a.tiny else dict(
        counts=(1, 3, 5, 7, 9), widths=(1.0, 2.0, 4.0), noises=(0.0, 1.0), samples=a.samples)
    sweep = class_sweep(prepare("rv80e"), seed=a.seed, **kw)
    print(f"random assembly: yield {sweep.random_yield.fraction:.2%}")
    for r in sweep.rows():
        print(f"pins {r['pin_classes']:2d} x {r['pin_width_um']:g} um, noise {r['noise_um']:g} um: yield "
              f"{r['yield']:.2%} [{r['ci95_low']:.2%}, {r['ci95_high']:.2%}], pin surplus {r['pin_surplus_fraction']:.1%}")
    out = Path(a.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    atomic_write("--out", out, class_sweep_svg(sweep))
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
