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
