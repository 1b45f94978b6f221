"""Figures of measured units (docs/bench-data.md), as SVG text: each loop's samples and its
averaged branches with the definitions drawn on it (the lost-motion readings at +-x T_R, the
backlash at zero torque, the rigidity's secant), beside the design's nominal unit and its 5 % /
95 % units; each TE curve and its spectrum by order (a unit's forward and backward runs in one
colour, solid and dashed), its lost motion against output position beside the model's; a
calibration's before/after overlay."""

from __future__ import annotations

from typing import Sequence

import numpy as np

from rvbacklash.analysis.bench import BenchLoop, BenchTransmissionError, BenchTwoRunTE
from rvbacklash.analysis.loop_reading import angle_at, as_branches
from rvbacklash.report.plots import BLUE, GREEN, GREY, RED, _svg, plt

UNIT_COLORS = ("#3b6ea5", "#c0392b", "#1f7a3a", "#8e44ad", "#d35400", "#16a085", "#2c3e50")


def _definitions(ax, u: BenchLoop, color: str) -> None:
    """The readings of the definitions on a loop: lost motion (the four points at +-x T_R and
    their means), backlash (the two points at zero torque), the rigidity's secant."""
    b = as_branches(u.loop)
    tr, x = u.rated_torque_nm, u.measuring_torque_fraction * u.rated_torque_nm
    pts = [(angle_at(*b[n], t, n), t) for n, t in (("load+", x), ("unload+", x), ("load-", -x), ("unload-", -x))]
    ax.plot(*zip(*pts), "o", ms=4, mfc="none", color=color)
    zero = [(angle_at(*b[n], 0.0, n), 0.0) for n in ("unload+", "unload-")]
    ax.plot(*zip(*zero), "s", ms=4, color=color)
    ax.annotate("", xy=zero[0], xytext=zero[1], arrowprops={"arrowstyle": "<->", "color": color, "lw": 0.8})
    lo, hi = u.rigidity_interval_fraction
    for name, sign in (("load+", 1.0), ("load-", -1.0)):
        t0, t1 = sign * lo * tr, sign * hi * tr
        ax.plot([angle_at(*b[name], t0, name), angle_at(*b[name], t1, name)], [t0, t1], "--", color=color, lw=0.9)


def loop_figure(units: Sequence[BenchLoop], nominal=None, others: Sequence = (), title: str = ""):
    """Every measured loop (samples as dots, averaged branches as lines, the definitions marked),
    the design's nominal unit (and e.g. its 5 % / 95 % units) dashed; a zoom near zero beside it."""
    fig, (ax, zx) = plt.subplots(1, 2, figsize=(10.0, 4.6), gridspec_kw={"width_ratios": [1.35, 1.0]})
    draw_loops(fig, ax, zx, units, nominal, others, title)
    return fig


def draw_loops(fig, ax, zx, units: Sequence[BenchLoop], nominal=None, others: Sequence = (), title: str = "") -> None:
    u0 = units[0]
    x = u0.measuring_torque_fraction * u0.rated_torque_nm
    for k, u in enumerate(units):
        color = UNIT_COLORS[k % len(UNIT_COLORS)]
        label = (f"{u.source}: lost motion {u.lost_motion_arcmin:.3f} ± {u.uncertainty_k2['lost_motion_arcmin']:.3f}, "
                 f"backlash {u.backlash_arcmin:.3f} arcmin, rigidity {u.torsional_rigidity_nm_per_arcmin:.0f} "
                 f"N·m/arcmin")
        for a in (ax, zx):
            a.plot(u.angle_arcmin, u.torque_nm, ".", ms=1.2, color=color, alpha=0.35, rasterized=True)
            for i, br in enumerate(u.loop):
                a.plot(br.angle_arcmin, br.torque_nm, "-", color=color, lw=1.1,
                       label=label if i == 0 and a is ax else None)
            _definitions(a, u, color)
    for r, (color, ls) in zip((nominal, *others), ((GREY, "--"), (GREEN, ":"), (RED, ":"), (BLUE, "-."))):
        if r is None:
            continue
        for i, br in enumerate(r.loop):
            for a in (ax, zx):
                a.plot(br.angle_arcmin, br.torque_nm, ls, color=color, lw=1.0,
                       label=f"model, {r.unit}: lost motion {r.lost_motion_arcmin:.3f} arcmin"
                       if i == 0 and a is ax else None)
    for a in (ax, zx):
        a.axhline(0, color="k", lw=0.5)
        a.axvline(0, color="k", lw=0.5)
        for t in (x, -x):
            a.axhline(t, color=GREY, lw=0.7, ls=":")
        a.grid(alpha=0.3)
        a.set_xlabel("output angle [arcmin]")
    ax.set_ylabel("output torque [N·m]")
    ax.set_title(title or f"measured loops, T_R = {u0.rated_torque_nm:g} N·m\n○ lost-motion readings at "
                          f"±{u0.measuring_torque_fraction * 100:g} % T_R, ■ backlash, -- rigidity secant",
                 fontsize=9)
    zx.set_ylim(-5 * x, 5 * x)
    near = [a for u in units for br in u.loop for t, a in zip(br.torque_nm, br.angle_arcmin) if abs(t) <= 5 * x]
    if near:
        span = max(abs(min(near)), abs(max(near)), 1e-3)
        zx.set_xlim(-1.3 * span, 1.3 * span)
    zx.set_title("near zero torque", fontsize=9)
    ax.legend(*ax.get_legend_handles_labels(), fontsize=6.5, loc="upper left", bbox_to_anchor=(0.0, -0.14),
              frameon=False)


def te_figure(units: Sequence[BenchTransmissionError]):
    """Each TE curve over the output revolution and its amplitude spectrum by order."""
    fig, (ax, sx) = plt.subplots(1, 2, figsize=(10.0, 3.8))
    draw_te(ax, sx, units)
    return fig


def draw_te(ax, sx, units: Sequence[BenchTransmissionError], styles: Sequence[tuple[str, str]] = ()) -> None:
    """Each curve and its spectrum; ``styles``: (colour, line style) of each unit (default: a colour
    each, solid)."""
    for k, u in enumerate(units):
        color, ls = styles[k] if k < len(styles) else (UNIT_COLORS[k % len(UNIT_COLORS)], "-")
        order = np.argsort(u.output_angle_deg)
        ax.plot(np.asarray(u.output_angle_deg)[order], np.asarray(u.te_arcsec)[order], ls, color=color, lw=0.9,
                label=f"{u.source}: TE p-p {u.te_peak_to_peak_arcsec:.2f} arcsec")
        spec = np.asarray(u.spectrum_amplitude_arcsec)
        m = np.arange(spec.size)
        top = max((s.order for s in u.leading_orders), default=10)
        show = m[1:min(spec.size, max(2 * top, 20) + 1)]
        sx.vlines(show + 0.15 * k, 0, spec[show], color=color, lw=1.2, linestyles="dashed" if ls != "-" else "solid")
        sx.axhline(u.spectrum_floor_arcsec, color=color, lw=0.6, ls=":")
    ax.set_xlabel("output angle [deg]")
    ax.set_ylabel("transmission error [arcsec]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    sx.set_xlabel("order [per output revolution]")
    sx.set_ylabel("amplitude [arcsec]")
    sx.set_title("spectrum (dotted: the noise floor below which no line is listed)", fontsize=9)
    sx.grid(alpha=0.3)


def draw_lost_motion(ax, units: Sequence[BenchTwoRunTE], te_model=None, first_color: int = 0) -> None:
    """Each unit's lost motion against output position (the gap between its runs) and its mean;
    the design's nominal unit's (``te_model``: a TransmissionErrorResult, rigid and unloaded)
    dashed, the production run's 5-95 % band of the mean when the unit was placed."""
    banded = False
    for k, u in enumerate(units):
        color = UNIT_COLORS[(first_color + k) % len(UNIT_COLORS)]
        order = np.argsort(u.output_angle_deg)
        ax.plot(np.asarray(u.output_angle_deg)[order], np.asarray(u.lost_motion_arcmin)[order], color=color, lw=0.9,
                label=f"{u.source}: lost motion, mean {u.lost_motion_mean_arcmin:.4f} arcmin ({u.ccw_run} run above)")
        ax.axhline(u.lost_motion_mean_arcmin, color=color, lw=0.8, ls=":")
        for p in u.placement:
            if p.figure == "lost_motion_mean_arcmin" and not banded:
                ax.axhspan(p.predicted_q05, p.predicted_q95, color=GREY, alpha=0.15,
                           label="the design's production run: mean lost motion, 5-95 %")
                banded = True
    if te_model is not None:
        lm = np.asarray(te_model.lost_motion_arcmin)
        ax.plot(te_model.output_angle_deg, lm, "--", color=GREY, lw=1.0,
                label=f"model, {te_model.design_name} {te_model.unit} unit (rigid, no load): mean "
                      f"{float(np.mean(lm)):.4f} arcmin")
    ax.set_xlabel("output angle [deg]")
    ax.set_ylabel("lost motion [arcmin]")
    ax.set_title("lost motion against output position: backward minus forward TE (the upper run as the ccw flank), "
                 "the transmission model's definition", fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)


def bench_svg(result, nominal=None, others: Sequence = (), te_model=None) -> str:
    """SVG of a BenchResult: its loops (with the model's loops given), its TE curves (each unit's
    runs), the lost motion of units of two runs (with ``te_model``'s, a TransmissionErrorResult)."""
    loops = [u for u in result.units if isinstance(u, BenchLoop)]
    tes = [u for u in result.units if isinstance(u, BenchTransmissionError)]
    two = [u for u in result.units if isinstance(u, BenchTwoRunTE)]
    rows = int(bool(loops)) + int(bool(tes or two)) + int(bool(two))
    fig = plt.figure(figsize=(10.0, 4.8 * rows))
    grid = fig.add_gridspec(rows, 2, width_ratios=[1.35, 1.0] if loops else [1.0, 1.0], hspace=0.75)
    row = 0
    if loops:
        draw_loops(fig, fig.add_subplot(grid[row, 0]), fig.add_subplot(grid[row, 1]), loops, nominal, others)
        row += 1
    if tes or two:
        curves = list(tes) + [r for u in two for r in (u.forward, u.backward)]
        styles = [(UNIT_COLORS[k % len(UNIT_COLORS)], "-") for k in range(len(tes))]
        styles += [(UNIT_COLORS[(len(tes) + k) % len(UNIT_COLORS)], ls) for k in range(len(two)) for ls in ("-", "--")]
        draw_te(fig.add_subplot(grid[row, 0]), fig.add_subplot(grid[row, 1]), curves, styles)
        row += 1
    if two:
        draw_lost_motion(fig.add_subplot(grid[row, :]), two, te_model, first_color=len(tes))
    return _svg(fig)


def calibration_figure(cal):
    """The measured samples with the design's nominal loop before and after calibration."""
    fig, (ax, zx) = plt.subplots(1, 2, figsize=(10.0, 4.4), gridspec_kw={"width_ratios": [1.35, 1.0]})
    units = [u for u in cal.bench.units if isinstance(u, BenchLoop)]
    for k, u in enumerate(units):
        for a in (ax, zx):
            a.plot(u.angle_arcmin, u.torque_nm, ".", ms=1.2, color=UNIT_COLORS[k % len(UNIT_COLORS)], alpha=0.35,
                   rasterized=True,
                   label=f"measured: {u.source}" if a is ax else None)
    for r, color, ls, what in ((cal.before_loop, GREY, "--", "before (the design)"),
                               (cal.after_loop, RED, "-", "after (calibrated)")):
        for i, br in enumerate(r.loop):
            for a in (ax, zx):
                a.plot(br.angle_arcmin, br.torque_nm, ls, color=color, lw=1.2,
                       label=f"{what}: lost motion {r.lost_motion_arcmin:.3f} arcmin, rigidity "
                             f"{r.torsional_rigidity_nm_per_arcmin:.0f} N·m/arcmin" if i == 0 and a is ax else None)
    x = cal.after_loop.measuring_torque_fraction * cal.after_loop.rated_torque_nm
    for a in (ax, zx):
        a.axhline(0, color="k", lw=0.5)
        a.axvline(0, color="k", lw=0.5)
        a.grid(alpha=0.3)
        a.set_xlabel("output angle [arcmin]")
    ax.set_ylabel("output torque [N·m]")
    ax.set_title(f"{cal.design_name}: calibration on {len(units)} measured loop(s)", fontsize=10)
    zx.set_ylim(-5 * x, 5 * x)
    near = [a for br in cal.after_loop.loop for t, a in zip(br.torque_nm, br.angle_arcmin) if abs(t) <= 5 * x]
    if near:
        span = max(abs(min(near)), abs(max(near)), 1e-3)
        zx.set_xlim(-1.3 * span, 1.3 * span)
    zx.set_title("near zero torque", fontsize=9)
    fig.legend(*ax.get_legend_handles_labels(), fontsize=7, loc="upper center", bbox_to_anchor=(0.5, 0.0), ncol=1,
               frameon=False, markerscale=6)
    return fig


def calibration_svg(cal) -> str:
    return _svg(calibration_figure(cal))
