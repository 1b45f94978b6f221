"""``rvbacklash capacity``: the capacity and life datasheet of a design (docs/capacity.md)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Optional

import typer

from rvbacklash.cli.app import app
from rvbacklash.cli.common import (DESIGN_HELP, FORCE_OPTION, FORMAT_OPTION, QUIET_OPTION, Format, Outputs, command,
                                   csv_option, json_option, stdout_console)


def _h(v: float) -> str:
    return "inf" if not math.isfinite(v) else f"{v:,.0f}"


def print_capacity(r, console) -> None:
    """Each bearing's load, rating and L10; the reducer's life; the derived ratings; the main bearings;
    the duty cycle."""
    from rich.markup import escape
    from rich.table import Table

    console.print(f"[bold]{escape(r.design_name)}[/], {escape(r.unit)} unit: {r.stated_rated_torque_nm:g} N m at "
                  f"{r.rated_output_speed_rpm:g} r/min output (crank bearings at {r.bearing_speed_rpm:g} r/min), "
                  f"{r.crank_angles} crank angles per revolution, life method {r.life_method}")
    t = Table(title="Bearings over a revolution at the stated rated torque", title_justify="left")
    for col in ("bearing", "P eq [N]", "P max [N]", "C [N]", "C0 [N]", "s0", "L10 ISO 281 [h]",
                "L10 ISO/TS 16281 [h]", "L10 [h]"):
        t.add_column(escape(col), justify="left" if col == "bearing" else "right")
    speed = r.bearing_speed_rpm
    for b in r.bearings:
        h281 = b.l10_iso281_mrev * 1e6 / (60.0 * speed)
        h16281 = b.l10_iso16281_mrev * 1e6 / (60.0 * speed) if math.isfinite(b.l10_iso16281_mrev) else math.nan
        t.add_row(b.name, f"{b.equivalent_load_n:,.0f}", f"{b.max_load_n:,.0f}", f"{b.dynamic_load_rating_n:,.0f}",
                  f"{b.static_load_rating_n:,.0f}", f"{b.static_safety:.2f}", _h(h281),
                  "-" if math.isnan(h16281) else _h(h16281), _h(b.l10_h))
    console.print(t)
    s = Table(title="Ratings", title_justify="left")
    for col in ("quantity", "value", "note"):
        s.add_column(col, justify="right" if col == "value" else "left")
    s.add_row("reducer L10 at the stated rated torque [h]", _h(r.reducer_life_h),
              escape(f"its {len(r.bearings)} bearings as a system (Lundberg-Palmgren, e = 9/8); weakest "
                     f"{r.weakest_bearing}: {_h(r.weakest_bearing_life_h)} h"))
    s.add_row("derived rated torque [N m]", f"{r.derived_rated_torque_nm:.1f}",
              escape(f"L10 = {r.rated_life_h:g} h at {r.rated_output_speed_rpm:g} r/min (life there "
                     f"{r.life_at_derived_rated_torque_h:,.1f} h); stated {r.stated_rated_torque_nm:g}; by method: "
                     + ", ".join(f"{m} {v:.1f}" for m, v in r.derived_rated_torque_by_method_nm.items())))
    s.add_row("momentary maximum torque [N m]", f"{r.momentary_maximum_torque_nm:.0f}",
              escape(f"first static limit: {r.limiting_element}"))
    s.add_row("allowable acceleration torque [N m]", f"{r.allowable_acceleration_torque_nm:.0f}",
              escape(r.acceleration_rule))
    s.add_row("largest pin force / Hertz pressure at T_R", f"{r.max_pin_force_n:.0f} N",
              f"{r.max_pin_stress_mpa:.0f} MPa")
    s.add_row("crank needle bearing load over a revolution [N]",
              f"{r.needle_load_range_n[0]:,.0f}-{r.needle_load_range_n[1]:,.0f}",
              "the pins' resultant and the disc's moment turn against the bores")
    m = r.main_bearings
    if m is None:
        s.add_row("main bearings", "-", "not given ([structure] main_bearing_*)")
    else:
        s.add_row("moment rigidity [N m/arcmin]", f"{m.moment_rigidity_nm_per_arcmin:.0f}",
                  escape(f"main bearings, tangent at no external load (secant to the allowable moment "
                         f"{m.moment_rigidity_secant_nm_per_arcmin:.0f})"))
        s.add_row("allowable moment [N m]", f"{m.allowable_moment_nm:.0f}",
                  escape(f"static {m.allowable_moment_static_nm:.0f} (4200 MPa / s0 = {m.static_safety:g}), life "
                         f"{m.allowable_moment_life_nm:.0f} (L10 = {r.rated_life_h:g} h at "
                         f"{r.rated_output_speed_rpm:g} r/min)"))
    console.print(s)
    for row in r.static_limits_at_momentary:
        console.print(f"[dim]at the momentary maximum: {escape(row.element)} {row.value:,.0f} of {row.limit:,.0f} "
                      f"({row.ratio:.1%}; {escape(row.criterion)})[/]")
    d = r.duty_cycle
    if d is not None:
        u = Table(title=f"Duty cycle {d.source}", title_justify="left")
        for col in ("quantity", "value", "note"):
            u.add_column(col, justify="right" if col == "value" else "left")
        u.add_row("life [h]", _h(d.life_h), escape(f"bearing by bearing (Miner), as a system; weakest "
                                                   f"{d.weakest_bearing} {_h(d.weakest_bearing_life_h)} h"))
        u.add_row("makers' formula [h]", _h(d.makers_life_h),
                  escape(f"K (N0/Nm) (T0/Tm)^(10/3), T0 = derived {r.derived_rated_torque_nm:.1f} N m"))
        u.add_row("mean speed N_m / torque T_m", f"{d.mean_output_speed_rpm:.4g} r/min / {d.mean_output_torque_nm:.4g} N m",
                  "life-equivalent (p = 10/3)")
        u.add_row("main bearings' life [h]", _h(d.main_bearing_life_h), "under the cycle's moment, thrust, radial load")
        for c in d.peak_checks:
            u.add_row(escape(c.quantity), f"{c.largest:.0f} / {c.allowable:.0f}", "ok" if c.ok else "[red]EXCEEDED[/]")
        console.print(u)


@app.command()
@command
def capacity(
    design: str = typer.Argument(..., help=DESIGN_HELP),
    duty_cycle: Optional[Path] = typer.Option(None, "--duty-cycle", help="A duty cycle (CSV or TOML: time_share or "
                                              "time_s, output_speed_rpm, output_torque_nm [, moment_nm, thrust_n, "
                                              "radial_n]; docs/capacity.md): its life and peak checks.",
                                              metavar="FILE"),
    angles: Optional[int] = typer.Option(None, "--angles", help="Crank angles per revolution (default 24)."),
    life_method: Optional[str] = typer.Option(None, "--life-method", help="iso16281 (from the rollers' load "
                                              "distribution) or iso281 (C/P); default: the design's [capacity]."),
    json_out: Optional[str] = json_option("the ratings, lives and the loads over a revolution"),
    csv_out: Optional[str] = csv_option("one row per bearing"),
    plot: Optional[str] = typer.Option(None, "--plot", help="Write an SVG of the loads over a revolution and the "
                                                            "bearings' lives to FILE.", metavar="FILE"),
    fmt: Format = FORMAT_OPTION,
    force: bool = FORCE_OPTION,
    quiet: bool = QUIET_OPTION,
) -> None:
    """Capacity and life of the nominal unit (docs/capacity.md): each crank bearing's load over a
    revolution, rating and L10, the reducer's life, the derived rated torque beside the stated one,
    the momentary maximum torque and its limiting element, the allowable acceleration torque, the
    main bearings' moment rigidity and allowable moment; with --duty-cycle, that cycle's life."""
    import rvbacklash.api as api
    from rvbacklash.report.capacity_plots import loads_svg
    from rvbacklash.report.files import render_csv, render_json

    out = Outputs(fmt, force, quiet, json=json_out, csv=csv_out, plot=plot)
    result = api.capacity(design, duty_cycle=duty_cycle, angles=angles, life_method=life_method)
    data, rows = result.to_dict(), result.rows()
    out.finish({"--json": lambda: render_json(data), "--csv": lambda: render_csv(rows),
                "--plot": lambda: loads_svg(result)},
               lambda: print_capacity(result, stdout_console()), data, rows)
