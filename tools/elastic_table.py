"""Recompute the production-run figures of docs/elastic.md (prints markdown).

    .venv/bin/python tools/elastic_table.py [--samples 1e5] [--seed 1] [--share-units 5000]

rv80e, the elastic model under both readings of the per-element errors: the distributions of
lost motion, backlash and rigidity with the specs lost motion <= 1 arcmin and rigidity >= 300
N m/arcmin, the joint yield, the share of the mean lost motion of each element of the chain and
each element's mean compliance share.
"""

from __future__ import annotations

import argparse
from dataclasses import replace

import numpy as np

import rvbacklash as rb
from rvbacklash.models import elastic as el
from rvbacklash.sampling.elastic_source import sample_units

SPECS = {"lost_motion": 1.0, "rigidity": 300.0}  # a rigidity spec near the derived chain's nominal (310 since issue 28, 305 since issue 36), to show its yield


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--samples", type=float, default=1e5)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--share-units", type=int, default=5000)
    a = ap.parse_args()
    p = rb.prepare("rv80e")
    model = el.elastic_model(p)
    for em in ("long_wave", "independent"):
        r = rb.simulate(p, samples=int(a.samples), seed=a.seed, model="elastic", specs=SPECS, error_model=em)
        print(f"\n{em}: {r.samples_done:,} units, seed {a.seed}, preloaded cycloid stage (rigid): see docs/contact.md\n")
        print("| output | mean | σ | 0.135 % | 50 % | 99.865 % [95 % CI] | yield |")
        print("|---|---|---|---|---|---|---|")
        for name, o in r.outputs.items():
            q = {x.probability: x for x in o.quantiles}
            fmt = ".3f" if o.unit == "arcmin" else ".0f"
            top = q[0.99865]
            y = f"{o.yield_.fraction * 100:.2f} % ({'≤' if o.spec_is_upper else '≥'} {o.spec_limit:g})" if o.yield_ else "—"
            print(f"| {name} [{o.unit}] | {o.mean:{fmt}} | {o.sigma:{fmt}} | {q[0.00135].value:{fmt}} | {q[0.5].value:{fmt}} "
                  f"| {top.value:{fmt}} [{top.ci95_low:{fmt}}, {top.ci95_high:{fmt}}] | {y} |")
        print(f"\njoint yield (both specs): {r.joint_yield.fraction * 100:.2f} %")
        pe = replace(p, contact_errors=replace(p.contact_errors, error_model=em))
        units = sample_units(pe, a.seed, a.share_units)
        shares = np.zeros(el.N_ELEMENTS)
        compliance = np.zeros(el.N_ELEMENTS)
        for i in range(a.share_units):
            u = el.ElasticUnit(units.gap_um[i], units.lever_um_per_rad[i], float(units.chi_rad[i]),
                               float(units.involute_backlash_rad[i]), float(units.crank_clearance_um[i]))
            fig = el.PreparedUnit(model, u).figures()
            shares += fig[el.ELEMENT_LOST_MOTION:el.SHARES]
            compliance += fig[el.SHARES:] / fig[el.SHARES:].sum()
        total = shares.sum()
        print(f"share of the mean lost motion ({a.share_units} units): "
              + ", ".join(f"{name} {s / total * 100:.0f} %" for name, s in zip(el.ELEMENTS, shares) if s))
        print(f"mean compliance share ({a.share_units} units): "
              + ", ".join(f"{name} {s / a.share_units * 100:.1f} %" for name, s in zip(el.ELEMENTS, compliance) if s))


if __name__ == "__main__":
    main()
