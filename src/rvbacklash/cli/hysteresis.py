"""``rvbacklash hysteresis``: the test bench's loop of one unit (docs/elastic.md)."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer

from rvbacklash.cli.app import app
from rvbacklash.cli.common import (DESIGN_HELP, FORCE_OPTION, FORMAT_OPTION, QUIET_OPTION, Format, Outputs, command,
                                   csv_option, json_option, stdout_console)


def print_hysteresis(result, console) -> None:
    """The figures of a loop, the share of each element and the pins in contact."""
    from rich.markup import escape
    from rich.table import Table

    r = result
    console.print(f"[bold]{escape(r.design_name)}[/], {escape(r.unit)}: input locked, output loaded "
                  f"0 -> +{r.rated_torque_nm:g} -> 0 -> -{r.rated_torque_nm:g} -> 0 N m")
    t = Table(title="Test-bench figures", title_justify="left")
    for col in ("quantity", "value", "definition"):
        t.add_column(col, justify="left" if col != "value" else "right")
    x = r.measuring_torque_fraction * 100
    lo, hi = (v * 100 for v in r.rigidity_interval_fraction)
    t.add_row(escape("lost motion [arcmin]"), f"{r.lost_motion_arcmin:.4f}"
              + (" [bold red](stick band)[/]" if r.lost_motion_in_stick_band else ""),
              escape(f"mean of load/unload angles at +{x:g} % T_R minus the same at -{x:g} % T_R"))
    t.add_row(escape("backlash [arcmin]"), f"{r.backlash_arcmin:.4f}", "width of the loop at zero torque")
    t.add_row(escape("torsional rigidity [N m/arcmin]"), f"{r.torsional_rigidity_nm_per_arcmin:.1f}",
              escape(f"secant of the loading branches over {lo:g}-{hi:g} % T_R"))
    for sec in r.rigidity_secants:
        t.add_row(escape(f"  secant {sec.from_fraction * 100:g}-{sec.to_fraction * 100:g} % T_R [N m/arcmin]"),
                  f"{sec.rigidity_nm_per_arcmin:.1f}", "the same definition over this interval (compare like with like)")
    t.add_row("pins in contact at +T_R", " + ".join(map(str, r.pins_in_contact_at_rated)),
              f"per disc; largest pin force {r.max_pin_force_at_rated_n:.0f} N")
    t.add_row(f"pins in contact at +{x:g} % T_R", " + ".join(map(str, r.pins_in_contact_at_measuring)), "per disc")
    console.print(t)
    s = Table(title="Where the lost motion and the compliance are", title_justify="left")
    for col in ("element", "lost motion [arcmin]", "share", "dead band [arcmin]", "wind-up [arcmin]",
                "stiffness [N m/arcmin]", "compliance share"):
        s.add_column(escape(col), justify="left" if col == "element" else "right")
    total = r.lost_motion_arcmin
    for name, v in r.lost_motion_share_arcmin.items():
        k = r.element_stiffness_nm_per_arcmin[name]
        if k is None and v == 0.0 and r.dead_band_arcmin[name] == 0.0:
            continue  # an element this design does not model (rigid): its row says nothing
        s.add_row(name.replace("_", " "), f"{v:.4f}", f"{v / total:.1%}" if total else "-",
                  f"{r.dead_band_arcmin[name]:.4f}", f"{v - r.dead_band_arcmin[name]:.4f}",
                  "rigid" if k is None else f"{k:.4g}", f"{r.compliance_share[name]:.1%}")
    s.add_row("total", f"{total:.4f}", "100.0%" if total else "-", f"{total - r.wind_up_arcmin:.4f}",
              f"{r.wind_up_arcmin:.4f}", f"{r.torsional_rigidity_nm_per_arcmin:.4g}", "100.0%")
    console.print(s)
    if r.structure_model == "derived":
        structure = f"derived from [structure] (disc translation: {r.disc_translation})"
    elif r.structure_model == "stated":
        structure = f"stated {r.structure_stiffness_nm_per_arcmin:.0f} N m/arcmin"
    else:
        structure = "rigid (no [structure] table: the rigidity is an upper bound)"
    console.print(f"[dim]{escape(r.contact_law)} contacts, lever factor {r.lever_factor:.4f} ({escape(r.lever_arms)}), "
                  f"involute mesh {r.involute_stiffness_nm_per_arcmin:.3g} N m/arcmin, structure {escape(structure)}, friction "
                  f"{r.friction_torque_nm:g} N m + {r.friction_load_fraction:g} |T|; crank clearance "
                  f"{r.crank_clearance_um:.2f} um, involute backlash {r.involute_backlash_arcmin:.4f} arcmin[/]")
    for w in r.warnings:
        console.print(f"[bold red]warning:[/] {escape(w)}")


@app.command()
@command
def hysteresis(
    design: str = typer.Argument(..., help=DESIGN_HELP),
    measured: Optional[Path] = typer.Option(None, "--measured", help="A TOML file of measured units (docs/contact.md); "
                                            "default: the nominal unit.", metavar="UNIT.toml"),
    unit: Optional[int] = typer.Option(None, "--unit", help="The unit of --measured to run (0-based); default: the "
                                                           "first."),
    points: int = typer.Option(41, "--points", help="Loop nodes per branch (the definitions' torques are added)."),
    json_out: Optional[str] = json_option("the figures and the loop"),
    csv_out: Optional[str] = csv_option("the loop (branch, torque, angle)"),
    plot: Optional[str] = typer.Option(None, "--plot", help="Write an SVG of the loop to FILE.", metavar="FILE"),
    fmt: Format = FORMAT_OPTION,
    force: bool = FORCE_OPTION,
    quiet: bool = QUIET_OPTION,
) -> None:
    """The test bench's hysteresis loop (input locked, 0 -> +T_R -> 0 -> -T_R -> 0): lost motion,
    backlash, torsional rigidity and the pins in contact, from the design's [elastic] table."""
    import rvbacklash.api as api
    from rvbacklash.report.elastic_plots import loop_svg
    from rvbacklash.report.files import render_csv, render_json

    out = Outputs(fmt, force, quiet, json=json_out, csv=csv_out, plot=plot)
    result = api.hysteresis(design, measured=measured, unit=unit, points=points)
    data, rows = result.to_dict(), result.rows()
    out.finish({"--json": lambda: render_json(data), "--csv": lambda: render_csv(rows),
                "--plot": lambda: loop_svg(result)},
               lambda: print_hysteresis(result, stdout_console()), data, rows)
