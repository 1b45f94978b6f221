"""Figures of the capacity and life ratings (docs/capacity.md), as SVG text, drawn from results only:
the loads over a revolution (each crank needle bearing's and support bearing's load, the largest pin
force) and the lives of the bearings."""

from __future__ import annotations

import math

import numpy as np

from rvbacklash.report.plots import BLUE, GREEN, GREY, RED, _svg, plt


def loads_figure(result):
    """Loads over one crank revolution against the carrier (a CapacityResult's ``loads`` at the stated
    rated torque): the needle bearings (one line per bearing), the support bearings, the largest pin
    force; beside it each bearing's L10 [h] with the rated life marked."""
    loads = result.loads
    chi = loads.crank_angle_rad
    turn = np.degrees(chi - chi[0]) * loads.geometry.pins / loads.geometry.cycloid_teeth if loads.geometry else \
        np.linspace(0, 360, chi.size, endpoint=False)
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11.0, 4.2), gridspec_kw={"width_ratios": [1.5, 1.0]})
    needle = loads.crank_bearing_load_magnitude_n
    for d in range(needle.shape[1]):
        for c in range(needle.shape[2]):
            ax.plot(turn, needle[:, d, c], color=BLUE, lw=1.0, alpha=0.85,
                    label="crank needle bearings" if d == c == 0 else None)
    support = loads.support_bearing_load_magnitude_n
    for c in range(support.shape[1]):
        for end in range(2):
            ax.plot(turn, support[:, c, end], color=GREEN, lw=1.0, ls="--", alpha=0.85,
                    label="support bearings" if c == end == 0 else None)
    ax.plot(turn, loads.pin_force_n.max(axis=(1, 2)), color=RED, lw=1.4, label="largest pin force")
    ax.set_xlabel("crank rotation against the carrier [deg]")
    ax.set_ylabel("load [N]")
    ax.set_xlim(0, 360)
    ax.grid(alpha=0.3)
    ax.set_title(f"{result.design_name}: loads over a revolution at {loads.output_torque_nm:g} N·m", fontsize=10)
    ax.legend(fontsize=7.5, loc="upper right")
    names = [b.name for b in result.bearings]
    hours = [b.l10_h for b in result.bearings]
    colors = [BLUE if b.kind == "crank_needle" else GREEN for b in result.bearings]
    y = np.arange(len(names))
    bx.barh(y, [h if math.isfinite(h) else 0.0 for h in hours], color=colors, alpha=0.85)
    bx.axvline(result.rated_life_h, color=GREY, ls=":", lw=1.2)
    bx.axvline(result.reducer_life_h, color=RED, lw=1.4)
    bx.set_yticks(y, names, fontsize=7)
    bx.set_xscale("log")
    bx.xaxis.set_minor_formatter(plt.NullFormatter())
    bx.set_xlabel("L10 [h]")
    bx.set_title(f"lives at {result.rated_output_speed_rpm:g} r/min: reducer {result.reducer_life_h:.0f} h (red), "
                 f"rated {result.rated_life_h:g} h (dotted)", fontsize=9)
    bx.grid(alpha=0.3, axis="x")
    fig.tight_layout()
    return fig


def loads_svg(result) -> str:
    """SVG of ``loads_figure``."""
    return _svg(loads_figure(result))


FAMILY_COLORS = {"clearance": BLUE, "modification": GREEN, "edit": GREY}
FAMILY_LABELS = {"clearance": "crank-bearing clearance / preload", "modification": "equidistance modification",
                 "edit": "other what-ifs"}


def trade_figure(trade):
    """Lost motion against life (a CapacityTrade): each point's nominal lost motion [arcmin] against
    its reducer L10 [h] at the stated rated torque; a family's what-ifs (the clearance's, the
    modification's) joined through the design's own point, in the order of their value; the design
    as given in red; the rated life dotted."""
    design = trade.points[0]
    fig, ax = plt.subplots(figsize=(8.0, 4.4))
    for family, color in FAMILY_COLORS.items():
        pts = [p for p in trade.points[1:] if p.family == family]
        if not pts:
            continue
        if family in ("clearance", "modification"):  # a curve through the design's own value
            key = (lambda p: p.crank_clearance_um) if family == "clearance" else \
                (lambda p: p.equidistance_modification_um)
            line = sorted(pts + [design], key=key)
            ax.plot([p.lost_motion_arcmin for p in line], [p.reducer_life_h for p in line], color=color, lw=1.0,
                    alpha=0.6)
        ax.scatter([p.lost_motion_arcmin for p in pts], [p.reducer_life_h for p in pts], color=color, s=28, zorder=3,
                   label=FAMILY_LABELS[family])
        for p in pts:
            value = p.crank_clearance_um if family == "clearance" else (
                p.equidistance_modification_um if family == "modification" else None)
            ax.annotate(f"{value:g} µm" if value is not None else p.name, (p.lost_motion_arcmin, p.reducer_life_h),
                        textcoords="offset points", xytext=(5, 4), fontsize=7, color=color)
    ax.scatter([design.lost_motion_arcmin], [design.reducer_life_h], color=RED, s=60, marker="D", zorder=4,
               label=f"the design: {design.lost_motion_arcmin:.3g} arcmin, {design.reducer_life_h:,.0f} h")
    ax.axhline(trade.rated_life_h, color=GREY, ls=":", lw=1.2)
    ax.set_xlabel("lost motion of the nominal unit [arcmin]")
    ax.set_ylabel(f"reducer L10 at {trade.stated_rated_torque_nm:g} N·m [h]")
    ax.set_title(f"{trade.design_name}: lost motion against life ({trade.life_method}, "
                 f"{trade.rated_output_speed_rpm:g} r/min; rated life {trade.rated_life_h:g} h dotted)", fontsize=9.5)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7.5, loc="best")
    fig.tight_layout()
    return fig


def trade_svg(trade) -> str:
    """SVG of ``trade_figure``."""
    return _svg(trade_figure(trade))
