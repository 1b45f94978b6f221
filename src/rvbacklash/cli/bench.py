"""``rvbacklash bench`` (measured loops and TE curves) and ``rvbacklash calibrate`` (the design's
unknowns fitted to measured loops); docs/bench-data.md."""

from __future__ import annotations

from pathlib import Path
from typing import List, Optional

import typer

from rvbacklash.cli.app import app
from rvbacklash.cli.common import (DESIGN_HELP, FORCE_OPTION, FORMAT_OPTION, QUIET_OPTION, SEED_OPTION, Format,
                                   Outputs, command, csv_option, json_option, parse_samples, stdout_console)

TORQUE_UNIT = typer.Option(None, "--torque-unit", help="Unit of a torque column whose header has none: N m, kN m.")
ANGLE_UNIT = typer.Option(None, "--angle-unit", help="Unit of angle columns whose header has none: arcmin, arcsec, "
                                                     "deg, rad, mrad, urad.")
LOOP_FIGURES = ("lost_motion_arcmin", "backlash_arcmin", "torsional_rigidity_nm_per_arcmin")
TIME_UNIT = typer.Option(None, "--time-unit", help="Unit of a time column whose header has none: s, ms, min.")
COLUMNS = typer.Option(None, "--columns", metavar="MAP",
                       help="Column map for headers not recognised: ROLE=COLUMN pairs, comma-separated (roles: "
                            "angle, te, input_angle, torque, time; angle_bw, te_bw, input_angle_bw for a backward "
                            "run; direction), e.g. te=Transmission_Error_Fw,te_bw=Transmission_Error_Bw.")
FORMAT_PROFILE = typer.Option(None, "--format-profile", metavar="FILE",
                              help="A rig's file format as TOML: column map, units, decimal mark, separator, sheet, "
                                   "direction values (docs/bench-data.md, 'Rig files'); flags override it.")
DECIMAL = typer.Option(None, "--decimal", metavar="MARK",
                       help="Decimal mark of the numbers: '.' or ','. Default: '.', and ',' where the file is "
                            "separated by ';' or tabs.")


def print_bench(result, console) -> None:
    """One row per unit: its figures with their uncertainty, what the reader found, its percentiles."""
    from rich.markup import escape
    from rich.table import Table

    from rvbacklash.analysis.bench import BenchLoop, BenchTransmissionError, BenchTwoRunTE

    loops = [u for u in result.units if isinstance(u, BenchLoop)]
    if loops:
        u0 = loops[0]
        t = Table(title=f"Measured loops (T_R {u0.rated_torque_nm:g} N m from {u0.rated_torque_from}; ± is the "
                        f"expanded uncertainty, k = 2)", title_justify="left")
        for col in ("file", f"lost motion ±{u0.measuring_torque_fraction * 100:g} % [arcmin]", "backlash [arcmin]",
                    f"rigidity {u0.rigidity_interval_fraction[0] * 100:g}-{u0.rigidity_interval_fraction[1] * 100:g} "
                    f"% [N m/arcmin]", "loss [J]", "found"):
            t.add_column(escape(col), justify="left" if col in ("file", "found") else "right")
        for u in loops:
            k = u.uncertainty_k2
            drift = "no drift estimate" if u.drift_arcmin_per_s is None else \
                f"drift {u.drift_arcmin_per_s:.3g} arcmin/{u.drift_per}"
            t.add_row(escape(u.source), f"{u.lost_motion_arcmin:.4f} ± {k['lost_motion_arcmin']:.4f}",
                      f"{u.backlash_arcmin:.4f} ± {k['backlash_arcmin']:.4f}",
                      f"{u.torsional_rigidity_nm_per_arcmin:.1f} ± {k['torsional_rigidity_nm_per_arcmin']:.1f}",
                      f"{u.hysteresis_loss_j:.3g}",
                      escape(f"{u.cycles} cycles, {u.samples} samples, noise {u.noise_arcmin:.4f} arcmin, {drift}"))
        console.print(t)
    tes = [u for u in result.units if isinstance(u, BenchTransmissionError)]
    if tes:
        t = Table(title="Measured transmission error", title_justify="left")
        for col in ("file", "TE p-p [arcsec]", "leading orders [arcsec]", "found"):
            t.add_column(escape(col), justify="right" if col.startswith("TE") else "left")
        for u in tes:
            t.add_row(escape(u.source), f"{u.te_peak_to_peak_arcsec:.2f}",
                      ", ".join(f"{s.order}: {s.amplitude_arcsec:.2f}" for s in u.leading_orders[:5]) or "none",
                      escape(f"{u.revolutions:.2f} revolutions, {u.samples} samples, noise {u.noise_arcsec:.2f} "
                             f"arcsec"))
        console.print(t)
    two = [u for u in result.units if isinstance(u, BenchTwoRunTE)]
    if two:
        print_two_runs(two, console)
    if result.design_name is not None:
        t = Table(title=f"In the predicted production run of {result.design_name} ({result.samples_predicted} units, "
                        f"seed {result.seed})", title_justify="left")
        for col in ("file", "figure", "measured", "percentile", "predicted 5 % .. 95 %", "flag"):
            t.add_column(col, justify="left" if col in ("file", "figure", "flag") else "right")
        for u in result.units:
            for p in u.placement:
                flag = ("OUTSIDE 0.135-99.865 %" + (f": look at {', '.join(p.explaining_factors)}"
                                                    if p.explaining_factors else "")) if p.outside else ""
                if p.beyond_every_predicted_unit:
                    flag += (" (beyond every predicted unit: a model input, e.g. the structure - calibrate - or a "
                             "part far out of its tolerance)" if p.figure in LOOP_FIGURES else
                             " (beyond every predicted unit: a part far out of its tolerance, or a model input)")
                t.add_row(escape(u.source), p.figure, f"{p.measured:.4g}", f"{p.percentile:.1f} %",
                          f"{p.predicted_q05:.4g} .. {p.predicted_q95:.4g}", escape(flag))
        console.print(t)
    for f, s in result.spread.items():
        pred = "" if s["predicted_sigma"] is None else f", predicted {s['predicted_sigma']:.4g}"
        console.print(f"unit-to-unit spread of {f}: sigma {s['measured_sigma']:.4g} over {s['units']} units{pred}")
    for u in result.units:
        for n in u.notes:
            console.print(f"[dim]{escape(u.source)}: {escape(n)}[/]")
        for line in u.metadata[:MAX_METADATA_SHOWN]:
            console.print(f"[dim]{escape(u.source)}: metadata: {escape(line)}[/]")
        if len(u.metadata) > MAX_METADATA_SHOWN:
            console.print(f"[dim]{escape(u.source)}: metadata: {len(u.metadata) - MAX_METADATA_SHOWN} more lines "
                          f"(--json: metadata)[/]")
    for w in result.warnings:
        console.print(f"[bold red]warning:[/] {escape(w)}")


MAX_METADATA_SHOWN = 6


def print_two_runs(units, console) -> None:
    """One row per unit of two TE runs: each run's peak-to-peak and orders, the lost motion."""
    from rich.markup import escape
    from rich.table import Table

    t = Table(title="Measured transmission error, forward and backward runs (lost motion: the gap between the runs, "
                    "as the transmission model's at every output position)", title_justify="left")
    for col in ("file", "TE p-p fw / bw [arcsec]", "leading orders fw [arcsec]", "leading orders bw [arcsec]",
                "lost motion mean (min .. max) [arcmin]", "found"):
        t.add_column(escape(col), justify="right" if col.startswith(("TE", "lost")) else "left")
    for u in units:
        f, b = u.forward, u.backward
        t.add_row(escape(u.source), f"{u.te_peak_to_peak_arcsec:.2f} / {u.te_peak_to_peak_backward_arcsec:.2f}",
                  *(", ".join(f"{s.order}: {s.amplitude_arcsec:.2f}" for s in r.leading_orders[:4]) or "none"
                    for r in (f, b)),
                  f"{u.lost_motion_mean_arcmin:.4f} ({u.lost_motion_min_arcmin:.4f} .. {u.lost_motion_max_arcmin:.4f})",
                  escape(f"{f.revolutions:.2f} / {b.revolutions:.2f} revolutions, {f.samples} / {b.samples} samples, "
                         f"noise {f.noise_arcsec:.2f} / {b.noise_arcsec:.2f} arcsec; {u.ccw_run} run above"))
    console.print(t)


@app.command()
@command
def bench(
    files: List[Path] = typer.Argument(..., help="Bench files (CSV/TSV/.xlsx, one unit each): a hysteresis loop "
                                                 "(torque and output angle columns) or a TE curve (output angle and "
                                                 "TE; one run, or forward and backward runs of the unit).",
                                       metavar="FILE..."),
    design: Optional[str] = typer.Option(None, "--design", help="Place each unit in this design's predicted "
                                                                "production run. " + DESIGN_HELP, metavar="D"),
    rated_torque_nm: Optional[float] = typer.Option(None, "--rated-torque-nm", help="T_R of the definitions "
                                                    "[N m]; default: the design's, else the loop's peaks."),
    torque_unit: Optional[str] = TORQUE_UNIT,
    angle_unit: Optional[str] = ANGLE_UNIT,
    te_unit: Optional[str] = typer.Option(None, "--te-unit", help="Unit of a TE column whose header has none."),
    time_unit: Optional[str] = TIME_UNIT,
    columns: Optional[str] = COLUMNS,
    format_profile: Optional[Path] = FORMAT_PROFILE,
    decimal: Optional[str] = DECIMAL,
    ratio: Optional[float] = typer.Option(None, "--ratio", help="Reduction ratio for TE files with input and output "
                                                                "angles; default: the design's."),
    samples: str = typer.Option("2000", "--samples", "-n", help="Predicted units with --design (TE: at most 200)."),
    seed: int = SEED_OPTION,
    json_out: Optional[str] = json_option("every unit's figures"),
    csv_out: Optional[str] = csv_option("one row per unit"),
    plot: Optional[str] = typer.Option(None, "--plot", help="Write an SVG of the loops (definitions drawn, the "
                                                            "design's nominal and 5 %/95 % units) and TE curves.",
                                       metavar="FILE"),
    fmt: Format = FORMAT_OPTION,
    force: bool = FORCE_OPTION,
    quiet: bool = QUIET_OPTION,
) -> None:
    """Read measured hysteresis loops and TE curves by the model's own definitions (lost motion,
    backlash, rigidity, hysteresis loss, TE peak-to-peak and orders), with their uncertainty;
    with --design, each unit in the design's predicted production run."""
    import rvbacklash.api as api
    from rvbacklash.report.bench_plots import bench_svg
    from rvbacklash.report.files import render_csv, render_json

    out = Outputs(fmt, force, quiet, json=json_out, csv=csv_out, plot=plot)
    n = parse_samples(samples)
    problem = api.prepare(design) if design is not None else None
    result = api.read_bench(files, design=problem, rated_torque_nm=rated_torque_nm, torque_unit=torque_unit,
                            angle_unit=angle_unit, te_unit=te_unit, time_unit=time_unit, ratio=ratio, samples=n,
                            seed=seed, columns=columns, format_profile=format_profile, decimal=decimal)
    data, rows = result.to_dict(), result.rows()

    def svg() -> str:
        nominal, others, te_model = None, (), None
        if problem is not None and problem.design.elastic is not None and \
                any(u.kind == "hysteresis" for u in result.units):
            from rvbacklash.analysis.hysteresis import elastic_section

            s = elastic_section(problem, samples=min(n, 2000), seed=seed)
            nominal, others = s.nominal, tuple(s.quantile_units.values())
        if problem is not None and any(u.kind == "transmission_error_two_runs" for u in result.units):
            te_model = api.transmission_error(problem, shares=False)  # the nominal unit's lost motion curve
        return bench_svg(result, nominal, others, te_model=te_model)

    out.finish({"--json": lambda: render_json(data), "--csv": lambda: render_csv(rows), "--plot": svg},
               lambda: print_bench(result, stdout_console()), data, rows)


def print_calibration(result, console) -> None:
    from rich.markup import escape
    from rich.table import Table

    t = Table(title=f"{escape(result.design_name)} calibrated on {len(result.sources)} loop(s)", title_justify="left")
    cols = ("parameter", "design", "fitted", "95 % interval", "from", "flag")
    for col in cols:
        t.add_column(col, justify="left" if col in ("parameter", "from", "flag") else "right")
    for p in result.parameters:
        flag = [f"AT {p.at_bound.upper()} BOUND: no estimate"] if p.at_bound else []
        flag += ["LACK OF FIT: interval too narrow"] if result.lack_of_fit else []
        t.add_row(p.name, "derived" if p.design_value is None else f"{p.design_value:.4g}", f"{p.value:.4g}",
                  f"{p.ci95_low:.4g} .. {p.ci95_high:.4g}", p.ci_from, "; ".join(flag))
    console.print(t)
    f = Table(title="Nominal unit before and after, and the measured units' mean", title_justify="left")
    for col in ("figure", "before", "after", "measured"):
        f.add_column(col, justify="left" if col == "figure" else "right")
    for k in result.before:
        f.add_row(k, f"{result.before[k]:.4g}", f"{result.after[k]:.4g}", f"{result.measured[k]:.4g}")
    console.print(f)
    console.print(f"residual {result.residual_rms_arcmin:.4f} arcmin rms over {result.samples_fitted} samples (noise "
                  f"{', '.join(f'{n:.4f}' for n in result.noise_arcmin)} arcmin); Jacobian condition "
                  f"{result.jacobian_condition:.3g}")
    for k, s in result.spread.items():
        pred = "" if s["predicted_sigma"] is None else f"; predicted {s['predicted_sigma']:.4g}"
        console.print(f"unit-to-unit spread of {k}: sigma {s['measured_sigma']:.4g} over {s['units']} units{pred}")
    console.print(f"residual {result.residual_over_expected:.2f} times what the noise and the model's resolution "
                  f"explain ({result.expected_residual_arcmin:.4f} arcmin)")
    if result.lack_of_fit:
        m = Table(title="Where the misfit sits (residual = measured - model)", title_justify="left")
        for col in ("branch", "|T| / T_R", "samples", "rms [arcmin]", "mean [arcmin]", "x expected"):
            m.add_column(col, justify="left" if col == "branch" else "right")
        for s in result.misfit:
            m.add_row(s.branch, f"{100 * s.from_fraction:g}-{100 * s.to_fraction:g} %", str(s.samples),
                      f"{s.residual_rms_arcmin:.4f}", f"{s.residual_mean_arcmin:+.4f}",
                      f"[bold red]{s.over_expected:.1f}[/]" if s.over_expected > 1.25 else f"{s.over_expected:.1f}")
        console.print(m)
    for w in (*result.flags, *result.warnings):
        console.print(f"[bold red]warning:[/] {escape(w)}")


@app.command()
@command
def calibrate(
    design: str = typer.Argument(..., help=DESIGN_HELP),
    bench_files: List[Path] = typer.Option(..., "--bench", help="A measured loop (CSV/TSV/.xlsx; repeat for a "
                                                                "batch).",
                                           metavar="FILE"),
    write_design: Optional[str] = typer.Option(None, "--write-design", metavar="FILE",
                                               help="Write the calibrated design (TOML, comments say what was "
                                                    "fitted, from which files, when)."),
    torque_unit: Optional[str] = TORQUE_UNIT,
    angle_unit: Optional[str] = ANGLE_UNIT,
    time_unit: Optional[str] = TIME_UNIT,
    columns: Optional[str] = COLUMNS,
    format_profile: Optional[Path] = FORMAT_PROFILE,
    decimal: Optional[str] = DECIMAL,
    bootstrap: int = typer.Option(50, "--bootstrap", help="Resamples over units for the intervals (3 units or more)."),
    samples: str = typer.Option("0", "--samples", "-n", help="Predicted units for the spread comparison (0: none)."),
    seed: int = SEED_OPTION,
    json_out: Optional[str] = json_option("the fitted parameters"),
    csv_out: Optional[str] = csv_option("one row per parameter"),
    plot: Optional[str] = typer.Option(None, "--plot", help="Write an SVG of the measured loops with the nominal "
                                                            "loop before and after.", metavar="FILE"),
    fmt: Format = FORMAT_OPTION,
    force: bool = FORCE_OPTION,
    quiet: bool = QUIET_OPTION,
) -> None:
    """Fit the structure's stiffness, the friction torque and the crank bearings' clearance offset
    to measured loops (least squares, 95 % intervals) and write the calibrated design."""
    import rvbacklash.api as api
    from rvbacklash.analysis.calibration import calibration_header
    from rvbacklash.report.bench_plots import calibration_svg
    from rvbacklash.report.design_toml import design_toml
    from rvbacklash.report.files import render_csv, render_json

    out = Outputs(fmt, force, quiet, write_design=write_design, json=json_out, csv=csv_out, plot=plot)
    n = parse_samples(samples)
    result = api.calibrate(design, bench=bench_files, torque_unit=torque_unit, angle_unit=angle_unit,
                           time_unit=time_unit, bootstrap=bootstrap, seed=seed, samples=n, columns=columns,
                           format_profile=format_profile, decimal=decimal)
    data, rows = result.to_dict(), result.rows()
    out.finish({"--write-design": lambda: design_toml(result.design, calibration_header(result)),
                "--json": lambda: render_json(data), "--csv": lambda: render_csv(rows),
                "--plot": lambda: calibration_svg(result)},
               lambda: print_calibration(result, stdout_console()), data, rows)
