"""``rvbacklash service-life``: precision over the service life of a design (docs/service-life.md)."""

from __future__ import annotations

import math
from typing import Optional

import typer

from rvbacklash.cli.app import app
from rvbacklash.cli.common import (DESIGN_HELP, FORCE_OPTION, FORMAT_OPTION, QUIET_OPTION, SEED_OPTION, Format,
                                   Outputs, command, csv_option, json_option, parse_samples, stdout_console)
from rvbacklash.errors import InputError


def _hours(text: str) -> list[float]:
    try:
        values = [float(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise InputError("hours", text, "allowed: hours separated by commas, e.g. 0,1000,6000") from None
    if not values:
        raise InputError("hours", text, "allowed: hours separated by commas, e.g. 0,1000,6000")
    return values


def _life(v: float, last: float) -> str:
    return f"> {last:,.0f}" if not math.isfinite(v) else f"{v:,.0f}"


def print_service_life(r, console) -> None:
    """The nominal unit at the asked hours, its contacts' wear rates, the production run."""
    from rich.markup import escape
    from rich.table import Table

    console.print(f"[bold]{escape(r.design_name)}[/], duty cycle {escape(r.duty_cycle)} (mean output speed "
                  f"{r.mean_output_speed_rpm:.3g} r/min): {r.steps} time steps, {r.crank_angles} crank angles each"
                  + ("  [red][PARTIAL: interrupted][/]" if r.partial else ""))
    t = Table(title="Nominal unit", title_justify="left")
    for col in ("hours", "lost motion [arcmin]", "backlash [arcmin]", "rigidity [N m/arcmin]", "flank wear [um]",
                "pin + seat wear [um]", "crank clearance growth [um]", "largest pin pressure [MPa]"):
        t.add_column(escape(col), justify="right")
    for p in r.points:
        t.add_row(f"{p.hours:,.0f}", f"{p.lost_motion_arcmin:.3f}", f"{p.backlash_arcmin:.3f}",
                  f"{p.rigidity_nm_per_arcmin:.0f}", f"{p.max_flank_wear_um:.2f}", f"{p.max_pin_and_seat_wear_um:.2f}",
                  f"{p.crank_clearance_growth_um:.2f}", f"{p.max_pin_stress_mpa:.0f}")
    console.print(t)
    if r.transmission_error:
        e = Table(title="Nominal unit's transmission error (rigid, unloaded flank curve of the worn unit)",
                  title_justify="left")
        for col in ("hours", "TE peak-to-peak ccw [arcsec]", "TE peak-to-peak cw [arcsec]",
                    "rigid play of the cycloid stage [arcmin]"):
            e.add_column(escape(col), justify="right")
        for x in r.transmission_error:
            e.add_row(f"{x.hours:,.0f}", f"{x.te_peak_to_peak_ccw_arcsec:.4f}", f"{x.te_peak_to_peak_cw_arcsec:.4f}",
                      f"{x.rigid_play_mean_arcmin:.3f}")
        console.print(e)
    w = Table(title="Wear rates at 0 h (steady coefficient; running-in multiplies them at first)", title_justify="left")
    for col in ("contact", "deepest [um/1000 h]", "mean [um/1000 h]", "k [mm3/(N m)]", "sliding"):
        w.add_column(escape(col), justify="left" if col in ("contact", "sliding") else "right")
    for c in r.wear_rates:
        w.add_row(escape(c.contact), f"{c.max_depth_rate_um_per_kh:.3f}", f"{c.mean_depth_rate_um_per_kh:.3f}",
                  f"{c.wear_coefficient_mm3_per_nm:.3g}", escape(c.sliding))
    console.print(w)
    prod = r.production
    if prod is not None:
        y = Table(title=f"Production run: {prod.units:,} units, seed {prod.seed}, lost motion <= "
                        f"{prod.spec_lost_motion_arcmin:g} arcmin" + (" [PARTIAL]" if prod.partial else ""),
                  title_justify="left")
        for col in ("hours", "yield", "95 % interval", "lost motion 5 / 50 / 95 % [arcmin]"):
            y.add_column(escape(col), justify="right")
        for h, p, q in zip(prod.hours, prod.yield_at_hours, prod.lost_motion_quantiles_arcmin):
            y.add_row(f"{h:,.0f}", f"{p.fraction:.1%}", f"{p.ci95_low:.1%} - {p.ci95_high:.1%}",
                      f"{q[0]:.3f} / {q[1]:.3f} / {q[2]:.3f}")
        console.print(y)
        last = prod.hours[-1]
        life = ", ".join(f"{k}: {_life(v, last)} h" for k, v in prod.accuracy_life_quantiles_h.items())
        console.print(f"accuracy life (hours until lost motion > {prod.spec_lost_motion_arcmin:g} arcmin), quantiles "
                      f"of the run: {life}; {prod.out_at_start:,} units out at 0 h, {prod.still_in_spec:,} still in "
                      f"at {last:,.0f} h")
        a = prod.accuracy_life_yield
        if a is not None:
            console.print(f"in spec at every time step to {last:,.0f} h (accuracy life reaching it): {a.fraction:.1%} "
                          f"[{a.ci95_low:.1%} - {a.ci95_high:.1%}]")
        how = ("its own wear: the nominal unit's scaled by its discs' own load shares, re-solved every step"
               if prod.unit_wear == "own" else "the nominal unit's wear")
        console.print(f"[dim]each unit is read with {how} (docs/service-life.md)[/]")
    if r.accuracy_life_sensitivity is not None:
        from rvbacklash.report.allocation_tables import print_sensitivity

        console.print(f"[bold]Which tolerance buys hours[/]: Sobol indices of the accuracy life (lost motion <= "
                      f"{prod.spec_lost_motion_arcmin if prod is not None else ''} arcmin, censored at "
                      f"{r.points[-1].hours:,.0f} h), each unit with its own wear")
        print_sensitivity(r.accuracy_life_sensitivity, console)


@app.command("service-life")
@command
def service_life(
    design: str = typer.Argument(..., help=DESIGN_HELP),
    duty_cycle: str = typer.Option(..., "--duty-cycle", help="A duty cycle (CSV or TOML: time_share or time_s, "
                                   "output_speed_rpm, output_torque_nm; docs/capacity.md), or the name of an example "
                                   "cycle: robot-joint.", metavar="FILE"),
    hours: str = typer.Option("0,1000,6000", "--hours", help="Hours of the duty cycle at which to report, "
                                                             "comma-separated."),
    spec_lost_motion_arcmin: float = typer.Option(1.5, "--spec-lost-motion-arcmin",
                                                  help="Spec of the lost motion (upper limit) [arcmin]: the yield and "
                                                       "each unit's accuracy life."),
    samples: str = typer.Option("2000", "--samples", "-n", help="Units of the production run (0: the nominal unit "
                                                               "only)."),
    seed: int = SEED_OPTION,
    angles: Optional[int] = typer.Option(None, "--angles", help="Crank angles per revolution of each step's loads "
                                                               "(default 12)."),
    step_fraction: Optional[float] = typer.Option(None, "--step-fraction", help="Largest wear depth per time step as "
                                                  "a share of the reference clearance (default 0.1)."),
    unit_wear: str = typer.Option("own", "--unit-wear", help="The production run's units: 'own' (each unit's wear "
                                  "from its discs' own load shares, re-solved every step) or 'nominal' (every unit "
                                  "wears as the nominal unit)."),
    sensitivity: bool = typer.Option(False, "--sensitivity", help="Add the Sobol indices of the accuracy life "
                                     "(which tolerance buys hours; the life censored at the last hour, each unit with "
                                     "its own wear): N (D + 2) units more, minutes."),
    sensitivity_samples: str = typer.Option("256", "--sensitivity-samples", help="Units per sample set N of "
                                            "--sensitivity, a power of two from 64 (as `sensitivity -n`)."),
    json_out: Optional[str] = json_option("the nominal unit's trajectory, wear rates, worn flank and the production "
                                          "run"),
    csv_out: Optional[str] = csv_option("one row per asked hour (nominal unit and production run)"),
    plot: Optional[str] = typer.Option(None, "--plot", help="Write an SVG of lost motion and yield vs hours and the "
                                                            "worn flank to FILE.", metavar="FILE"),
    fmt: Format = FORMAT_OPTION,
    force: bool = FORCE_OPTION,
    quiet: bool = QUIET_OPTION,
) -> None:
    """Precision over the service life (docs/service-life.md): Archard wear of the cycloid flanks, pins,
    pin seats and crank needle bearings from the elastic solution's loads under a duty cycle, stepped
    in time with the loads re-solved; the nominal unit's lost motion, backlash and rigidity at the
    asked hours, and the production run's yield against the lost-motion spec and accuracy life."""
    import rvbacklash.api as api
    from rvbacklash.cli.common import progress_bar
    from rvbacklash.report.files import render_csv, render_json
    from rvbacklash.report.service_life_plots import service_life_svg

    n = parse_samples(samples)
    if n < 0:
        raise InputError("samples", samples, "allowed: 0 (the nominal unit only) or a number of units >= 1")
    wanted = _hours(hours)
    sobol = 0
    if not sensitivity and sensitivity_samples != "256":
        raise InputError("--sensitivity-samples", sensitivity_samples, "allowed with --sensitivity only")
    if sensitivity:
        try:
            sobol = parse_samples(sensitivity_samples)
        except InputError as e:
            raise e.renamed("--sensitivity-samples") from None
    out = Outputs(fmt, force, quiet, json=json_out, csv=csv_out, plot=plot)
    # the bar's share of each stage: the nominal stepping, the production run, the Sobol run's units
    stages = {"nominal": 1.0, **({"units": 1.0} if n else {}), **({"sensitivity": 2.0} if sobol else {})}
    starts, total = {}, 0.0
    for name, weight in stages.items():
        starts[name], total = total, total + weight
    with progress_bar(1000, "service life", "starting (the first run compiles its kernels, ~1 min, once)",
                      enabled=not quiet) as update:
        def progress(stage: str, share: float) -> None:
            update(int(1000 * (starts[stage] + stages[stage] * min(share, 1.0)) / total))

        result = api.service_life(design, duty_cycle=duty_cycle, hours=wanted,
                                  spec_lost_motion_arcmin=spec_lost_motion_arcmin, samples=n, seed=seed,
                                  angles=angles, step_fraction=step_fraction, unit_wear=unit_wear,
                                  sensitivity_samples=sobol, progress=progress)
    data = result.to_dict()
    rows = _rows(result)
    out.finish({"--json": lambda: render_json(data), "--csv": lambda: render_csv(rows),
                "--plot": lambda: service_life_svg(result)},
               lambda: print_service_life(result, stdout_console()), data, rows)


def _rows(r) -> list[dict]:
    """One row per asked hour: the nominal unit's figures and, with a production run, its yield and
    lost-motion quantiles."""
    rows = [p.to_dict() for p in r.points]
    te = {x.hours: x for x in r.transmission_error}
    for row in rows:
        x = te.get(row["hours"])
        if x is not None:
            row.update(te_peak_to_peak_ccw_arcsec=x.te_peak_to_peak_ccw_arcsec,
                       te_peak_to_peak_cw_arcsec=x.te_peak_to_peak_cw_arcsec)
    if r.production is not None:
        for row, extra in zip(rows, r.production.rows()):
            row.update({k: v for k, v in extra.items() if k != "hours"})
    return rows
