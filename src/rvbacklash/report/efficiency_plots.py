"""Figures of the losses (docs/efficiency.md), as SVG text, drawn from results only: the efficiency
map against output torque at each output speed, the no-load running torque against input speed at
each temperature, and each element's loss at the rated point."""

from __future__ import annotations

import numpy as np

from rvbacklash.report.plots import BLUE, GREY, RED, _svg, plt


def efficiency_figure(result):
    """Three panels of an EfficiencyResult: the map, the no-load running torque, the losses per element."""
    fig, (ax, bx, cx) = plt.subplots(1, 3, figsize=(13.5, 4.2), gridspec_kw={"width_ratios": [1.2, 1.0, 1.0]})
    speeds = sorted({p.output_speed_rpm for p in result.efficiency_map})
    cmap = plt.get_cmap("viridis")
    for i, n in enumerate(speeds):
        pts = sorted((p.output_torque_nm, p.efficiency) for p in result.efficiency_map if p.output_speed_rpm == n)
        ax.plot([t for t, _ in pts], [100 * e for _, e in pts], marker="o", ms=3, lw=1.2,
                color=cmap(i / max(len(speeds) - 1, 1)), label=f"{n:g} r/min")
    ax.axvline(result.rated_torque_nm, color=GREY, ls=":", lw=1.0)
    ax.set_xlabel("output torque [N·m]")
    ax.set_ylabel("efficiency [%]")
    ax.set_title(f"{result.design_name}: efficiency at {result.temperature_c:g} °C (output speeds)", fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7.5, loc="lower right")
    temps = sorted({p.temperature_c for p in result.no_load_running_torque})
    for i, t in enumerate(temps):
        pts = sorted((p.input_speed_rpm, p.no_load_torque_nm) for p in result.no_load_running_torque
                     if p.temperature_c == t)
        bx.plot([n for n, _ in pts], [q for _, q in pts], marker="o", ms=3, lw=1.2,
                color=plt.get_cmap("plasma")(i / max(len(temps) - 1, 1)), label=f"{t:g} °C")
    bx.set_xlabel("input speed [r/min]")
    bx.set_ylabel("no-load running torque at the input [N·m]")
    bx.set_title("no-load running torque", fontsize=10)
    bx.grid(alpha=0.3)
    bx.legend(fontsize=7.5)
    names = [e.element for e in result.elements]
    y = np.arange(len(names))
    cx.barh(y, [e.loss_w for e in result.elements], color=[RED if e.loss_w == max(x.loss_w for x in result.elements)
                                                          else BLUE for e in result.elements], alpha=0.85)
    cx.set_yticks(y, names, fontsize=7.5)
    cx.invert_yaxis()
    cx.set_xlabel("loss [W]")
    cx.set_title(f"losses at {result.rated_torque_nm:g} N·m, {result.rated_output_speed_rpm:g} r/min: "
                 f"η = {100 * result.efficiency_at_rated:.1f} %", fontsize=9)
    cx.grid(alpha=0.3, axis="x")
    fig.tight_layout()
    return fig


def efficiency_svg(result) -> str:
    """SVG of ``efficiency_figure``."""
    return _svg(efficiency_figure(result))
