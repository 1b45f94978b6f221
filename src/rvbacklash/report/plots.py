"""Figures as SVG text (matplotlib, Agg backend; no display needed)."""

from __future__ import annotations

import io

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def _svg(fig) -> str:
    buf = io.StringIO()
    fig.savefig(buf, format="svg", bbox_inches="tight")
    plt.close(fig)
    return buf.getvalue()


def cdf_points(result) -> tuple[np.ndarray, np.ndarray]:
    """(x [arcmin], P(backlash <= x)) of a SimulationResult: the sampled histogram's cdf, or
    the exact cdf for the exact method."""
    h = result.histogram
    edges = np.asarray(h["edges"])
    if h.get("counts") is not None:
        c = np.cumsum(np.asarray(h["counts"], float))
        n = result.stats["samples_done"]
        below = h.get("underflow") or 0
        return edges, np.concatenate([[below], below + c]) / n
    curve = result.exact_curve
    return np.asarray(curve["x"]), np.asarray(curve["cdf"])


def scenario_overlay_svg(scenarios, spec_arcmin: float | None = None, title: str = "") -> str:
    """Cumulative distributions of the output backlash of several scenarios on one axis."""
    fig, ax = plt.subplots(figsize=(7.5, 4.2))
    for s in scenarios:
        x, p = cdf_points(s.result)
        ax.plot(x, p, label=f"{s.name}  (q99.865 = {s.result.stats['quantiles']['0.99865']['value']:.3f})")
    if spec_arcmin is not None:
        ax.axvline(spec_arcmin, color="k", ls="--", lw=1, label=f"spec {spec_arcmin:g} arcmin")
    ax.set_xlabel("output backlash [arcmin]")
    ax.set_ylabel("P(backlash <= x)")
    ax.set_ylim(0, 1)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="lower right")
    if title:
        ax.set_title(title, fontsize=10)
    return _svg(fig)
