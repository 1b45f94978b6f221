"""Recompute the Monte-Carlo table of docs/contact.md (prints markdown).

    .venv/bin/python tools/contact_table.py [--samples 1e6] [--seed 1]

Rows: sun2014, rv80e, rv80e with a 20 and a 40 um equidistance modification; the linear model
and the contact model under both readings of the per-element errors (long_wave, independent).
"""

from __future__ import annotations

import argparse

import rvbacklash as rb
from rvbacklash.design.loading import design_from_toml, example_text

DESIGNS = [("sun2014", "sun2014", None, 3.0), ("rv80e", "rv80e", None, 3.0),
           ("rv80e, Δr_rp = 20 µm", "rv80e", 20.0, 4.0), ("rv80e, Δr_rp = 40 µm", "rv80e", 40.0, 4.0)]


def problem(name: str, dr: float | None):
    text = example_text(name)
    if dr is not None:
        text = text.replace("equidistance_modification_um = 5.0", f"equidistance_modification_um = {dr}")
    return rb.prepare(design_from_toml(text))


def f(x, spec=".3f"):
    return "—" if x is None else format(x, spec)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--samples", type=float, default=1e6)
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    n = int(a.samples)
    print("| design | model | mean | σ | 0.135 % | 50 % | 99.865 % | P(≤ spec) | preloaded | preload mean / 99.865 % [µm] "
          "| free units: mean / 99.865 % |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for label, name, dr, spec in DESIGNS:
        p = problem(name, dr)
        runs = [("linear", rb.simulate(p, samples=n, seed=a.seed, spec_arcmin=spec))]
        for em in ("long_wave", "independent"):
            runs.append((f"contact, {em}", rb.simulate(p, samples=n, seed=a.seed, spec_arcmin=spec, model="contact",
                                                       error_model=em)))
        for model, r in runs:
            o = r.output
            q = [o.quantiles.at(x).value for x in (0.00135, 0.5, 0.99865)]
            y = f"{o.yield_.fraction * 100:.1f} % (≤ {spec:g})"
            if r.preload_fraction is None:
                pre, depth, free = f"{o.negative_fraction * 100:.2f} % (< 0)", "—", "—"
            else:
                pl, fr = r.outputs["preload"], r.outputs["backlash_free"]
                pre = f"{r.preload_fraction * 100:.1f} %"
                depth = f"{f(pl.mean, '.2f')} / {f(pl.quantiles.at(0.99865).value, '.2f')}" if pl.samples else "—"
                free = f"{f(fr.mean)} / {f(fr.quantiles.at(0.99865).value)}" if fr.samples else "—"
            print(f"| {label} | {model} | {o.mean:.3f} | {o.sigma:.3f} | {f(q[0])} | {f(q[1])} | {f(q[2])} | {y} | "
                  f"{pre} | {depth} | {free} |")


if __name__ == "__main__":
    main()
