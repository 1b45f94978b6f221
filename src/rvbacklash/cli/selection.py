"""``rvbacklash assemble``: the assembly sheet of a measured batch (docs/selective-assembly.md)."""

from __future__ import annotations

from typing import Optional

import typer

from rvbacklash.cli.app import app
from rvbacklash.cli.common import (DESIGN_HELP, FORCE_OPTION, FORMAT_OPTION, QUIET_OPTION, SEED_OPTION, Format,
                                   Outputs, command, csv_option, json_option, stdout_console)
from rvbacklash.errors import InputError

DEFAULT_SELECT = "pins=5x2um,rollers=3x2um"


def print_sheet(sheet, console) -> None:
    import math

    from rich.markup import escape
    from rich.table import Table

    lines = sheet.summary()
    console.print(f"[bold]{escape(lines[0])}[/]")
    t = Table(title="assembly sheet", title_justify="left")
    for c in ("unit", "pins", "rollers", "play [arcmin]", "crank clearance [µm]", "lost motion [arcmin]",
              "backlash [arcmin]", "rigidity [N·m/arcmin]", "P(pass)", "note"):
        t.add_column(c, justify="left" if c == "note" else "right")
    for r in sheet.sheet:
        f = (lambda v, k=".3f": "-" if v is None or (isinstance(v, float) and math.isnan(v)) else format(v, k))
        t.add_row(str(r.unit), f"class {r.pin_class}" if r.built else "-", f"class {r.roller_class} "
                  f"({r.roller_serial})" if r.built else "-", f(r.predicted_play_arcmin), f(r.crank_clearance_um, ".2f"),
                  f(r.lost_motion_arcmin), f(r.backlash_arcmin), f(r.rigidity_nm_per_arcmin, ".0f"),
                  f(r.pass_probability, ".2f"), escape(r.reason))
    console.print(t)
    for line in lines[1:]:
        if not line.startswith("unit "):
            console.print(escape(line))


@app.command()
@command
def assemble(
    design: str = typer.Argument(..., help=DESIGN_HELP),
    parts: str = typer.Option(..., "--parts", help="Measured parts of the batch, CSV: serial,kind,diameter_um (kind "
                                                   "pin or roller: a roller set; diameter deviation [um]). With "
                                                   "--generate: the file to write.", metavar="FILE"),
    units: str = typer.Option(..., "--units", help="The batch's measured units (the measured-unit TOML: discs, "
                                                   "housing, crank; pins ignored). With --generate: the file to "
                                                   "write.", metavar="FILE"),
    select: str = typer.Option(DEFAULT_SELECT, "--select", help="The classes and rules, as simulate --select."),
    spec_lost_motion_arcmin: Optional[float] = typer.Option(None, "--spec-lost-motion-arcmin",
                                                            help="Spec of the lost motion: each unit's P(pass)."),
    assembled: Optional[str] = typer.Option(None, "--assembled", help="Write the built units as assembled (the "
                                            "measured-unit TOML: re-run one with hysteresis --measured).",
                                            metavar="FILE"),
    generate: Optional[int] = typer.Option(None, "--generate", help="Write a batch of N measured units and their "
                                           "parts (25 % spare) to --units and --parts instead, drawn with --seed.",
                                           metavar="N"),
    seed: int = SEED_OPTION,
    json_out: Optional[str] = json_option("the sheet and its summary"),
    csv_out: Optional[str] = csv_option("the sheet: one row per unit"),
    fmt: Format = FORMAT_OPTION,
    force: bool = FORCE_OPTION,
    quiet: bool = QUIET_OPTION,
) -> None:
    """Assembly sheet of a measured batch: which pin class and roller set go into which unit, its
    predicted lost motion, backlash and rigidity, P(pass); units that cannot be built, with the reason."""
    import rvbacklash.api as api
    from rvbacklash.report.files import render_csv, render_json

    if generate is not None:
        out = Outputs(fmt, force, quiet, units=units, parts=parts)
        batch_units, batch_parts = api.generate_batch(design, units=generate, seed=seed)
        from rvbacklash.analysis.selection.assembly import write_parts_csv
        from rvbacklash.design.measured import units_to_toml

        header = f"{generate} units of `rvbacklash assemble {design} --generate {generate} --seed {seed}` (pins not " \
                 f"yet chosen; crank bearings with rollers of nominal diameter)"
        data = {"units": generate, "parts": len(batch_parts), "seed": seed}
        out.finish({"--units": lambda: units_to_toml(batch_units, header), "--parts": lambda: write_parts_csv(
            batch_parts)}, lambda: stdout_console().print(f"{generate} units, {len(batch_parts)} parts"), data, [data])
        return
    if spec_lost_motion_arcmin is not None and not spec_lost_motion_arcmin > 0:
        raise InputError("--spec-lost-motion-arcmin", spec_lost_motion_arcmin, "allowed: a finite number > 0")
    from rvbacklash.analysis.selection.classes import parse_selection

    selection = parse_selection(select, "--select")
    out = Outputs(fmt, force, quiet, json=json_out, csv=csv_out, assembled=assembled)
    sheet, built = api.assemble(design, units=units, parts=parts, select=selection,
                                spec_lost_motion_arcmin=spec_lost_motion_arcmin)
    data, rows = sheet.to_dict(), sheet.rows()

    def assembled_toml() -> str:
        from rvbacklash.design.measured import units_to_toml

        return units_to_toml(built, f"the built units of `rvbacklash assemble {design} --units {units} --parts {parts}"
                                    f" --select {select}`, in sheet order")

    out.finish({"--json": lambda: render_json(data), "--csv": lambda: render_csv(rows), "--assembled": assembled_toml},
               lambda: print_sheet(sheet, stdout_console()), data, rows)
