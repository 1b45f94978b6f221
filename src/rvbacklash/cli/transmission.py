"""``rvbacklash transmission-error``: one unit over a full output revolution (docs/transmission-error.md)."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer

from rvbacklash.cli.app import app
from rvbacklash.cli.common import (DESIGN_HELP, FORCE_OPTION, FORMAT_OPTION, QUIET_OPTION, Format, Outputs, command,
                                   csv_option, json_option, stdout_console)


def print_transmission_error(result, console) -> None:
    """The figures of one unit, its leading spectral lines and the error groups' shares."""
    from rich.markup import escape
    from rich.table import Table

    r = result
    console.print(f"[bold]{escape(r.design_name)}[/], {escape(r.unit)}: one output revolution, {r.positions} positions, "
                  f"from crank angle {r.crank_angle_deg:g} deg")
    t = Table(title="Transmission error and rigid lost motion", title_justify="left")
    for col in ("quantity", "value"):
        t.add_column(col, justify="left" if col == "quantity" else "right")
    t.add_row(escape(f"TE peak-to-peak, {r.load_direction} flank [arcsec]"), f"{r.te_peak_to_peak_arcsec:.2f}")
    t.add_row(escape("TE min .. max [arcsec]"), f"{r.te_min_arcsec:.2f} .. {r.te_max_arcsec:.2f}")
    t.add_row(escape("TE peak-to-peak, other flank [arcsec]"), f"{r.te_peak_to_peak_other_flank_arcsec:.2f}")
    t.add_row(escape("lost motion min .. max [arcmin]"),
              f"{r.lost_motion_min_arcmin:.4f} .. {r.lost_motion_max_arcmin:.4f}")
    t.add_row(escape("lost motion at the reference position [arcmin]"), f"{r.lost_motion_reference_arcmin:.4f}")
    t.add_row(escape("  = cycloid stage [arcmin]"), f"{r.cycloid_stage_reference_arcmin:.4f}")
    t.add_row(escape(f"  + involute and crank stages [arcmin] ({r.other_stages_from})"), f"{r.other_stages_arcmin:.4f}")
    t.add_row("positions with the cycloid stage preloaded", str(r.preloaded_positions))
    t.add_row(escape("error-free unit's own ripple [arcsec]"), f"{r.nominal_ripple_arcsec:.3f}")
    console.print(t)
    if r.leading_orders:
        s = Table(title="Leading orders (per output revolution)", title_justify="left")
        s.add_column("order", justify="right")
        s.add_column(escape("amplitude [arcsec]"), justify="right")
        for line in r.leading_orders:
            s.add_row(str(line.order), f"{line.amplitude_arcsec:.3f}")
        console.print(s)
    else:
        console.print(escape(r.no_spectrum()) + ".", highlight=False)
    if r.group_shares:
        g = Table(title="Error groups (each switched off in turn)", title_justify="left")
        for col in ("group", "TE p-p without [arcsec]", "variance share"):
            g.add_column(escape(col), justify="left" if col == "group" else "right")
        for x in r.group_shares:
            g.add_row(escape(x.group), f"{x.te_peak_to_peak_without_arcsec:.2f}", f"{x.variance_share:.1%}")
        console.print(g)


@app.command("transmission-error")
@command
def transmission_error(
    design: str = typer.Argument(..., help=DESIGN_HELP),
    measured: Optional[Path] = typer.Option(None, "--measured", help="A TOML file of measured units (docs/contact.md); "
                                            "default: the nominal unit.", metavar="UNIT.toml"),
    unit: Optional[int] = typer.Option(None, "--unit", help="The unit of --measured to run (0-based); default: the "
                                                           "first."),
    positions: int = typer.Option(1024, "--positions", help="Output positions per revolution (at least 8 z_p, "
                                                            "the production run's grid: 320 for rv80e)."),
    load_direction: str = typer.Option("ccw", "--load-direction", help="Flank of the headline figures: ccw | cw."),
    temperature: Optional[float] = typer.Option(None, "--temperature", help="The reducer's temperature (oil and parts "
                                                "alike, as efficiency's) [degC]: the unit with its parts' differential "
                                                "expansion ([thermal]; docs/efficiency.md); default: the reference "
                                                "temperature (20), no expansion."),
    json_out: Optional[str] = json_option("the figures, the curves and the spectrum"),
    csv_out: Optional[str] = csv_option("the curves (one row per output position)"),
    plot: Optional[str] = typer.Option(None, "--plot", help="Write an SVG of the curves and the spectrum to FILE.",
                                        metavar="FILE"),
    fmt: Format = FORMAT_OPTION,
    force: bool = FORCE_OPTION,
    quiet: bool = QUIET_OPTION,
) -> None:
    """Angular transmission error over one output revolution (both load directions, peak-to-peak,
    spectrum by order) and the rigid lost motion at every output position, on the exact geometry."""
    import rvbacklash.api as api
    from rvbacklash.report.files import render_csv, render_json
    from rvbacklash.report.transmission_plots import te_svg

    out = Outputs(fmt, force, quiet, json=json_out, csv=csv_out, plot=plot)
    result = api.transmission_error(design, measured=measured, unit=unit, positions=positions,
                                    load_direction=load_direction, temperature_c=temperature)
    data, rows = result.to_dict(), result.rows()
    out.finish({"--json": lambda: render_json(data), "--csv": lambda: render_csv(rows),
                "--plot": lambda: te_svg(result)},
               lambda: print_transmission_error(result, stdout_console()), data, rows)


SPEC_TE_OPTION = typer.Option(None, "--spec-te-arcsec",
                              help="Spec of the transmission error's peak-to-peak over one output revolution "
                                   "(upper limit) [arcsec]; turns --model contact into --model transmission (the "
                                   "contact model's units through a full revolution; docs/transmission-error.md).")
