"""Rich tables of the global sensitivity and the tolerance allocation for the terminal."""

from __future__ import annotations

from typing import TYPE_CHECKING

from rich.console import Console
from rich.markup import escape
from rich.table import Table

if TYPE_CHECKING:
    from rvbacklash.analysis.allocation import AllocationResult
    from rvbacklash.analysis.sensitivity_global import SensitivityResult


def _ci(value: float, lo: float, hi: float) -> str:
    return escape(f"{value:.4f} [{lo:.4f}, {hi:.4f}]")


def print_sensitivity(result: SensitivityResult, console: Console) -> None:
    r = result
    console.print(f"[bold]{escape(r.design_name)}[/]  {r.model} model, output {r.output} {escape('[' + r.unit + ']')}: "
                  f"mean {r.mean:.4g}, sigma {r.sigma:.4g}; N = {r.samples:,} per set, {r.model_runs:,} model runs, "
                  f"seed {r.seed}, {r.resamples} bootstrap resamples"
                  + (" [bold red](PARTIAL: interrupted)[/]" if r.partial else ""))
    t = Table(title="Sobol indices per factor group, with 95 % intervals (largest total index first)",
              title_justify="left")
    for col, just in [("rank", "right"), ("id", "right"), ("factor", "left"), ("first order [95 % CI]", "right"),
                      ("total [95 % CI]", "right"), ("linear var. share", "right"), ("linear rank", "right")]:
        t.add_column(escape(col), justify=just)
    for g in r.groups:
        t.add_row(str(g.rank), "" if g.id is None else str(g.id), g.input,
                  _ci(g.first, g.first_ci95_low, g.first_ci95_high), _ci(g.total, g.total_ci95_low, g.total_ci95_high),
                  "" if g.linear_variance_share is None else f"{g.linear_variance_share:.4f}",
                  "" if g.linear_rank is None else str(g.linear_rank))
    console.print(t)
    console.print(f"sum of first-order indices {r.sum_first:.4f} (1 for an additive model); {escape(r.method)}",
                  style="dim")
    for note in r.notes:
        console.print(escape(note), style="dim")


def print_allocation(result: AllocationResult, console: Console) -> None:
    r = result
    y = r.yield_
    exact = y.ci95_low == y.ci95_high
    console.print(f"[bold]{escape(r.design_name)}[/]  {r.model} model: {escape(r.binding.constraint)}"
                  + (" [bold red](PARTIAL: interrupted)[/]" if r.partial else ""))
    t = Table(title=escape(f"Grades before -> after (cost in {r.unit})"), title_justify="left")
    for col, just in [("part group", "left"), ("grade table", "left"), ("before", "right"), ("after", "right"),
                      ("allowed", "right"), ("cost before", "right"), ("cost after", "right"), ("factors", "left")]:
        t.add_column(escape(col), justify=just)
    for g in r.groups:
        change = "" if g.grade_before is None or g.grade_before == g.grade_after else \
            (" [green](coarser)[/]" if g.grade_after > g.grade_before else " [yellow](finer)[/]")
        t.add_row(g.group, g.grade_table, "mixed" if g.grade_before is None else str(g.grade_before),
                  f"{g.grade_after}{change}", f"{g.grade_min}-{g.grade_max}",
                  "" if g.cost_before is None else f"{g.cost_before:.4g}", f"{g.cost_after:.4g}", ", ".join(g.factors))
    console.print(t)
    s = Table(title="Result", title_justify="left")
    for col in ("", "cost", "yield", "95 % interval"):
        s.add_column(col, justify="left" if col == "" else "right")

    def yrow(p):
        return ("", "") if p is None else (f"{p.fraction:.6f}", "exact" if p.ci95_low == p.ci95_high
                                            else escape(f"[{p.ci95_low:.6f}, {p.ci95_high:.6f}]"))

    s.add_row("allocated", f"{r.cost:.4g}", *yrow(y))
    if r.verification is not None:
        s.add_row("  re-run, independent stream", "", *yrow(r.verification))
    s.add_row("design as given", "" if r.cost_before is None else f"{r.cost_before:.4g}", *yrow(r.yield_before))
    b = r.baseline
    if b.cost is not None:
        s.add_row(f"baseline: uniform grade {b.grade}", f"{b.cost:.4g}", *yrow(b.yield_))
    else:
        s.add_row("baseline: no uniform grade meets the spec", "", "", "")
    console.print(s)
    if r.saving is not None:
        console.print(f"saving against the baseline: {r.saving:.4g} {escape(r.unit)} ({r.saving_fraction:.1%})")
    bd = r.binding
    console.print(f"binding constraint: {escape(bd.constraint)}, slack {bd.slack:.3g}"
                  + ("" if exact else " (lower end of the 95 % interval)")
                  + (f"; at their finest allowed grade: {', '.join(bd.at_finest)}" if bd.at_finest else ""))
    console.print(f"{escape(r.optimality)}; {r.evaluations} candidates evaluated, {r.elapsed_s:.2f} s; "
                  f"Pareto front: {len(r.front)} designs (--csv, --plot)", style="dim")
    for note in r.notes:
        console.print(escape(note), style="dim")


def print_class_allocation(result, console) -> None:
    """``allocate --select-classes``: every option of the menu, its grades and its cost per reducer
    built split into its terms (analysis.allocation.classes), the chosen one marked."""
    from rich.markup import escape
    from rich.table import Table

    lines = result.summary()
    console.print(f"[bold]{escape(lines[0])}[/]")
    t = Table(title=f"grades and classes: cost per reducer built [{escape(result.unit)}]", title_justify="left")
    for c in ("", "selection", "grades", "yield", "grades cost", "measuring + classes", "surplus", "total",
              "pin sets / unit", "roller sets / unit"):
        t.add_column(c, justify="left" if c in ("", "selection", "grades") else "right")

    def f(v, k=".2f"):
        return "-" if v is None else format(v, k)

    for o in result.options:
        grades = " ".join(f"{g}={v}" for g, v in (o.grades or {}).items()) if o.grades else escape(o.note or "-")
        t.add_row("*" if o.chosen else "", escape(o.selection), grades,
                  f(o.yield_.fraction if o.yield_ else None, ".4f"), f(o.grades_cost), f(o.selection_cost),
                  f(o.surplus_cost), f(o.total_cost), f(o.pin_sets_per_unit), f(o.roller_sets_per_unit))
    console.print(t)
    for line in lines[len(result.options) + 1:]:
        console.print(escape(line))
