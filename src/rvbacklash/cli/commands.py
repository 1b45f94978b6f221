"""The commands: each maps its flags to API parameters and its result to the outputs."""

from __future__ import annotations

import sys
from enum import Enum
from pathlib import Path
from typing import Optional

import typer

from rvbacklash.cli.app import app
from rvbacklash.cli.common import (CONTACT_NOTE, DESIGN_HELP, ERROR_MODEL_OPTION, FORCE_OPTION, FORMAT_OPTION, METHOD_OPTION,
                                   MODEL_OPTION, QUIET_OPTION, SAMPLES_OPTION, SEED_OPTION,
                                   SPEC_LOST_MOTION_OPTION, SPEC_OPTION, SPEC_PRELOAD_OPTION, SPEC_RIGIDITY_OPTION,
                                   WORKERS_OPTION, Format, Outputs, command, csv_option, json_option, parse_samples,
                                   progress_bar, stdout_console, workers_or_none)
from rvbacklash.cli.transmission import SPEC_TE_OPTION
from rvbacklash.errors import InputError



# the command that re-runs a saved unit alone to the run's figures (the transmission model's: its TE curve on
# the exact geometry, converged in positions; the run's figure, refined between its 8 z_p positions, within a few %)
RERUN_SAVED_UNIT = {"contact": "contact", "elastic": "hysteresis", "transmission": "transmission-error"}

@app.command()
@command
def analyze(
    design: str = typer.Argument(..., help=DESIGN_HELP),
    json_out: Optional[str] = json_option(),
    csv_out: Optional[str] = csv_option("the factor table"),
    fmt: Format = FORMAT_OPTION,
    force: bool = FORCE_OPTION,
    quiet: bool = QUIET_OPTION,
) -> None:
    """Stack-up and sensitivity of the linear model (Sun et al. 2014, Tables 2-3, Eq. (1)-(7))."""
    import rvbacklash.api as api
    from rvbacklash.report import tables
    from rvbacklash.report.files import render_csv, render_json

    out = Outputs(fmt, force, quiet, json=json_out, csv=csv_out)
    result = api.analyze(design)
    data, rows = result.to_dict(), result.rows()
    console = stdout_console()
    out.finish({"--json": lambda: render_json(data), "--csv": lambda: render_csv(rows)},
               lambda: (tables.print_stackup(result, console), tables.print_sources(result, console)), data, rows)


@app.command()
@command
def simulate(
    design: str = typer.Argument(..., help=DESIGN_HELP),
    samples: str = SAMPLES_OPTION,
    seed: int = SEED_OPTION,
    spec_arcmin: Optional[float] = SPEC_OPTION,
    method: str = METHOD_OPTION,
    model: str = MODEL_OPTION,
    quantile: list[float] = typer.Option([], "--quantile", help="Extra quantile to report (0 < p < 1); repeatable."),
    workers: int = WORKERS_OPTION,
    error_model: Optional[str] = ERROR_MODEL_OPTION,
    save_units: Optional[tuple[int, str]] = typer.Option(
        None, "--save-units", help="Write the first N units with their errors to FILE (TOML, the measured-unit "
                                   "format; contact, elastic and transmission models: the transmission model's "
                                   "with their kinematic errors).", metavar="N FILE"),
    spec_lost_motion_arcmin: Optional[float] = SPEC_LOST_MOTION_OPTION,
    spec_rigidity_nm_per_arcmin: Optional[float] = SPEC_RIGIDITY_OPTION,
    spec_preload_um: Optional[float] = SPEC_PRELOAD_OPTION,
    spec_te_arcsec: Optional[float] = SPEC_TE_OPTION,
    spec_life_h: Optional[float] = typer.Option(None, "--spec-life-h", help="Spec of the reducer's L10 at the rated "
                                                "torque and speed (lower limit) [h]; --model elastic (docs/capacity.md)."),
    spec_rated_torque_nm: Optional[float] = typer.Option(None, "--spec-rated-torque-nm", help="Spec of the derived "
                                                         "rated torque (lower limit) [N m]; --model elastic."),
    life: bool = typer.Option(False, "--life", help="Each unit's life, weakest bearing's life, derived rated torque and "
                                                    "largest pin stress beside its precision figures (--model elastic; "
                                                    "implied by a life spec)."),
    select: Optional[str] = typer.Option(
        None, "--select", help="Selective assembly beside random assembly (--model elastic, contact or "
                               "transmission): pins and needle rollers from diameter classes per unit, e.g. "
                               "pins=5x2um,rollers=3x2um[,noise=0.5um][,play=[MIN:]MAX][,target=ARCMIN], or class "
                               "boundaries pins=-4,-2,0,2,4um; replaces the design's [selection] table; none: "
                               "random assembly (docs/selective-assembly.md)."),
    json_out: Optional[str] = json_option(),
    csv_out: Optional[str] = csv_option("the statistics"),
    fmt: Format = FORMAT_OPTION,
    force: bool = FORCE_OPTION,
    quiet: bool = QUIET_OPTION,
) -> None:
    """Monte-Carlo simulation of the output backlash, with confidence intervals and yield."""
    import rvbacklash.api as api
    from rvbacklash.report import tables
    from rvbacklash.report.files import render_csv, render_json

    n = parse_samples(samples) if method != "exact" else None
    threads = workers_or_none(workers)
    specs = api.output_specs(model, spec_arcmin, spec_lost_motion_arcmin, spec_rigidity_nm_per_arcmin,
                             spec_preload_um, spec_life_h, spec_rated_torque_nm)
    if life and model != "elastic":
        raise InputError("--life", True, "allowed with --model elastic only")
    model, specs = api.te_model_and_specs(model, spec_te_arcsec, specs)
    n_save, save_path = save_units if save_units is not None else (0, None)
    if save_units is not None and n_save < 1:
        raise InputError("--save-units", n_save, "allowed: N >= 1 units to write to FILE")
    out = Outputs(fmt, force, quiet, json=json_out, csv=csv_out, save_units=save_path)
    problem = api.prepare(design)
    from rvbacklash.analysis.selection.classes import resolve_selection

    selection = resolve_selection(select, problem.design)
    if select is None and not _table_selection_applies(selection, model, n, specs, spec_arcmin, life, quiet):
        selection = None
    if selection is not None:
        _simulate_selected(problem, design, selection, out, n, seed, spec_arcmin, quantile, threads, model,
                           error_model, n_save, specs, life)
        return
    with progress_bar(n, note=CONTACT_NOTE if model != "linear" else None) as progress:
        result = api.simulate(problem, samples=n if n is not None else 1, seed=seed, method=method,
                              spec_arcmin=spec_arcmin, quantiles=quantile, workers=threads, model=model,
                              progress=progress, error_model=error_model, save_units=n_save, specs=specs,
                              life=life)
    data, rows = result.to_dict(), result.rows()

    def units_toml() -> str:
        from rvbacklash.design.measured import units_to_toml

        return units_to_toml(api.measured_units(problem, result),
                             f"{len(result.units)} units of `rvbacklash simulate {design} --model {model} --seed {seed}`"
                             f"\n(design {problem.name}); re-run one: rvbacklash {RERUN_SAVED_UNIT[model]} {design} "
                             f"--measured FILE --unit K")
    out.finish({"--json": lambda: render_json(data), "--csv": lambda: render_csv(rows), "--save-units": units_toml},
               lambda: tables.print_simulation(result, stdout_console()), data, rows)
    if result.partial:
        raise typer.Exit(130)


def _table_selection_applies(selection, model, n, specs, spec_arcmin, life, quiet) -> bool:
    """Whether the design's [selection] table (no --select given) applies to this run: a sampled
    contact, elastic or transmission run with a spec and no --life. Where it does not, the run is
    the random assembly and a note says why (a design with the table runs every command; the
    --select flag itself is checked strictly)."""
    if selection is None:
        return False
    why = ("the linear model draws no parts" if model not in ("contact", "elastic", "transmission") else
           "--method exact" if n is None else "--life" if life else
           "no spec to compare the yields" if not specs and spec_arcmin is None else None)
    if why is not None and not quiet:
        sys.stderr.write(f"note: the design's [selection] table is not applied ({why}); random assembly\n")
    return why is None


def _simulate_selected(problem, design, selection, out, n, seed, spec_arcmin, quantile, threads, model, error_model,
                       n_save, specs, life) -> None:
    """``simulate --select`` (or the design's [selection]): the run with random and with selective
    assembly (same units)."""
    import rvbacklash.api as api
    from rvbacklash.report import tables
    from rvbacklash.report.files import render_csv, render_json
    from rvbacklash.report.selection import print_selection

    if n is None:
        raise InputError("--method", "exact", "allowed with --select: a sampled method (default)")
    if life:
        raise InputError("--life", True, "not allowed with --select (the precision outputs are selected against)")
    if model not in ("elastic", "contact", "transmission"):
        raise InputError("--select", str(selection), "allowed with --model elastic, contact or transmission (the "
                                                     "linear model draws no parts); --select none: random assembly")
    if not specs and spec_arcmin is None:
        raise InputError("--select", str(selection), "needs a spec to compare the yields, e.g. "
                                                     "--spec-lost-motion-arcmin 1 (--select none: random assembly)")
    with progress_bar(2 * n, note=CONTACT_NOTE) as progress:
        result = api.simulate_selected(problem, select=selection, samples=n, seed=seed, spec_arcmin=spec_arcmin,
                                       specs=specs, quantiles=quantile, workers=threads, model=model,
                                       progress=progress, error_model=error_model, save_units=n_save)
    data, rows = result.to_dict(), result.rows()

    def units_toml() -> str:
        from rvbacklash.design.measured import units_to_toml

        return units_to_toml(api.measured_units(problem, result.selected),
                             f"{len(result.selected.units)} selected units of `rvbacklash simulate {design} --model "
                             f"{model} --seed {seed} --select {selection}`\n(design {problem.name}); re-run one: "
                             f"rvbacklash {RERUN_SAVED_UNIT[model]} {design} --measured FILE --unit K")

    def show() -> None:
        console = stdout_console()
        tables.print_simulation(result.selected, console)
        print_selection(result, console)

    out.finish({"--json": lambda: render_json(data), "--csv": lambda: render_csv(rows), "--save-units": units_toml},
               show, data, rows)
    if result.partial:
        raise typer.Exit(130)


def parse_scenario(text: str):
    """'NAME:key=value,key=value' -> Scenario. Keys: involute, cycloid, crank, all, edition, or a
    factor key; values: grades (edition: 1995 | 2013); each key once."""
    from rvbacklash.analysis.scenarios import Scenario

    name, sep, body = text.partition(":")
    if not sep or not name.strip():
        raise InputError("--scenario", text, "allowed: NAME:key=grade[,key=grade...], e.g. b:involute=5")
    overrides: dict[str, int | str] = {}
    for item in (p.strip() for p in body.split(",")):
        key, eq, value = item.partition("=")
        key, value = key.strip(), value.strip()
        if not item or not eq or not key or not value:
            raise InputError("--scenario", text, f"'{item}' is not key=grade; allowed: NAME:key=grade[,key=grade...]")
        if key in overrides:
            raise InputError("--scenario", text, f"key '{key}' is given twice; allowed: each key once")
        if key == "edition":
            overrides[key] = value
            continue
        try:
            overrides[key] = int(value)
        except ValueError:
            raise InputError("--scenario", text, f"grade of '{key}' must be an integer, got '{value}'") from None
    try:
        return Scenario(name.strip(), overrides)
    except InputError as e:
        raise InputError("--scenario", text, e.allowed if not e.has_value else f"{e.value}: {e.allowed}") from None


SCENARIO_OPTION = typer.Option([], "--scenario", help="NAME:key=grade,... (keys: involute, cycloid, crank, all, "
                                                      "edition, or a factor key); repeatable.")
PAPER_OPTION = typer.Option(False, "--paper", help="Add the paper's Fig. 4 scenarios (a)-(d).")


@app.command()
@command
def compare(
    design: str = typer.Argument(..., help=DESIGN_HELP),
    scenario: list[str] = SCENARIO_OPTION,
    paper: bool = PAPER_OPTION,
    samples: str = typer.Option("1000000", "--samples", "-n", help="Samples per scenario (e.g. 1e6)."),
    seed: int = typer.Option(0, "--seed", help="Seed (an integer >= 0), the same for every scenario."),
    spec_arcmin: Optional[float] = SPEC_OPTION,
    method: str = METHOD_OPTION,
    model: str = MODEL_OPTION,
    workers: int = WORKERS_OPTION,
    json_out: Optional[str] = json_option("the scenario table"),
    csv_out: Optional[str] = csv_option("the scenario table"),
    plot: Optional[str] = typer.Option(None, "--plot", help="Write an SVG overlay of the distributions to FILE.",
                                        metavar="FILE"),
    fmt: Format = FORMAT_OPTION,
    force: bool = FORCE_OPTION,
    quiet: bool = QUIET_OPTION,
) -> None:
    """Compare precision-grade scenarios of one design (Sun et al. 2014, Fig. 4)."""
    import rvbacklash.api as api
    from rvbacklash.report import tables
    from rvbacklash.report.files import render_csv, render_json
    from rvbacklash.report.plots import scenario_overlay_svg

    n = parse_samples(samples) if method != "exact" else None
    chosen = [parse_scenario(text) for text in scenario]
    if not chosen and not paper:
        raise InputError("--scenario", None, "allowed: at least one --scenario NAME:KEY=GRADE, or --paper")
    threads = workers_or_none(workers)
    out = Outputs(fmt, force, quiet, json=json_out, csv=csv_out, plot=plot)
    problem = api.prepare(design)
    with progress_bar(n, note=CONTACT_NOTE if model == "contact" else None) as progress:
        results = api.compare(problem, chosen, paper=paper, samples=n if n is not None else 1, seed=seed,
                              method=method, spec_arcmin=spec_arcmin, model=model, workers=threads,
                              progress=progress)
    data, rows = results.to_dict(), results.rows()
    out.finish({"--json": lambda: render_json(data), "--csv": lambda: render_csv(rows),
                "--plot": lambda: scenario_overlay_svg(results.scenarios, spec_arcmin,
                                                       f"{problem.name}: precision-grade scenarios")},
               lambda: tables.print_scenarios(results, stdout_console()), data, rows)
    if results.partial:
        raise typer.Exit(130)


@app.command()
@command
def report(
    design: str = typer.Argument(..., help=DESIGN_HELP),
    output: str = typer.Option(..., "--output", "-o", help="The HTML file to write.", metavar="FILE"),
    samples: str = SAMPLES_OPTION,
    seed: int = SEED_OPTION,
    spec_arcmin: Optional[float] = SPEC_OPTION,
    method: str = METHOD_OPTION,
    model: str = MODEL_OPTION,
    scenario: list[str] = SCENARIO_OPTION,
    paper: bool = PAPER_OPTION,
    spec_lost_motion_arcmin: Optional[float] = SPEC_LOST_MOTION_OPTION,
    spec_rigidity_nm_per_arcmin: Optional[float] = SPEC_RIGIDITY_OPTION,
    spec_preload_um: Optional[float] = SPEC_PRELOAD_OPTION,
    spec_te_arcsec: Optional[float] = SPEC_TE_OPTION,
    sensitivity: bool = typer.Option(False, "--sensitivity", help="Add the Sobol indices of the model (What to "
                                                                  "tighten; minutes for the contact/elastic models)."),
    allocate: bool = typer.Option(False, "--allocate", help="Add the cheapest grades that meet --spec-arcmin at "
                                                            "--yield, their Pareto front and the Sobol indices."),
    yield_target: Optional[float] = typer.Option(None, "--yield", help="Target yield of --allocate: the share of "
                                                                       "units that must meet the spec, 0.5 < P < 1."),
    allocate_model: Optional[str] = typer.Option(None, "--allocate-model", help="Model of --allocate: linear (exact, "
                                                 "seconds; the rigid stack-up, conservative), contact, elastic or "
                                                 "transmission (Monte-Carlo per candidate, minutes to hours); default: "
                                                 "--model."),
    allocate_samples: str = typer.Option("65536", "--allocate-samples", help="Monte-Carlo samples per candidate "
                                         "of --allocate with a Monte-Carlo model (e.g. 2000 for a quick "
                                         "look, yields within about +-1 %)."),
    sweep: Optional[Path] = typer.Option(None, "--sweep", help="Add a finished sweep's results (the --out DIR of "
                                                               "`rvbacklash sweep`).", metavar="DIR"),
    workers: int = WORKERS_OPTION,
    capacity: bool = typer.Option(False, "--capacity", help="Add the capacity and life section (the nominal unit's "
                                                            "bearings, lives, derived ratings: docs/capacity.md)."),
    efficiency: bool = typer.Option(False, "--efficiency", help="Add the losses, efficiency and temperature section "
                                                                "(the nominal unit's datasheet: docs/efficiency.md)."),
    duty_cycle: Optional[str] = typer.Option(None, "--duty-cycle", help="A duty cycle (CSV or TOML, as `efficiency`'s, "
                                             "or a packaged cycle's name): the duty cycle of the efficiency and "
                                             "service-life sections (the efficiency section's thermal balance: the "
                                             "steady case temperature and lost motion there). Alone it implies "
                                             "--efficiency; with --service-life it does not.",
                                             metavar="FILE"),
    service_life: bool = typer.Option(False, "--service-life", help="Add the service-life section (lost motion and "
                                      "yield vs hours of --duty-cycle, default robot-joint; a production run of at "
                                      "most 2000 units: docs/service-life.md)."),
    hours: Optional[str] = typer.Option(None, "--hours", help="Hours of the duty cycle at which the service-life "
                                        "section reports, comma-separated (with --service-life; default 0,1000,6000)."),
    select: Optional[str] = typer.Option(None, "--select", help="Add the selective assembly section (--model "
                                         "contact, elastic or transmission, a spec): as simulate --select; default: "
                                         "the design's [selection] table; none: no section."),
    json_out: Optional[str] = json_option("every number of the report"),
    csv_out: Optional[str] = csv_option("the key numbers"),
    fmt: Format = typer.Option(Format.table, "--format", help="What to print on standard output: table (the path "
                                                              "written), json or csv (the key numbers)."),
    force: bool = FORCE_OPTION,
    quiet: bool = QUIET_OPTION,
) -> None:
    """One self-contained HTML report: design, factors, stack-up, charts, Monte-Carlo, scenarios
    (and the test-bench loop, the Sobol indices, the tolerance allocation, a sweep, the service life, when asked)."""
    import rvbacklash.api as api
    from rvbacklash.report.files import render_csv, render_json
    from rvbacklash.report.html import render_html

    n = parse_samples(samples) if method != "exact" else None
    chosen = [parse_scenario(text) for text in scenario]
    threads = workers_or_none(workers)
    specs = api.output_specs(model, spec_arcmin, spec_lost_motion_arcmin, spec_rigidity_nm_per_arcmin,
                         spec_preload_um)
    # a TE spec makes the report's run the transmission model's (the default linear model has no TE)
    model, _ = api.te_model_and_specs("contact" if spec_te_arcsec is not None and model == "linear" else model,
                                  spec_te_arcsec, {})
    if allocate and yield_target is None:
        raise InputError("--yield", None, "allowed: a target yield 0.5 < P < 1; --allocate needs it")
    if allocate and spec_arcmin is None:
        raise InputError("--spec-arcmin", None, "allowed: a spec > 0 [arcmin] of the model's primary output; "
                                                "--allocate needs it")
    if yield_target is not None and not allocate:
        raise InputError("--yield", yield_target, "allowed with --allocate only")
    life_hours = None
    if service_life and hours is not None:
        from rvbacklash.cli.service_life import _hours

        life_hours = _hours(hours)
    elif hours is not None:
        raise InputError("--hours", hours, "allowed with --service-life only")
    out = Outputs(fmt, force, quiet, output=output, json=json_out, csv=csv_out)
    problem = api.prepare(design)
    from rvbacklash.analysis.selection.classes import resolve_selection

    selection = resolve_selection(select, problem.design)
    if select is None and not _table_selection_applies(selection, model, n, specs, spec_arcmin, False, quiet):
        selection = None
    if selection is not None and (model not in ("contact", "elastic", "transmission") or n is None):
        raise InputError("--select", str(selection), "allowed with --model contact, elastic or transmission "
                                                     "(--select none: no selection section)")
    if selection is not None and not specs and spec_arcmin is None:
        raise InputError("--select", str(selection), "needs a spec to compare the yields, e.g. "
                                                     "--spec-lost-motion-arcmin 1 (--select none: no section)")
    with progress_bar(n, note=CONTACT_NOTE if model != "linear" else None) as progress:
        data = api.make_report(problem, samples=n if n is not None else 1, seed=seed, method=method,
                               spec_arcmin=spec_arcmin, specs=specs or None, scenarios=chosen, paper=paper, model=model,
                               workers=threads, sensitivity=sensitivity, allocate=allocate, yield_target=yield_target,
                               spec_rigidity_nm_per_arcmin=spec_rigidity_nm_per_arcmin,
                               spec_preload_um=spec_preload_um, spec_te_arcsec=spec_te_arcsec,
                               allocate_model=allocate_model,
                               allocate_samples=parse_samples(allocate_samples), sweep_dir=sweep,
                               progress=progress, capacity=capacity, efficiency=efficiency, duty_cycle=duty_cycle,
                               select=selection, service_life=service_life,
                               **({"service_life_hours": life_hours} if life_hours is not None else {}))
    summary = {"report": str(out.paths["--output"].resolve()), **data.metadata(),
               "key_numbers": data.key_numbers()}
    rows = data.rows()
    out.finish({"--output": lambda: render_html(data), "--json": lambda: render_json(data.to_dict()),
                "--csv": lambda: render_csv(rows)},
               lambda: _print_key_numbers(summary["key_numbers"], data.partial, data.model), summary, rows)
    if data.partial:
        raise typer.Exit(130)


def _print_key_numbers(numbers: dict, partial: bool, model: str) -> None:
    """The report's key numbers, one per line, in their order (the chosen model's first); with a
    model other than the linear one, a line marks where the linear stack-up that explains its
    figures begins (the files written follow)."""
    console = stdout_console()
    if partial:
        console.print("[bold red]PARTIAL: interrupted; the report shows what was finished[/]")
    width = max(map(len, numbers), default=0)
    console.print(f"{model} model:", highlight=False, markup=False)
    for name, value in numbers.items():
        if model != "linear" and name == "design.ratio":
            console.print("linear stack-up (explains the figures above):", highlight=False, markup=False)
        console.print(f"  {name:<{width}}  {value:.6g}" if isinstance(value, float) else f"  {name:<{width}}  {value}",
                      highlight=False, markup=False)


@app.command()
@command
def contact(
    design: str = typer.Argument(..., help=DESIGN_HELP),
    crank_angle_deg: Optional[float] = typer.Option(None, "--crank-angle-deg", help="Crank angle of the measurement "
                                                    "[deg], -360 to 360; default: the unit's own, else 0."),
    measured: Optional[Path] = typer.Option(None, "--measured", help="A TOML file of measured units (docs/contact.md); "
                                            "default: the nominal design.", metavar="UNIT.toml"),
    unit: Optional[int] = typer.Option(None, "--unit", help="The unit of --measured to run (0-based); default: all."),
    json_out: Optional[str] = json_option(),
    csv_out: Optional[str] = csv_option("the per-disc table"),
    plot: Optional[str] = typer.Option(None, "--plot", help="Write an SVG of disc 1, the pins and the first "
                                                             "contacts to FILE.", metavar="FILE"),
    fmt: Format = FORMAT_OPTION,
    force: bool = FORCE_OPTION,
    quiet: bool = QUIET_OPTION,
) -> None:
    """Play of one unit from the exact cycloid-pin geometry: the nominal design or measured units;
    per disc and direction the first-contact pins, the preload, the output lost motion [arcmin]."""
    import rvbacklash.api as api
    from rvbacklash.report import tables
    from rvbacklash.report.files import render_csv, render_json
    from rvbacklash.report.plots import contact_svg

    out = Outputs(fmt, force, quiet, json=json_out, csv=csv_out, plot=plot)
    result = api.contact(design, crank_angle_deg=crank_angle_deg, measured=measured, unit=unit)
    results = result if isinstance(result, list) else [result]
    if len(results) == 1:
        data, rows = results[0].to_dict(), results[0].rows()
    else:
        data = {"design": results[0].design_name, "units": [r.to_dict() for r in results]}
        rows = [{"index": k, **{key: v for key, v in r.to_dict().items() if not isinstance(v, (dict, list))}}
                for k, r in enumerate(results)]
    if plot is not None and len(results) > 1:
        raise InputError("--plot", str(plot), "allowed with one unit: pick it with --unit")
    out.finish({"--json": lambda: render_json(data), "--csv": lambda: render_csv(rows),
                "--plot": lambda: contact_svg(results[0])},
               lambda: [tables.print_contact(r, stdout_console()) for r in results], data, rows)


tolerance_app = typer.Typer(help="Tolerances from precision grades (ISO 1328-1, ISO 286).", no_args_is_help=True,
                            rich_markup_mode=None)
app.add_typer(tolerance_app, name="tolerance")


@tolerance_app.command("iso1328")
@command
def tolerance_iso1328(
    edition: str = typer.Option("1995", "--edition", help="1995 | 2013"),
    module: float = typer.Option(..., "--module", help="Module m [mm]."),
    diameter: float = typer.Option(..., "--diameter", help="Reference diameter d [mm]."),
    width: float = typer.Option(..., "--width", help="Face width b [mm]."),
    grade: int = typer.Option(..., "--grade", help="Grade (1995: 0-12) or class (2013: 1-11)."),
    json_out: Optional[str] = json_option("the tolerances"),
    csv_out: Optional[str] = csv_option("the tolerances"),
    fmt: Format = FORMAT_OPTION,
    force: bool = FORCE_OPTION,
    quiet: bool = QUIET_OPTION,
) -> None:
    """Gear tolerances f_pt, F_p, F_alpha, f_falpha, F_beta, F_r [um] of one gear."""
    from rvbacklash.report.files import render_csv, render_json
    from rvbacklash.standards.iso1328 import iso1328_tolerances

    out = Outputs(fmt, force, quiet, json=json_out, csv=csv_out)
    t = iso1328_tolerances(edition, module, diameter, width, grade)
    data = t.to_dict()

    def table() -> None:
        sys.stdout.write(f"{t.standard}, grade {t.grade}: m = {module:g} mm, d = {diameter:g} mm, b = {width:g} mm "
                         f"({t.note})\n")
        for k in ("fpt_um", "Fp_um", "Falpha_um", "ffalpha_um", "Fbeta_um", "Fr_um"):
            sys.stdout.write(f"  {k:11s} {getattr(t, k):8.1f}\n")

    out.finish({"--json": lambda: render_json(data), "--csv": lambda: render_csv([data])}, table, data, [data])


@tolerance_app.command("iso286")
@command
def tolerance_iso286(
    size: float = typer.Option(..., "--size", help="Nominal size D [mm]."),
    grade: str = typer.Option(..., "--grade", help="IT1 .. IT12"),
    fit: Optional[str] = typer.Option(None, "--fit", help="A fit such as H7/g6."),
    json_out: Optional[str] = json_option("the tolerance and fit"),
    csv_out: Optional[str] = csv_option("the tolerance and fit"),
    fmt: Format = FORMAT_OPTION,
    force: bool = FORCE_OPTION,
    quiet: bool = QUIET_OPTION,
) -> None:
    """Standard tolerance IT [um] and, optionally, the limits and clearance of a fit."""
    from rvbacklash.report.files import render_csv, render_json
    from rvbacklash.standards import iso286

    out = Outputs(fmt, force, quiet, json=json_out, csv=csv_out)
    g = iso286.parse_it(grade)
    step = iso286.size_step_mm(size)
    data = {"standard": "ISO 286-1:2010", "size_mm": size, "grade": f"IT{g}", "size_step_mm": list(step),
            "IT_um": iso286.it_um(g, size)}
    if fit is not None:
        data["fit"] = iso286.fit(fit, size).to_dict()

    def table() -> None:
        sys.stdout.write(f"ISO 286-1 IT{g} at {size:g} mm (step {step[0]:g}..{step[1]:g}): {data['IT_um']:g} um\n")
        if fit is not None:
            f = data["fit"]
            sys.stdout.write(f"  fit {f['fit']}: hole {f['hole_lower_um']:+g}/{f['hole_upper_um']:+g} um, shaft "
                             f"{f['shaft_lower_um']:+g}/{f['shaft_upper_um']:+g} um, clearance "
                             f"{f['clearance_min_um']:g} .. {f['clearance_max_um']:g} um\n")

    row = {k: v for k, v in data.items() if k not in ("fit", "size_step_mm")} | (
        {f"fit_{k}": v for k, v in data["fit"].items()} if fit is not None else {})
    out.finish({"--json": lambda: render_json(data), "--csv": lambda: render_csv([row])}, table, data, [row])


class SchemaOutput(str, Enum):
    simulate = "simulate"
    analyze = "analyze"
    hysteresis = "hysteresis"
    allocate = "allocate"
    sensitivity = "sensitivity"
    sweep = "sweep"
    transmission_error = "transmission-error"
    contact = "contact"
    assemble = "assemble"
    capacity = "capacity"
    efficiency = "efficiency"
    service_life = "service-life"
    bench = "bench"
    calibrate = "calibrate"


@app.command()
@command
def schema(output: Optional[SchemaOutput] = typer.Option(
        None, "--output", help="Print instead the JSON Schema of this command's JSON output (simulate, analyze, "
                               "hysteresis, allocate, sensitivity, sweep, transmission-error, contact, bench, calibrate, capacity, efficiency); its "
                               "schema_version is in CHANGELOG.md.")
           ) -> None:
    """Print the JSON schema of the design file, or of a command's JSON output (--output)."""
    from rvbacklash.report.files import render_json

    if output is None:
        from rvbacklash.design.schema import Design

        sys.stdout.write(render_json(Design.model_json_schema(), stamp=False))
        return
    from rvbacklash.report.schemas import output_schema

    sys.stdout.write(render_json(output_schema(output.value), stamp=False))


@app.command()
@command
def examples(name: Optional[str] = typer.Argument(None, help="Print this example's TOML.")) -> None:
    """List the built-in example designs and sweeps, or print one to start from."""
    from rvbacklash.design.loading import available_examples, example_text, load_design
    from rvbacklash.design.sweep_spec import available_sweeps, sweep_description, sweep_example_text

    if name is None:
        for n in available_examples():
            sys.stdout.write(f"{n:10s} {load_design(n).description}\n")
        for n in available_sweeps():
            sys.stdout.write(f"{n:10s} sweep: {sweep_description(n)}\n")
        return
    sys.stdout.write(sweep_example_text(name) if name in available_sweeps() else example_text(name))
