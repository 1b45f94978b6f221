"""``rvbacklash efficiency``: losses, efficiency, no-load, starting and back-driving torque, and the
thermal balance of a duty cycle (docs/efficiency.md)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Optional

import typer

from rvbacklash.cli.app import app
from rvbacklash.cli.common import (DESIGN_HELP, FORCE_OPTION, FORMAT_OPTION, QUIET_OPTION, Format, Outputs, command,
                                   SEED_OPTION, csv_option, json_option, progress_bar, stdout_console)


def print_efficiency(r, console) -> None:
    """The rated point and its losses per element, the map, the no-load torque, starting and
    back-driving torques, the thermal balance."""
    from rich.markup import escape
    from rich.table import Table

    console.print(f"[bold]{escape(r.design_name)}[/], {escape(r.unit)} unit: ratio {r.ratio:g}, {r.crank_angles} crank "
                  f"angles per revolution, oil at {r.temperature_c:g} degC ({r.viscosity_mm2_s:.1f} mm^2/s)")
    console.print(f"efficiency at {r.rated_torque_nm:g} N m, {r.rated_output_speed_rpm:g} r/min output: "
                  f"[bold]{r.efficiency_at_rated:.1%}[/] (input torque {r.input_torque_at_rated_nm:.3f} N m, losses "
                  f"{r.total_loss_at_rated_w:.1f} W of {r.output_power_at_rated_w:.0f} W out; pins' film parameter "
                  f"{r.pin_film_parameter:.2f}, friction {r.pin_friction_coefficient:.3f}; mesh "
                  f"{r.mesh_friction_coefficient:.3f})")
    t = Table(title="Losses per element at the rated point", title_justify="left")
    for col in ("element", "loss [W]", "share", "at the input [N m]", "load-dependent [W]"):
        t.add_column(escape(col), justify="left" if col == "element" else "right")
    for e in r.elements:
        t.add_row(e.element, f"{e.loss_w:.2f}", f"{e.share_of_losses:.1%}", f"{e.input_torque_nm:.4f}",
                  f"{e.load_dependent_w:.2f}")
    console.print(t)
    speeds = sorted({p.output_speed_rpm for p in r.efficiency_map})
    m = Table(title=escape(f"Efficiency map at {r.temperature_c:g} degC (rows: output torque [N m]; columns: output "
                           f"speed [r/min])"), title_justify="left")
    m.add_column("T [N m]", justify="right")
    for n in speeds:
        m.add_column(f"{n:g}", justify="right")
    for torque in sorted({p.output_torque_nm for p in r.efficiency_map}):
        row = {p.output_speed_rpm: p.efficiency for p in r.efficiency_map if p.output_torque_nm == torque}
        m.add_row(f"{torque:g}", *(f"{row[n]:.1%}" for n in speeds))
    console.print(m)
    console.print("efficiency at the rated point by temperature: " + ", ".join(
        f"{p.temperature_c:g} degC {p.efficiency:.1%}" for p in r.efficiency_by_temperature))
    temps = sorted({p.temperature_c for p in r.no_load_running_torque})
    inputs = sorted({p.input_speed_rpm for p in r.no_load_running_torque})
    q = Table(title=escape("No-load running torque at the input [N m] (rows: input speed [r/min]; columns: degC)"),
              title_justify="left")
    q.add_column("n_in", justify="right")
    for temp in temps:
        q.add_column(f"{temp:g}", justify="right")
    for n in inputs:
        row = {p.temperature_c: p.no_load_torque_nm for p in r.no_load_running_torque if p.input_speed_rpm == n}
        q.add_row(f"{n:g}", *(f"{row[temp]:.3f}" for temp in temps))
    console.print(q)
    back = "self-locking" if not math.isfinite(r.back_driving_torque_nm) else f"{r.back_driving_torque_nm:.2f} N m"
    console.print(f"starting (breakaway) torque at the input, no load: {r.starting_torque_nm:.4f} N m; starting "
                  f"efficiency at {r.rated_torque_nm:g} N m: {r.starting_efficiency:.1%}; back-driving torque at the "
                  f"output: {back}")
    console.print(f"breakaway friction at the output, running kinematics: {r.breakaway_torque_at_output_nm:.2f} N m "
                  f"+ {r.breakaway_load_fraction:.3f} |T|; under the bench's twist (input locked): "
                  f"{r.contacts_loop_friction_nm:.2f} N m + {r.contacts_loop_friction_load_fraction:.4f} |T| = "
                  f"{r.contacts_loop_friction_at_rated_nm:.2f} N m at {r.rated_torque_nm:g} N m (the hysteresis loop "
                  f"uses {r.loop_friction_model}: {r.stated_friction_torque_nm:.3g} N m + "
                  f"{r.loop_friction_load_fraction:.4g} |T|)")
    console.print("lost motion / backlash / rigidity / TE of the nominal unit by temperature (the parts' expansion): "
                  + ", ".join(
        f"{p.temperature_c:g} degC {p.lost_motion_arcmin:.3f} / {p.backlash_arcmin:.3f} arcmin / "
        f"{p.torsional_rigidity_nm_per_arcmin:.1f} N m/arcmin / {p.te_peak_to_peak_arcsec:.2f} arcsec"
        for p in r.precision_by_temperature))
    run = r.production
    if run is not None:
        line = (f"production run ({run.units} units, seed {run.seed}): efficiency at the rated point mean "
                f"{run.mean:.1%}, sigma {run.sigma:.1%}, min {run.min:.1%}, median {run.median:.1%}, max {run.max:.1%} "
                f"(nominal {run.nominal_efficiency:.1%})")
        if run.yield_ is not None:
            line += f"; yield at >= {run.spec_min_efficiency:.1%}: {run.yield_:.1%}"
        console.print(line)
        for b in run.by_torque:
            line = (f"  at {b.output_torque_nm:g} N m: mean {b.mean:.1%}, sigma {b.sigma:.1%}, min {b.min:.1%}, "
                    f"median {b.median:.1%}, max {b.max:.1%}")
            if b.yield_ is not None:
                line += f"; yield {b.yield_:.1%}"
            console.print(escape(line))
        preloaded = [u for u in run.per_unit if u.cycloid_preload_um > 0.0]
        if preloaded:
            console.print(f"  {len(preloaded)} preloaded units (their pins bear on both flanks): mean efficiency "
                          f"{sum(u.efficiency for u in preloaded) / len(preloaded):.1%}")
    th = r.thermal
    if th is not None:
        u = Table(title=f"Thermal balance of {escape(th.duty_cycle)}", title_justify="left")
        for col in ("quantity", "value", "note"):
            u.add_column(col, justify="right" if col == "value" else "left")
        steady = "above 400" if not math.isfinite(th.steady_temperature_c) else f"{th.steady_temperature_c:.1f}"
        u.add_row(escape("steady case temperature [degC]"), steady,
                  escape(f"losses {th.loss_at_steady_w:.1f} W = heat off {th.housing_area_m2:.3f} m^2 at "
                         f"{th.ambient_c:g} degC ambient"))
        u.add_row(escape("time constant [min]"), f"{th.time_constant_min:.0f}",
                  escape(f"lumped: C = {th.heat_capacity_j_k:.0f} J/K over {th.heat_conductance_w_k:.2f} W/K"))
        u.add_row(f"allowable duty at {th.case_limit_c:g} degC", f"{th.allowable_duty_at_limit:.0%}",
                  "share of time the cycle may run (>= 100 %: continuously)")
        for p in th.precision:
            u.add_row(escape(f"lost motion / backlash at {p.temperature_c:.1f} degC [arcmin]"),
                      f"{p.lost_motion_arcmin:.3f} / {p.backlash_arcmin:.3f}",
                      escape(f"moving-distance {p.clearance.moving_distance_modification_um:+.2f} um, equidistance "
                             f"{p.clearance.equidistance_modification_um:+.3f} um, pin holes "
                             f"{p.clearance.pin_hole_clearance_um:+.2f} um, crank bearings "
                             f"{p.clearance.crank_bearing_clearance_um:+.2f} um, support bearings "
                             f"{p.clearance.support_bearing_clearance_um:+.2f} um, crank circle "
                             f"{p.clearance.crank_circle_um:+.2f} um, centre distance "
                             f"{p.clearance.centre_distance_um:+.2f} um; rigidity "
                             f"{p.torsional_rigidity_nm_per_arcmin:.1f} N m/arcmin, TE "
                             f"{p.te_peak_to_peak_arcsec:.2f} arcsec"))
        console.print(u)


@app.command()
@command
def efficiency(
    design: str = typer.Argument(..., help=DESIGN_HELP),
    duty_cycle: Optional[Path] = typer.Option(None, "--duty-cycle", help="A duty cycle (CSV or TOML, as `capacity`'s; "
                                              "docs/capacity.md): its steady case temperature, time constant, "
                                              "allowable duty at the case limit, lost motion and backlash there.",
                                              metavar="FILE"),
    temperature: Optional[float] = typer.Option(None, "--temperature", help="The reducer's temperature (oil and parts "
                                                "alike) [degC] of the figures, and the nominal unit's lost motion, "
                                                "backlash, rigidity and TE there (the parts' expansion, [thermal]); "
                                                "default: the design's [lubrication] temperature_c, 40."),
    output_speed: Optional[float] = typer.Option(None, "--output-speed", help="The rated point's output speed [r/min] "
                                                 "(default: [capacity] rated_output_speed_rpm)."),
    angles: Optional[int] = typer.Option(None, "--angles", help="Crank angles per revolution (default 12)."),
    samples: int = typer.Option(0, "--samples", "-n", help="Also this many units of the elastic model's production run (the "
                                                 "units `simulate --model elastic` draws with --seed), each followed "
                                                 "through the crank angles: their efficiency at the rated point."),
    seed: int = SEED_OPTION,
    unit_map: bool = typer.Option(False, "--unit-map", help="With -n: each unit's efficiency at the map's output "
                                  "torques too (10-100 % of the rated torque, the rated speed): the run's "
                                  "distribution and yield per torque."),
    spec_min_efficiency: Optional[float] = typer.Option(None, "--spec-min-efficiency", help="With -n: the yield "
                                                        "of efficiency >= this (0-1) at the rated point."),
    json_out: Optional[str] = json_option("the efficiency, the losses per element, the map, no-load, starting and "
                                          "back-driving torques, the thermal balance"),
    csv_out: Optional[str] = csv_option("one row per element at the rated point"),
    plot: Optional[str] = typer.Option(None, "--plot", help="Write an SVG of the efficiency map, the no-load running "
                                                            "torque and the losses per element to FILE.",
                                       metavar="FILE"),
    fmt: Format = FORMAT_OPTION,
    force: bool = FORCE_OPTION,
    quiet: bool = QUIET_OPTION,
) -> None:
    """Losses and efficiency of the nominal unit (docs/efficiency.md): the efficiency at the rated point
    and each element's loss, the efficiency map against output torque, speed and temperature, the
    no-load running torque against input speed, the starting and back-driving torques; with
    --duty-cycle, the steady case temperature and lost motion and backlash there."""
    import rvbacklash.api as api
    from rvbacklash.errors import InputError
    from rvbacklash.analysis.losses.efficiency import progress_steps
    from rvbacklash.report.efficiency_plots import efficiency_svg
    from rvbacklash.report.files import render_csv, render_json

    out = Outputs(fmt, force, quiet, json=json_out, csv=csv_out, plot=plot)
    if spec_min_efficiency is not None and not samples:
        raise InputError("spec_min_efficiency", spec_min_efficiency, "allowed: with -n/--samples (a production run)")
    with progress_bar(progress_steps(duty_cycle=duty_cycle, units=samples), what="losses", enabled=not quiet) as progress:
        result = api.efficiency(design, duty_cycle=duty_cycle, angles=angles, temperature_c=temperature,
                                output_speed_rpm=output_speed, samples=samples, seed=seed, unit_map=unit_map,
                                spec_min_efficiency=spec_min_efficiency, progress=progress)
    data, rows = result.to_dict(), result.rows()
    out.finish({"--json": lambda: render_json(data), "--csv": lambda: render_csv(rows),
                "--plot": lambda: efficiency_svg(result)},
               lambda: print_efficiency(result, stdout_console()), data, rows)
