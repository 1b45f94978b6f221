"""Figures as SVG text (matplotlib, Agg backend; no display needed)."""

from __future__ import annotations

import io
import re

import matplotlib

matplotlib.use("Agg")
matplotlib.rcParams["svg.hashsalt"] = "rvbacklash"  # stable element ids: same input, same SVG
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def _svg(fig) -> str:
    """SVG text of a figure; text as paths (no font needed), no RDF metadata (no date, no URLs)."""
    buf = io.StringIO()
    fig.savefig(buf, format="svg", bbox_inches="tight", metadata={"Date": None})
    plt.close(fig)
    return re.sub(r"\s*<metadata>.*?</metadata>", "", buf.getvalue(), flags=re.S)


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
    ax.legend(fontsize=7, loc="upper left")
    if title:
        ax.set_title(title, fontsize=10)
    return _svg(fig)


def inline_svg(svg: str) -> str:
    """An SVG document as an element for inline HTML (XML prolog and DOCTYPE removed)."""
    start = svg.find("<svg")
    return svg[start:] if start >= 0 else svg


def pareto_svg(stackup, top: int = 12) -> str:
    """Pareto chart: variance share of each factor, largest first, with the cumulative share."""
    fs = sorted(stackup.factors, key=lambda f: f.rank)[:top]
    names = [f"{f.id} {f.key}" for f in fs]
    shares = np.array([f.variance_share for f in fs]) * 100
    fig, ax = plt.subplots(figsize=(7.5, 3.8))
    ax.bar(range(len(fs)), shares, color="#3b6ea5")
    ax2 = ax.twinx()
    ax2.plot(range(len(fs)), np.cumsum(shares), color="#c0392b", marker="o", ms=3)
    ax2.set_ylim(0, 105)
    ax2.set_ylabel("cumulative [%]")
    ax.set_xticks(range(len(fs)))
    ax.set_xticklabels(names, rotation=60, ha="right", fontsize=7)
    ax.set_ylabel("share of output variance [%]")
    ax.set_title("Which tolerances cause the spread (variance share, S_i² σ_i² / σ²)", fontsize=10)
    ax.grid(axis="y", alpha=0.3)
    return _svg(fig)


def tornado_svg(stackup, top: int = 12) -> str:
    """Tornado chart: output swing over each factor's zone (sensitivity times zone, with sign)."""
    fs = sorted(stackup.factors, key=lambda f: -abs(f.sensitivity_arcmin_per_um) *
                (f.zone_upper_um - f.zone_lower_um))[:top][::-1]
    fig, ax = plt.subplots(figsize=(7.5, 3.8))
    for i, f in enumerate(fs):
        s = f.sensitivity_arcmin_per_um
        lo = s * (f.zone_lower_um - f.raw_mean_um)
        hi = s * (f.zone_upper_um - f.raw_mean_um)
        ax.barh(i, hi, color="#c0392b" if hi > 0 else "#3b6ea5")
        ax.barh(i, lo, color="#c0392b" if lo > 0 else "#3b6ea5")
    ax.set_yticks(range(len(fs)))
    ax.set_yticklabels([f"{f.id} {f.key}" for f in fs], fontsize=7)
    ax.axvline(0, color="k", lw=0.8)
    ax.set_xlabel("change of output backlash from the mean when the factor goes to its zone limits [arcmin]")
    ax.set_title("Sensitivity over the tolerance zone (tornado)", fontsize=10)
    ax.grid(axis="x", alpha=0.3)
    return _svg(fig)


def histogram_svg(sim, spec_arcmin: float | None) -> str:
    """Monte-Carlo histogram (density) with the exact distribution of the linear model."""
    h = sim.histogram
    edges = np.asarray(h["edges"])
    fig, ax = plt.subplots(figsize=(7.5, 3.8))
    ax.stairs(np.asarray(h["density"]), edges, fill=True, alpha=0.5, color="#3b6ea5",
              label=f"Monte-Carlo, {sim.stats['samples_done']:,} samples" if sim.method != "exact" else "exact")
    if sim.exact_curve is not None:
        ax.plot(sim.exact_curve["x"], sim.exact_curve["pdf"], color="k", lw=1.2, label="exact (linear model)")
    if spec_arcmin is not None:
        ax.axvline(spec_arcmin, color="#c0392b", ls="--", lw=1.2, label=f"spec {spec_arcmin:g} arcmin")
    ax.axvline(0, color="grey", lw=0.8)
    ax.set_xlabel("output backlash [arcmin]")
    ax.set_ylabel("density [1/arcmin]")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    return _svg(fig)


def convergence_svg(sim) -> str:
    """Estimate and 95 % interval of the 99.865 % quantile (and the yield) against N."""
    pts = [c for c in sim.convergence if c.get("q99865_arcmin") is not None]
    fig, ax = plt.subplots(figsize=(7.5, 3.4))
    if pts:
        n = np.array([c["samples"] for c in pts], float)
        q = np.array([c["q99865_arcmin"] for c in pts])
        lo = np.array([c["q99865_ci95"][0] if c["q99865_ci95"][0] is not None else np.nan for c in pts])
        hi = np.array([c["q99865_ci95"][1] if c["q99865_ci95"][1] is not None else np.nan for c in pts])
        ax.fill_between(n, lo, hi, alpha=0.3, color="#3b6ea5", label="95 % interval")
        ax.plot(n, q, color="#3b6ea5", marker="o", ms=3, label="99.865 % quantile")
        ax.set_xscale("log")
    ax.set_xlabel("samples N")
    ax.set_ylabel("99.865 % quantile [arcmin]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    yields = [c for c in sim.convergence if c.get("yield") is not None]
    if yields:
        ax3 = ax.twinx()
        ax3.plot([c["samples"] for c in yields], [100 * c["yield"] for c in yields], color="#c0392b", lw=1,
                 ls=":", label="yield")
        ax3.set_ylabel("yield [%]", color="#c0392b")
    ax.set_title("Convergence", fontsize=10)
    return _svg(fig)


def contact_svg(nominal) -> str:
    """Disc 0, its pins and the first-contact pins of each direction; the zooms show the gap
    at the first-contact pins, magnified so that it shows (factor in the title)."""
    from rvbacklash.model.cycloid_geometry import profile_points, rotate

    g, r = nominal.geometry, nominal.realization
    chi = r.chi_rad
    prof = profile_points(g.a_mm, g.rp_mm, g.rrp_mm, g.zc, r.moving_distance_um[0], r.equidistance_um[0])
    prof = rotate(prof, -chi / g.zc) + g.a_mm * np.array([np.cos(chi), np.sin(chi)])
    psi = g.pin_angles
    centres = g.rp_mm * np.stack([np.cos(psi), np.sin(psi)], axis=1)
    pins = nominal.contact_pins[0]
    fig = plt.figure(figsize=(9.5, 4.2))
    ax = fig.add_axes([0.0, 0.05, 0.45, 0.9])
    ax.fill(prof[:, 0], prof[:, 1], color="#d9e3ef", lw=0.8, ec="#3b6ea5")
    for j, c in enumerate(centres):
        col = "#c0392b" if j in pins["ccw"] else "#1f7a3a" if j in pins["cw"] else "#555555"
        ax.add_patch(plt.Circle(c, g.rrp_mm, fc="none", ec=col, lw=1.6 if col != "#555555" else 0.6))
    ax.plot(*g.a_mm * np.array([np.cos(chi), np.sin(chi)]), "k+", ms=6)
    ax.set_aspect("equal")
    ax.axis("off")
    ax.set_title(f"disc 1 and {g.zp} pins; first contact: red = ccw, green = cw", fontsize=8)
    for k, (name, col) in enumerate((("ccw", "#c0392b"), ("cw", "#1f7a3a"))):
        j = pins[name][0]
        gap = float(nominal.gaps_um[0, j])
        magnify = max(1.0, round(0.15 * g.rrp_mm / max(abs(gap) * 1e-3, 1e-9), -1))
        c = centres[j]
        pitch = g.a_mm * g.zp * np.array([np.cos(chi), np.sin(chi)])
        n = (c - pitch) / np.linalg.norm(c - pitch)  # contact normal, towards the pin
        contact = c - g.rrp_mm * n
        # exaggerate the gap: move the pin outwards by (magnify - 1) * gap along the normal
        shown = c + (magnify - 1) * gap * 1e-3 * n
        zx = fig.add_axes([0.5 + 0.25 * k, 0.12, 0.23, 0.76])
        near = np.where((np.linalg.norm(prof - contact, axis=1) < 3 * g.rrp_mm)[:, None], prof, np.nan)
        zx.plot(near[:, 0], near[:, 1], color="#3b6ea5", lw=1.2)
        zx.add_patch(plt.Circle(shown, g.rrp_mm, fc="none", ec=col, lw=1.4))
        zx.plot(*contact, "k.", ms=3)
        zx.set_xlim(contact[0] - 1.2 * g.rrp_mm, contact[0] + 1.2 * g.rrp_mm)
        zx.set_ylim(contact[1] - 1.2 * g.rrp_mm, contact[1] + 1.2 * g.rrp_mm)
        zx.set_aspect("equal")
        zx.set_xticks([])
        zx.set_yticks([])
        zx.set_title(f"pin {j} ({name}): gap {gap:.2f} µm\n(shown x{magnify:g})", fontsize=8)
    return _svg(fig)
