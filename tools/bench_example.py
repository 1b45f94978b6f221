#!/usr/bin/env python3
"""The worked example of docs/bench-data.md: bench files made by the model (a known structure
stiffness, friction and crank clearances, with noise, offsets, drift, two cycles, degrees), read
by `rvbacklash bench`, placed in rv80e's production run and calibrated; writes the files to
OUT (default: a temporary folder) and the figures to docs/.

    PYTHONPATH=src python tools/bench_example.py [OUT]
"""

from __future__ import annotations

import subprocess
import sys
import tempfile
from pathlib import Path

import rvbacklash as rb
from rvbacklash.analysis.bench_synthetic import model_loop_samples, te_curve, write_loop_csv, write_te_csv

ROOT = Path(__file__).resolve().parents[1]


def main() -> None:
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp())
    out.mkdir(parents=True, exist_ok=True)
    d = rb.load_design("rv80e")
    # the loop's friction from the contacts (the example states no friction: the default since schema 8.0)
    # with a static coefficient of 0.25 on the pins and the mesh (the design's 0.12)
    truth = rb.prepare(d.model_copy(update={
        "elastic": d.elastic.model_copy(update={"structure_stiffness_nm_per_arcmin": 400.0}),
        "lubrication": d.lubrication.model_copy(update={"static_friction_coefficient": 0.25})}))
    header = ("unit {k}: rv80e with a 400 N m/arcmin structure, static friction coefficient 0.25, crank clearance "
              "{g} um (synthetic)")
    for k, g in enumerate((3.0, 4.0, 5.0, 6.0, 7.0), start=1):
        t, q, a = model_loop_samples(truth, cycles=2, samples_per_branch=300, noise_arcmin=0.01, offset_arcmin=k,
                                     drift_arcmin_per_s=0.005, uneven=True, seed=k, crank_clearance_um=g)
        write_loop_csv(out / f"unit{k}.csv", t, q, a, angle_unit="deg", header=header.format(k=k, g=g))
    write_te_csv(out / "te1.tsv", *te_curve({1: 10.0, 2: 4.0, 39: 1.5, 78: 0.8}, samples=3000, noise_arcsec=0.3,
                                            start_deg=37.0, revolutions=1.2, seed=4))
    exe = [sys.executable, "-m", "rvbacklash"]
    runs = [["bench", out / "unit1.csv", out / "te1.tsv", "--design", "rv80e", "-n", "2000",
             "--plot", ROOT / "docs" / "bench-data-bench.svg", "--json", out / "bench.json", "--force"],
            ["calibrate", "rv80e", *sum((["--bench", out / f"unit{k}.csv"] for k in range(1, 6)), []),
             "--write-design", out / "calibrated.toml", "--samples", "2000", "--bootstrap", "20",
             "--plot", ROOT / "docs" / "bench-data-calibration.svg", "--json", out / "calibrate.json", "--force"],
            ["hysteresis", out / "calibrated.toml"]]
    for args in runs:
        print("$ rvbacklash " + " ".join(str(a).replace(str(out), "bench").replace(str(ROOT) + "/", "") for a in args))
        p = subprocess.run([*exe, *map(str, args)], capture_output=True, text=True)
        print(p.stdout.replace(str(out), "bench"), p.stderr, flush=True)
    print(f"files in {out}")


if __name__ == "__main__":
    main()
