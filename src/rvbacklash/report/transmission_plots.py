"""Figures of the transmission-error model (docs/transmission-error.md), as SVG text, drawn from
results only: a unit's TE curves over the output revolution with its lost motion, and the
amplitude spectrum by order."""

from __future__ import annotations

import textwrap
from typing import Sequence

import numpy as np

from rvbacklash.report.plots import BLUE, GREEN, GREY, RED, _svg, plt


def te_figure(result, others: Sequence = (), title: str = "", spectrum=None):
    """Left: TE of each load direction against the output angle (and of ``others``, the loaded
    flank only), lost motion on a second axis; right: the loaded flank's amplitude spectrum of
    ``spectrum`` (default ``result``), or why it has none (an error-free unit's TE is 0)."""
    fig, (ax, sx) = plt.subplots(1, 2, figsize=(11.0, 4.2), gridspec_kw={"width_ratios": [1.6, 1.0]})
    r = result
    ax.plot(r.output_angle_deg, r.te_ccw_arcsec, color=BLUE, lw=1.0,
            label=f"{r.unit}, ccw flank (p-p {np.ptp(r.te_ccw_arcsec):.1f}″)")
    ax.plot(r.output_angle_deg, r.te_cw_arcsec, color=GREEN, lw=0.8, ls="--",
            label=f"cw flank (p-p {np.ptp(r.te_cw_arcsec):.1f}″)")
    for o, color in zip(others, (RED, GREY)):
        ax.plot(o.output_angle_deg, o.te_arcsec, color=color, lw=0.8, label=f"{o.unit} (p-p {o.te_peak_to_peak_arcsec:.1f}″)")
    ax.set_xlabel("output angle [deg]")
    ax.set_ylabel("transmission error [arcsec]")
    ax.set_xlim(0, 360)
    ax.grid(alpha=0.3)
    lm = ax.twinx()
    lm.plot(r.output_angle_deg, r.lost_motion_arcmin, color=GREY, lw=0.6, alpha=0.7)
    lm.set_ylabel("rigid lost motion [arcmin] (grey)")
    ax.legend(fontsize=7.5, loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=2, frameon=False)
    ax.set_title(title or f"{r.design_name}: transmission error over one output revolution", fontsize=10)
    sp = spectrum if spectrum is not None else r
    orders = np.arange(sp.spectrum_amplitude_arcsec.size)
    if sp.leading_orders:
        sx.vlines(orders[1:], 0, sp.spectrum_amplitude_arcsec[1:], color=BLUE, lw=1.0)
    else:  # no axis of zeros: say why
        sx.text(0.5, 0.5, textwrap.fill(sp.no_spectrum(), 40), ha="center", va="center", fontsize=8.5,
                transform=sx.transAxes, color=GREY)
        sx.set_yticks([])
    sx.set_xlabel("order (per output revolution)")
    sx.set_ylabel(f"amplitude [arcsec], {sp.load_direction} flank")
    sx.set_xlim(0, min(orders[-1], 200))
    sx.grid(alpha=0.3)
    sx.set_title("spectrum" if sp is r else f"spectrum, {sp.unit}", fontsize=10)
    fig.tight_layout()
    return fig


def te_svg(result, others: Sequence = (), title: str = "", spectrum=None) -> str:
    return _svg(te_figure(result, others, title, spectrum))


def te_histogram_figure(sim, spec_te_arcsec: float | None = None):
    """Histogram (density) of the production run's TE peak-to-peak, its 0.135 % / 99.865 %
    quantiles dotted and the spec dashed; the legend below the axes (off the bars)."""
    o = sim.outputs["transmission_error"]
    fig, ax = plt.subplots(figsize=(7.5, 3.6))
    h = o.histogram
    ax.stairs(np.asarray(h.density), np.asarray(h.edges), fill=True, alpha=0.5, color=BLUE, label=f"{o.samples:,} units")
    for q in o.quantiles:
        if q.value is not None and q.probability in (0.00135, 0.99865):
            ax.axvline(q.value, color=GREY, lw=1.0, ls=":")
    spec = spec_te_arcsec if spec_te_arcsec is not None else o.spec_limit
    if spec is not None:
        y = f", yield {o.yield_.fraction * 100:.2f} %" if o.yield_ is not None else ""
        ax.axvline(spec, color=RED, ls="--", lw=1.2, label=f"spec ≤ {spec:g}″{y}")
    ax.set_xlabel("transmission error peak-to-peak [arcsec]")
    ax.set_ylabel("density")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7.5, loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=2, frameon=False)
    ax.set_title(f"{sim.design_name}: production run, TE peak-to-peak (quantiles 0.135 % / 99.865 % dotted)",
                 fontsize=10)
    fig.tight_layout()
    return fig


def spectrum_unit(section):
    """The unit whose spectrum the report draws: the nominal unit when it has lines, else the unit
    at the last (highest) quantile of TE peak-to-peak."""
    if section.nominal.leading_orders or not section.quantile_units:
        return section.nominal
    return list(section.quantile_units.values())[-1]


def transmission_figures(section) -> dict[str, str | None]:
    """Inline SVG for the report partial ``_transmission_section.html.j2`` from a
    ``TransmissionSection``: the nominal unit's curves with the quantile units' curves and a
    spectrum (``spectrum_unit``; "te_spectrum_of" names its unit), and the production run's
    histogram."""
    from rvbacklash.report.plots import inline_svg

    sim = section.simulation
    others = tuple(section.quantile_units.values())
    return {
        # the nominal unit's TE is 0 by definition: the spectrum drawn is the last (highest) quantile unit's
        "te_curves": inline_svg(te_svg(section.nominal, others,
                                       f"{section.nominal.design_name}: nominal unit and the units at "
                                       f"{', '.join(section.quantile_units)} of TE peak-to-peak",
                                       spectrum=spectrum_unit(section))),
        "te_histogram": inline_svg(_svg(te_histogram_figure(sim, section.spec_te_arcsec)))
        if sim is not None and "transmission_error" in sim.outputs else None,
        "te_spectrum_of": next((f"the unit at {k}" for k, u in section.quantile_units.items()
                                if u is spectrum_unit(section)), "the nominal unit"),
    }
