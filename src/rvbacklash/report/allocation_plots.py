"""Figure of a tolerance allocation as SVG text (matplotlib, Agg): the cost-yield Pareto front
with the uniform grades, the chosen design and the baseline."""

from __future__ import annotations

import numpy as np

from rvbacklash.report.plots import BLUE, GREY, RED, _svg, plt


def front_figure(result):
    """Cost against yield of the non-dominated designs (the Pareto front), the uniform grades and
    the chosen design; yield as the out-of-spec fraction on a log axis."""
    fig, ax = plt.subplots(figsize=(8.0, 4.4))

    def series(points):
        c = np.array([p.cost for p in points], float)
        y = np.array([p.yield_.fraction for p in points], float)
        lo = np.array([p.yield_.ci95_low for p in points], float)
        hi = np.array([p.yield_.ci95_high for p in points], float)
        return c, np.clip(1 - y, 1e-9, None), np.clip(1 - hi, 1e-9, None), np.clip(1 - lo, 1e-9, None)

    front = [p for p in result.front]
    if front:
        c, out, lo, hi = series(front)
        ax.errorbar(c, out, yerr=[np.clip(out - lo, 0, None), np.clip(hi - out, 0, None)], color=BLUE, marker="o",
                    ms=4, lw=1.2, capsize=2, label="Pareto front (cheapest design per yield)")
    if result.uniform:
        c, out, _, _ = series(result.uniform)
        ax.plot(c, out, ls="none", marker="s", ms=5, mfc="none", color=GREY, label="uniform grades")
        for p, ci, oi in zip(result.uniform, c, out):
            ax.annotate(str(next(iter(p.grades.values()))), (ci, oi), textcoords="offset points", xytext=(4, 3),
                        fontsize=7, color=GREY)
    ax.plot([result.cost], [max(1 - result.yield_.fraction, 1e-9)], marker="*", ms=14, color=RED, ls="none",
            label=f"chosen: cost {result.cost:.4g}")
    if result.baseline.cost is not None:
        ax.plot([result.baseline.cost], [max(1 - result.baseline.yield_.fraction, 1e-9)], marker="D", ms=7,
                color="k", mfc="none", ls="none", label=f"baseline: uniform grade {result.baseline.grade}")
    ax.axhline(1 - result.yield_target, color=RED, ls="--", lw=1, label=f"target yield {result.yield_target:g}")
    ax.set_yscale("log")
    ax.invert_yaxis()
    ax.set_xlabel(f"cost [{result.unit}]")
    what = f"{result.output} ≤ {result.spec_arcmin:g} arcmin" if result.spec_accuracy_life_h is None else \
        f"lost motion ≤ {result.spec_arcmin:g} arcmin for {result.spec_accuracy_life_h:g} h"
    ax.set_ylabel(f"out of spec, 1 - P({what})")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8, loc="lower right")
    ax.set_title(f"{result.design_name}: cost against yield ({result.model} model)", fontsize=10)
    return fig


def front_svg(result) -> str:
    return _svg(front_figure(result))
