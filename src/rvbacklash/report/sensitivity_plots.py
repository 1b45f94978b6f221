"""Figure of the global sensitivity as SVG text (matplotlib, Agg): first-order beside total Sobol
index per factor group, with interval whiskers."""

from __future__ import annotations

import numpy as np

from rvbacklash.report.plots import BLUE, GREY, RED, _svg, plt


def sobol_figure(result, top: int = 15):
    """First-order and total Sobol index of each group side by side, largest total first, with the
    95 % interval as whiskers; the linear model's variance share as a marker."""
    gs = list(result.groups)[:top]
    x = np.arange(len(gs))
    w = 0.38
    fig, ax = plt.subplots(figsize=(8.5, 4.4))
    first = np.array([g.first for g in gs])
    total = np.array([g.total for g in gs])
    ferr = np.array([[g.first - g.first_ci95_low for g in gs], [g.first_ci95_high - g.first for g in gs]])
    terr = np.array([[g.total - g.total_ci95_low for g in gs], [g.total_ci95_high - g.total for g in gs]])
    ax.bar(x - w / 2, first, w, color=BLUE, label="first order S_i", yerr=np.clip(ferr, 0, None), capsize=2,
           error_kw={"lw": 0.8})
    ax.bar(x + w / 2, total, w, color=RED, label="total S_Ti", yerr=np.clip(terr, 0, None), capsize=2,
           error_kw={"lw": 0.8})
    lin = [(i, g.linear_variance_share) for i, g in enumerate(gs) if g.linear_variance_share is not None]
    if lin:
        ax.plot([i for i, _ in lin], [v for _, v in lin], "k_", ms=14, mew=1.5,
                label="linear model, closed form: S²σ²/σ²")
    ax.set_xticks(x)
    ax.set_xticklabels([f"{g.id} {g.input}" if g.id is not None else g.input for g in gs], rotation=50, ha="right",
                       fontsize=8.5)
    ax.set_ylabel("Sobol index [-]")
    ax.set_ylim(bottom=min(0.0, float(np.min(first - ferr[0])) if len(gs) else 0.0))
    ax.axhline(0, color=GREY, lw=0.6)
    ax.grid(axis="y", alpha=0.3)
    ax.legend(fontsize=9)
    ax.set_title(f"Global sensitivity of {result.output} ({result.model} model, N = {result.samples:,}, "
                 f"95 % bootstrap intervals)", fontsize=10)
    return fig


def sobol_svg(result, top: int = 15) -> str:
    return _svg(sobol_figure(result, top))
