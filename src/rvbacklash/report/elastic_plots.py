"""Figures of the elastic hysteresis model (docs/elastic.md), as SVG text, drawn from results only:
the torque-angle loop of the nominal unit (and of other units beside it) and the histograms of a
production run's lost motion, backlash and torsional rigidity with their specs."""

from __future__ import annotations

from typing import Mapping, Sequence

import numpy as np

from rvbacklash.report.plots import BLUE, GREEN, GREY, RED, _svg, inline_svg, plt

LOOP_STYLES = ((BLUE, "-", 1.6), (GREEN, "--", 1.2), (RED, ":", 1.4), (GREY, "-.", 1.0))


def loop_figure(result, others: Sequence = (), title: str = ""):
    """The loop of ``result`` (a HysteresisResult) and of ``others`` on one axis (angle against
    torque, the test bench's plot), with the lost-motion torques +-x T_R and the rigidity
    interval marked; a zoom on +-5 x T_R beside it shows lost motion and backlash."""
    fig, (ax, zx) = plt.subplots(1, 2, figsize=(10.0, 4.4), gridspec_kw={"width_ratios": [1.35, 1.0]})
    tr = result.rated_torque_nm
    x = result.measuring_torque_fraction * tr
    for k, r in enumerate((result, *others)):
        color, ls, lw = LOOP_STYLES[k % len(LOOP_STYLES)]
        label = (f"{r.unit}: lost motion {r.lost_motion_arcmin:.3f} arcmin, backlash {r.backlash_arcmin:.3f} arcmin, "
                 f"rigidity {r.torsional_rigidity_nm_per_arcmin:.0f} N·m/arcmin")
        for i, b in enumerate(r.loop):
            for a in (ax, zx):
                a.plot(b.angle_arcmin, b.torque_nm, color=color, ls=ls, lw=lw, label=label if i == 0 and a is ax else None)
    lo, hi = result.rigidity_interval_fraction
    for a in (ax, zx):
        a.axhline(0, color="k", lw=0.6)
        a.axvline(0, color="k", lw=0.6)
        for t in (x, -x):
            a.axhline(t, color=GREY, lw=0.8, ls=":")
        a.grid(alpha=0.3)
        a.set_xlabel("output angle [arcmin]")
    ax.axhspan(lo * tr, hi * tr, color=GREY, alpha=0.08, lw=0)
    ax.axhspan(-hi * tr, -lo * tr, color=GREY, alpha=0.08, lw=0)
    ax.set_ylabel("output torque [N·m]")
    ax.set_title(title or f"{result.design_name}: hysteresis loop (input locked), ±{tr:g} N·m", fontsize=10)
    zx.set_ylim(-5 * x, 5 * x)
    near = [a for r in (result, *others) for b in r.loop for t, a in zip(b.torque_nm, b.angle_arcmin)
            if abs(t) <= 5 * x]
    if near:
        span = max(abs(min(near)), abs(max(near)), 1e-3)
        zx.set_xlim(-1.15 * span, 1.15 * span)
    zx.set_title(f"near zero: ±{result.measuring_torque_fraction * 100:g} % T_R dotted", fontsize=10)
    # below both axes, centred on the figure: never over the loops, never past the figure's edge
    fig.legend(*ax.get_legend_handles_labels(), fontsize=7.5, loc="upper center", bbox_to_anchor=(0.5, 0.0), ncol=1,
               frameon=False)
    return fig


def loop_svg(result, others: Sequence = (), title: str = "") -> str:
    """SVG of ``loop_figure``."""
    return _svg(loop_figure(result, others, title))


HISTOGRAMS = (("lost_motion", "lost motion [arcmin]"), ("backlash", "backlash [arcmin]"),
              ("rigidity", "torsional rigidity [N·m/arcmin]"))


def elastic_histograms_figure(sim, specs: Mapping[str, float] | None = None):
    """Histograms (density) of the three outputs of an elastic-model run, their 0.135 % / 99.865 %
    quantiles dotted and the specs dashed (upper limit for lost motion and backlash, lower limit
    for rigidity)."""
    specs = dict(specs or {})
    fig, axes = plt.subplots(1, 3, figsize=(11.0, 3.4))
    for ax, (name, label) in zip(axes, HISTOGRAMS):
        o = sim.outputs.get(name)
        if o is None:
            ax.set_axis_off()
            continue
        h = o.histogram
        ax.stairs(np.asarray(h.density), np.asarray(h.edges), fill=True, alpha=0.5, color=BLUE,
                  label=f"{o.samples:,} units")
        for q in o.quantiles:
            if q.value is not None and q.probability in (0.00135, 0.99865):
                ax.axvline(q.value, color=GREY, lw=1.0, ls=":")
        spec = specs.get(name, o.spec_limit)
        if spec is not None:
            side = "≤" if o.spec_is_upper else "≥"
            y = f", yield {o.yield_.fraction * 100:.2f} %" if o.yield_ is not None else ""
            ax.axvline(spec, color=RED, ls="--", lw=1.2, label=f"spec {side} {spec:g}{y}")
        ax.set_xlabel(label)
        ax.set_ylabel("density")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7.5, loc="upper center", bbox_to_anchor=(0.5, -0.2), frameon=False)  # below: off the bars
    fig.suptitle(f"{sim.design_name}: production run, elastic model (quantiles 0.135 % / 99.865 % dotted)",
                 fontsize=10)
    fig.tight_layout()
    return fig


def elastic_histograms_svg(sim, specs: Mapping[str, float] | None = None) -> str:
    """SVG of ``elastic_histograms_figure``."""
    return _svg(elastic_histograms_figure(sim, specs))


def element_label(name: str) -> str:
    return name.replace("_", " ")


def compliance_figure(result):
    """Two bar charts side by side for one unit (a HysteresisResult): where the lost motion comes
    from (each element's dead band and wind-up at +-x T_R, arcmin) and where the compliance is
    (each element's share of the chain's compliance over the rigidity interval, with its stiffness
    referred to the output). Elements the design does not model (rigid, no play) are left out."""
    names = [k for k in result.lost_motion_share_arcmin
             if result.lost_motion_share_arcmin[k] != 0.0 or result.compliance_share[k] != 0.0
             or result.dead_band_arcmin[k] != 0.0]
    y = np.arange(len(names))[::-1]
    fig, (lm, cs) = plt.subplots(1, 2, figsize=(10.0, 0.42 * len(names) + 1.6), sharey=True)
    dead = np.array([result.dead_band_arcmin[k] for k in names])
    total = np.array([result.lost_motion_share_arcmin[k] for k in names])
    lm.barh(y, dead, color=GREY, label="dead band (clearance)")
    lm.barh(y, total - dead, left=dead, color=BLUE, label="wind-up (elastic, friction)")
    lm.set_yticks(y, [element_label(k) for k in names], fontsize=8.5)
    lm.set_xlabel("share of the lost motion [arcmin]")
    lm.set_title(f"lost motion {result.lost_motion_arcmin:.3f} arcmin at ±"
                 f"{result.measuring_torque_fraction * 100:g} % T_R", fontsize=9.5)
    lm.grid(axis="x", alpha=0.3)
    lm.legend(fontsize=7.5, loc="upper center", bbox_to_anchor=(0.5, -0.18 - 0.5 / len(names)), ncol=2,
              frameon=False)
    share = np.array([result.compliance_share[k] for k in names]) * 100
    cs.barh(y, share, color=GREEN)
    for yy, v, k in zip(y, share, names):
        stiff = result.element_stiffness_nm_per_arcmin[k]
        if stiff is not None:
            k = f"{stiff:.0f}" if stiff < 1e5 else f"{stiff:.1e}"
            cs.text(v, yy, f" {v:.1f} % ({k} N·m/arcmin)", va="center", fontsize=7.5)
    cs.set_xlim(0, max(share.max(), 1e-9) * 1.9)
    cs.set_xlabel("share of the compliance [%]")
    lo, hi = (v * 100 for v in result.rigidity_interval_fraction)
    cs.set_title(f"rigidity {result.torsional_rigidity_nm_per_arcmin:.0f} N·m/arcmin ({lo:g}–{hi:g} % T_R)",
                 fontsize=9.5)
    cs.grid(axis="x", alpha=0.3)
    fig.tight_layout()
    return fig


def compliance_svg(result) -> str:
    """SVG of ``compliance_figure``."""
    return _svg(compliance_figure(result))


def elastic_figures(section) -> dict[str, str | None]:
    """Inline SVG elements for the report partial ``_elastic_section.html.j2`` from an
    ``ElasticSection``: the nominal loop with the quantile units' loops, and the histograms."""
    others = tuple(section.quantile_units.values())
    return {
        "elastic_loop": inline_svg(loop_svg(section.nominal, others,
                                            f"{section.nominal.design_name}: nominal unit and the units at "
                                            f"{', '.join(section.quantile_units)} of lost motion")),
        "elastic_histograms": inline_svg(elastic_histograms_svg(section.simulation, section.specs))
        if section.simulation is not None else None,
        "compliance_share": inline_svg(compliance_svg(section.nominal)),
    }
