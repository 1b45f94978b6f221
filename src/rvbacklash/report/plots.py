"""Figures as SVG text (matplotlib, Agg backend; no display needed), drawn from results only."""

from __future__ import annotations

import io
import re

import matplotlib

matplotlib.use("Agg")
matplotlib.rcParams["svg.hashsalt"] = "rvbacklash"  # stable element ids: same input, same SVG
matplotlib.rcParams["font.size"] = 10
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from rvbacklash.units import display_unit  # noqa: E402

BLUE, RED, GREEN, GREY = "#3b6ea5", "#c0392b", "#1f7a3a", "#555555"


def _svg(fig) -> str:
    """SVG text of a figure; text as paths (no font needed), no RDF metadata (no date, no URLs)."""
    buf = io.StringIO()
    fig.savefig(buf, format="svg", bbox_inches="tight", metadata={"Date": None})
    plt.close(fig)
    return re.sub(r"\s*<metadata>.*?</metadata>", "", buf.getvalue(), flags=re.S)


def inline_svg(svg: str) -> str:
    """An SVG document as an element for inline HTML (XML prolog and DOCTYPE removed)."""
    start = svg.find("<svg")
    return svg[start:] if start >= 0 else svg


def cdf_points(result) -> tuple[np.ndarray, np.ndarray]:
    """(x, P(output <= x)) of a SimulationResult's primary output: the sampled histogram's cdf,
    or the exact cdf for the exact method."""
    o = result.output
    h = o.histogram
    edges = np.asarray(h.edges)
    if h.counts is not None:
        c = np.cumsum(np.asarray(h.counts, float))
        below = h.underflow or 0
        return edges, np.concatenate([[below], below + c]) / o.samples
    curve = result.exact_curve
    return np.asarray(curve.x_arcmin), np.asarray(curve.cdf)


def scenario_overlay_svg(scenarios, spec_arcmin: float | None = None, title: str = "") -> str:
    """Cumulative distributions of the output backlash of several scenarios on one axis; the
    legend sits below the axes so that it never covers the tails."""
    return _svg(scenario_overlay_figure(scenarios, spec_arcmin, title))


def scenario_overlay_figure(scenarios, spec_arcmin: float | None = None, title: str = ""):
    fig, ax = plt.subplots(figsize=(7.5, 4.6))
    for s in scenarios:
        x, p = cdf_points(s.result)
        q = s.result.quantiles.at(0.99865).value
        ax.plot(x, p, label=f"{s.name}  (99.865 %: {q:.3f} arcmin)" if q is not None else s.name)
    if spec_arcmin is not None:
        ax.axvline(spec_arcmin, color="k", ls="--", lw=1, label=f"spec {spec_arcmin:g} arcmin")
    ax.set_xlabel("output backlash [arcmin]")
    ax.set_ylabel("P(backlash ≤ x)")
    ax.set_ylim(0, 1)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=1, frameon=False)
    if title:
        ax.set_title(title, fontsize=10)
    return fig


def pareto_svg(stackup, top: int = 12) -> str:
    """Pareto chart: variance share of each factor, largest first, with the cumulative share."""
    fs = sorted(stackup.factors, key=lambda f: f.rank)[:top]
    names = [f"{f.id} {f.key}" for f in fs]
    shares = np.array([f.variance_share for f in fs]) * 100
    fig, ax = plt.subplots(figsize=(8.5, 4.2))
    ax.bar(range(len(fs)), shares, color=BLUE, label="share of the output variance")
    ax2 = ax.twinx()
    ax2.plot(range(len(fs)), np.cumsum(shares), color=RED, marker="o", ms=3, label="cumulative")
    ax2.set_ylim(0, 105)
    ax2.set_ylabel("cumulative [%]", color=RED)
    ax.set_xticks(range(len(fs)))
    ax.set_xticklabels(names, rotation=50, ha="right", fontsize=9)
    ax.set_ylabel("share of output variance [%]")
    ax.set_title("Which tolerances cause the spread (variance share S_i² σ_i² / σ²)", fontsize=11)
    ax.grid(axis="y", alpha=0.3)
    return _svg(fig)


def tornado_svg(stackup, top: int = 12) -> str:
    """Tornado chart: output swing over each factor's zone (sensitivity times zone, with sign)."""
    return _svg(tornado_figure(stackup, top))


def tornado_figure(stackup, top: int = 12):
    from matplotlib.patches import Patch

    fs = sorted(stackup.factors, key=lambda f: -abs(f.sensitivity_arcmin_per_um) *
                (f.zone_upper_um - f.zone_lower_um))[:top][::-1]
    fig, ax = plt.subplots(figsize=(8.5, 4.6))
    for i, f in enumerate(fs):
        s = f.sensitivity_arcmin_per_um
        for end in (s * (f.zone_lower_um - f.raw_mean_um), s * (f.zone_upper_um - f.raw_mean_um)):
            ax.barh(i, end, color=RED if end > 0 else BLUE)
    ax.set_yticks(range(len(fs)))
    ax.set_yticklabels([f"{f.id} {f.key}" for f in fs], fontsize=9)
    ax.axvline(0, color="k", lw=0.8)
    ax.set_xlabel("change of the output backlash from its mean, factor at its zone limits [arcmin]")
    ax.set_title("Sensitivity over the tolerance zone (tornado)", fontsize=11)
    ax.legend(handles=[Patch(color=RED, label="more backlash"), Patch(color=BLUE, label="less backlash")],
              fontsize=9, loc="lower right")
    ax.grid(axis="x", alpha=0.3)
    return fig


def histogram_svg(sim, spec_arcmin: float | None) -> str:
    """Histogram (density) of the primary output with the exact distribution of the linear model;
    the legend names each curve's model and sits below the axes (it never covers the data)."""
    o = sim.output
    h = o.histogram
    edges = np.asarray(h.edges)
    fig, ax = plt.subplots(figsize=(8.5, 4.0))
    label = f"{sim.model} model: Monte-Carlo, {o.samples:,} units" if sim.method != "exact" else \
        f"{sim.model} model: exact distribution"
    ax.stairs(np.asarray(h.density), edges, fill=True, alpha=0.5, color=BLUE, label=label)
    if sim.exact_curve is not None and sim.method != "exact":
        ax.plot(sim.exact_curve.x_arcmin, sim.exact_curve.pdf_per_arcmin, color="k", lw=1.2,
                label="linear model (Eq. (2)): exact distribution" + (
                    " (rigid play summed at one pin, for comparison)" if sim.model != "linear" else ""))
    if spec_arcmin is not None:
        ax.axvline(spec_arcmin, color=RED, ls="--", lw=1.2, label=f"spec {spec_arcmin:g} arcmin")
    ax.axvline(0, color="grey", lw=0.8)
    unit = display_unit(o.unit)
    ax.set_xlabel(f"{o.description} [{unit}]")
    ax.set_ylabel(f"density [1/{unit}]")
    ax.legend(fontsize=9, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=1, frameon=False)
    ax.grid(alpha=0.3)
    return _svg(fig)


CONVERGENCE_MIN_POINTS = 3  # fewer points show no trend (one point per wave of blocks: 1, 2, 4, ...)


def shows_convergence(sim) -> bool:
    """Whether the run has enough convergence points (with a quantile) to draw."""
    return sum(c.q99865_arcmin is not None for c in sim.convergence) >= CONVERGENCE_MIN_POINTS


def convergence_svg(sim) -> str:
    """Estimate and 95 % interval of the 99.865 % quantile (and the yield) against N."""
    pts = [c for c in sim.convergence if c.q99865_arcmin is not None]
    fig, ax = plt.subplots(figsize=(8.5, 3.6))
    if pts:
        n = np.array([c.samples for c in pts], float)
        q = np.array([c.q99865_arcmin for c in pts])
        lo = np.array([np.nan if c.q99865_ci95_low_arcmin is None else c.q99865_ci95_low_arcmin for c in pts])
        hi = np.array([np.nan if c.q99865_ci95_high_arcmin is None else c.q99865_ci95_high_arcmin for c in pts])
        ax.fill_between(n, lo, hi, alpha=0.3, color=BLUE, label="95 % interval")
        ax.plot(n, q, color=BLUE, marker="o", ms=3, label="99.865 % quantile")
        ax.set_xscale("log")
    ax.set_xlabel("samples N")
    ax.set_ylabel("99.865 % quantile [arcmin]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=9, loc="upper left")
    yields = [c for c in sim.convergence if c.yield_fraction is not None]
    if yields:
        ax3 = ax.twinx()
        ax3.plot([c.samples for c in yields], [100 * c.yield_fraction for c in yields], color=RED, lw=1, ls=":",
                 label="yield")
        ax3.set_ylabel("yield [%] (dotted)", color=RED)
    ax.set_title("Convergence", fontsize=11)
    return _svg(fig)


def contact_svg(nominal) -> str:
    """Disc 1, its pins and the first-contact pins of each direction; the zooms show the gap
    at the first-contact pins, magnified so that it shows (factor in the title)."""
    g = nominal.geometry
    prof, centres = nominal.profile_xy_mm, nominal.pin_xy_mm
    first = nominal.discs[0]
    pins = {"ccw": first.contact_pins_ccw, "cw": first.contact_pins_cw}
    fig = plt.figure(figsize=(9.5, 4.2))
    ax = fig.add_axes([0.0, 0.05, 0.45, 0.9])
    ax.fill(prof[:, 0], prof[:, 1], color="#d9e3ef", lw=0.8, ec=BLUE)
    for j, c in enumerate(centres):
        col = RED if j in pins["ccw"] else GREEN if j in pins["cw"] else GREY
        ax.add_patch(plt.Circle(c, g.rrp_mm, fc="none", ec=col, lw=1.6 if col != GREY else 0.6))
    ax.plot(*nominal.disc_centre_xy_mm, "k+", ms=6)
    ax.set_aspect("equal")
    ax.axis("off")
    ax.set_title(f"disc 1 and {g.zp} pins; first contact: red = ccw, green = cw", fontsize=9)
    chi = np.radians(nominal.crank_angle_deg)
    for k, (name, col) in enumerate((("ccw", RED), ("cw", GREEN))):
        if not pins[name]:
            continue
        j = pins[name][0]
        gap = float(nominal.gaps_um[0, j])
        magnify = max(1.0, round(0.15 * g.rrp_mm / max(abs(gap) * 1e-3, 1e-9), -1))
        c = centres[j]
        pitch = g.a_mm * g.zp * np.array([np.cos(chi), np.sin(chi)])
        n = (c - pitch) / np.linalg.norm(c - pitch)  # contact normal, towards the pin
        contact = c - g.rrp_mm * n
        shown = c + (magnify - 1) * gap * 1e-3 * n  # exaggerate the gap along the normal
        zx = fig.add_axes([0.5 + 0.25 * k, 0.12, 0.23, 0.76])
        near = np.where((np.linalg.norm(prof - contact, axis=1) < 3 * g.rrp_mm)[:, None], prof, np.nan)
        zx.plot(near[:, 0], near[:, 1], color=BLUE, lw=1.2)
        zx.add_patch(plt.Circle(shown, g.rrp_mm, fc="none", ec=col, lw=1.4))
        zx.plot(*contact, "k.", ms=3)
        zx.set_xlim(contact[0] - 1.2 * g.rrp_mm, contact[0] + 1.2 * g.rrp_mm)
        zx.set_ylim(contact[1] - 1.2 * g.rrp_mm, contact[1] + 1.2 * g.rrp_mm)
        zx.set_aspect("equal")
        zx.set_xticks([])
        zx.set_yticks([])
        zx.set_title(f"pin {j} ({name}): gap {gap:.2f} µm\n(shown ×{magnify:g})", fontsize=9)
    return _svg(fig)


def preload_svg(sim) -> str:
    """Contact model: backlash of the units whose cycloid stage is free, beside the preload of the
    others, with the share of each."""
    free, pre = sim.outputs["backlash_free"], sim.outputs["preload"]
    fig, axes = plt.subplots(1, 2, figsize=(9.5, 3.6))
    for ax, o, colour, title in ((axes[0], free, BLUE, f"free units ({(1 - sim.preload_fraction) * 100:.1f} %)"),
                                 (axes[1], pre, RED, f"preloaded units ({sim.preload_fraction * 100:.1f} %)")):
        if o.samples:
            ax.stairs(np.asarray(o.histogram.density), np.asarray(o.histogram.edges), fill=True, alpha=0.6,
                      color=colour)
            q = o.quantiles.at(0.99865).value
            if q is not None:
                ax.axvline(q, color="k", ls=":", lw=1, label=f"99.865 %: {q:.3g} {display_unit(o.unit)}")
                ax.legend(fontsize=8)
        else:
            ax.text(0.5, 0.5, "none", ha="center", va="center", transform=ax.transAxes)
        ax.set_title(title, fontsize=10)
        ax.set_xlabel(f"{'output backlash' if o.unit == 'arcmin' else 'preload'} [{display_unit(o.unit)}]")
        ax.set_ylabel(f"density [1/{display_unit(o.unit)}]")
        ax.grid(alpha=0.3)
    fig.tight_layout()
    return _svg(fig)
