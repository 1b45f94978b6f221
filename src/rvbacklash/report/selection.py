"""Selective assembly on the terminal: the yields from random and selected assembly side by side,
each class's share of the parts bought and of the units built, the surplus; the assembly sheet's
summary (docs/selective-assembly.md)."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from rich.console import Console
from rich.markup import escape
from rich.table import Table

from rvbacklash.units import display_unit

if TYPE_CHECKING:  # pragma: no cover
    from rvbacklash.analysis.selection.run import SelectionResult


def _pct(p) -> tuple[str, str]:
    if p is None:
        return "-", ""
    return f"{p.fraction * 100:.2f} %", f"[{p.ci95_low * 100:.2f} %, {p.ci95_high * 100:.2f} %]"


def print_selection(r: "SelectionResult", console: Console) -> None:
    """The comparison tables of a SelectionResult (the selected run's own tables are printed before it)."""
    head = (f"[bold]{escape(r.design_name)}[/]  selective assembly {escape(str(r.selection))}: "
            f"{r.samples_done:,} units, seed {r.seed} (the same units assembled at random and selected)")
    if r.partial:
        head += "  [bold red]PARTIAL: interrupted[/]"
    console.print(head)
    t = Table(title="yield: random assembly vs selected", title_justify="left")
    for c in ("spec", "random", "95 % interval", "selected", "95 % interval ", "gain"):
        t.add_column(c, justify="left" if c == "spec" else "right")
    for y in r.yields:
        spec = "joint (every spec)" if y.output == "joint" else f"{y.output} <= {y.spec:g} {display_unit(y.unit)}"
        if y.output == "rigidity":
            spec = f"{y.output} >= {y.spec:g} {display_unit(y.unit)}"
        gain = y.gain
        t.add_row(escape(spec), *_pct(y.random), *_pct(y.selected),
                  "-" if gain is None else f"{gain * 100:+.2f} pts")
    console.print(t)
    t = Table(title="classes: share of the parts bought, of the units built, surplus per unit built [sets]",
              title_justify="left")
    for c in ("part", "class", "band [µm]", "mean [µm]", "bought", "used", "surplus"):
        t.add_column(c, justify="left" if c == "part" else "right")
    for c in r.classes:
        lo, hi = sorted((c.lower_um, c.upper_um))
        band = f"{'-inf' if math.isinf(lo) else f'{lo:.2f}'} .. {'inf' if math.isinf(hi) else f'{hi:.2f}'}"
        t.add_row(c.part + (" (radius)" if c.part == "pins" else " (clearance)"), str(c.class_index), band,
                  f"{c.mean_um:.3f}", f"{c.share_bought * 100:.1f} %", f"{c.share_used * 100:.1f} %",
                  f"{c.surplus_sets_per_unit:.3f}")
    console.print(t)
    console.print(f"pins: {r.pin_sets_per_unit:.3f} sets bought per unit built (surplus {r.pin_surplus_fraction:.1%}); "
                  f"rollers: {r.roller_sets_per_unit:.3f} (surplus {r.roller_surplus_fraction:.1%})")


def class_sweep_svg(sweep) -> str:
    """Yield versus the number of pin classes, one line per class width (and noise), random assembly
    as a dashed line; each point's 95 % interval as a bar; the pins' surplus on a second panel."""
    import io

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(10, 4))
    keys = sorted({(p.pin_width_um, p.noise_um) for p in sweep.points})
    for w, s in keys:
        pts = sorted((p for p in sweep.points if (p.pin_width_um, p.noise_um) == (w, s)), key=lambda p: p.pin_classes)
        x = [p.pin_classes for p in pts]
        y = [p.yield_.fraction * 100 for p in pts]
        err = [[(p.yield_.fraction - p.yield_.ci95_low) * 100 for p in pts],
               [(p.yield_.ci95_high - p.yield_.fraction) * 100 for p in pts]]
        label = f"pin classes {w:g} µm wide" + (f", noise {s:g} µm" if s else "")
        ax.errorbar(x, y, yerr=err, marker="o", capsize=3, label=label)
        bx.plot(x, [p.pin_surplus_fraction * 100 for p in pts], marker="o", label=label)
    ax.axhline(sweep.random_yield.fraction * 100, color="k", ls="--", label="random assembly")
    ax.set_xlabel("pin diameter classes")
    ax.set_ylabel(f"yield {sweep.output} ≤ {sweep.spec:g} [%]")
    ax.set_title(f"{sweep.design_name}: yield with rollers {sweep.rollers} ({sweep.samples:,} units)")
    ax.legend(fontsize=8)
    bx.set_xlabel("pin diameter classes")
    bx.set_ylabel("pins bought and left over [%]")
    bx.set_title("pin surplus (unlimited supply)")
    fig.tight_layout()
    buf = io.StringIO()
    fig.savefig(buf, format="svg")
    plt.close(fig)
    return buf.getvalue()
