"""Figures of the service life (docs/service-life.md), as SVG text, drawn from a ServiceLifeResult:
lost motion against hours (the nominal unit, the production run's 5 / 50 / 95 % units, the spec),
the run's yield against hours, the worn flank along its tooth."""

from __future__ import annotations

import numpy as np

from rvbacklash.report.plots import BLUE, GREEN, GREY, RED, _svg, plt


def service_life_figure(result):
    """Three panels: lost motion vs hours, yield vs hours (with the production run), worn flank."""
    prod = result.production
    panels = 3 if prod is not None else 2
    fig, axes = plt.subplots(1, panels, figsize=(4.4 * panels, 4.0))
    ax = axes[0]
    traj = result.trajectory
    hours = np.array([p.hours for p in traj])
    ax.plot(hours, [p.lost_motion_arcmin for p in traj], color=BLUE, lw=1.6, marker=".", label="nominal unit")
    if prod is not None:
        grid = np.array(prod.grid_hours)
        q = np.array(prod.grid_lost_motion_arcmin)
        ax.fill_between(grid, q[:, 0], q[:, 2], color=GREEN, alpha=0.2, label="production 5-95 %")
        ax.plot(grid, q[:, 1], color=GREEN, lw=1.2, label="production median")
        ax.axhline(prod.spec_lost_motion_arcmin, color=RED, ls="--", lw=1.2, label="spec")
    ax.set_xlabel("hours of the duty cycle [h]")
    ax.set_ylabel("lost motion [arcmin]")
    ax.set_title(f"{result.design_name}: lost motion over the service life", fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7.5)
    if prod is not None:
        bx = axes[1]
        bx.plot(prod.grid_hours, np.array(prod.grid_yield) * 100, color=GREEN, lw=1.6, marker=".")
        for h, p in zip(prod.hours, prod.yield_at_hours):
            bx.errorbar([h], [p.fraction * 100], yerr=[[100 * (p.fraction - p.ci95_low)],
                                                       [100 * (p.ci95_high - p.fraction)]], color=GREY, capsize=3)
        bx.set_xlabel("hours of the duty cycle [h]")
        bx.set_ylabel(f"yield: lost motion <= {prod.spec_lost_motion_arcmin:g} arcmin [%]")
        bx.set_ylim(0, 100)
        bx.set_title(f"{prod.units:,} units (95 % intervals at the asked hours)", fontsize=9)
        bx.grid(alpha=0.3)
    cx = axes[-1]
    prof = result.flank_profile
    for d, w in enumerate(prof.wear_um):
        cx.plot(prof.phase_deg, w, lw=1.2, label=f"disc {d + 1}")
    cx.set_xlabel("phase of the meeting pin [deg] (0 root, 180 tip)")
    cx.set_ylabel("flank wear depth [um]")
    cx.set_xlim(0, 360)
    cx.set_title(f"worn flank after {prof.hours:g} h", fontsize=9)
    cx.grid(alpha=0.3)
    cx.legend(fontsize=7.5)
    fig.tight_layout()
    return fig


def service_life_svg(result) -> str:
    """SVG of ``service_life_figure``."""
    return _svg(service_life_figure(result))
