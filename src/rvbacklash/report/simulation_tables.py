"""Rich summary of a Monte-Carlo (or exact) result for the terminal."""

from __future__ import annotations

from rich.console import Console
from rich.markup import escape
from rich.table import Table

from rvbacklash.analysis.simulation import SimulationResult


def _f(x, fmt: str = ".4f") -> str:
    return "-" if x is None else format(x, fmt)


def _ci(ci) -> str:
    return "-" if ci is None or None in ci else f"[{ci[0]:.4f}, {ci[1]:.4f}]"


def print_simulation(r: SimulationResult, console: Console) -> None:
    s = r.stats
    head = (f"[bold]{r.design_name}[/]  model {r.model}, method {r.method}"
            + (f", {s['samples_done']:,} samples, seed {r.seed}" if r.method != "exact" else " (no sampling)"))
    if r.partial:
        head += f"  [bold red]PARTIAL: interrupted after {s['samples_done']:,} of {r.samples:,} samples[/]"
    console.print(head)

    t = Table(title=escape("Output backlash [arcmin]"), title_justify="left")
    for c in ["statistic", "value", "95 % interval"]:
        t.add_column(c, justify="left" if c == "statistic" else "right")
    t.add_row("mean", _f(s["mean_arcmin"]), _ci(s["mean_ci95"]))
    t.add_row("standard deviation", _f(s["std_arcmin"]), "")
    if s.get("min_arcmin") is not None:
        t.add_row("min / max", f"{s['min_arcmin']:.4f} / {s['max_arcmin']:.4f}", "")
    for p, q in s["quantiles"].items():
        t.add_row(f"quantile {float(p) * 100:g} %", _f(q["value"]), _ci(q["ci95"]))
    if s.get("yield") is not None:
        y = s["yield"]
        t.add_row(f"yield P(backlash <= {s['spec_arcmin']:g})", f"{y['fraction'] * 100:.4f} %",
                  f"[{y['ci95'][0] * 100:.4f} %, {y['ci95'][1] * 100:.4f} %]")
        t.add_row("out of spec", f"{s['ppm_out']:.1f} ppm", "")
        t.add_row("Cp / Cpk (LSL 0, USL spec)", f"{_f(s['cp'], '.3f')} / {_f(s['cpk'], '.3f')}", "")
    t.add_row("P(backlash < 0): interference", f"{s['interference_fraction'] * 100:.4f} %", "")
    console.print(t)
    a = r.analytic
    console.print(f"linear stack-up (analyze): mean {a['mean_arcmin']:.4f}, sigma {a['sigma_arcmin']:.4f} arcmin")
    if r.elapsed_s > 0 and s.get("samples_done"):
        console.print(f"[dim]{r.elapsed_s:.2f} s, {s['samples_done'] / r.elapsed_s / 1e6:.1f} M samples/s[/]")
