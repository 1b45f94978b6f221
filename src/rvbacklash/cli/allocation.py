"""Commands `sensitivity` (Sobol indices of any model) and `allocate` (the cheapest grades that
meet a spec): flags to API parameters, results to tables, JSON, CSV, SVG and a design file."""

from __future__ import annotations

from typing import Optional

import typer

from rvbacklash.cli.app import app
from rvbacklash.errors import InputError
from rvbacklash.cli.common import (DESIGN_HELP, FORCE_OPTION, FORMAT_OPTION, QUIET_OPTION, SEED_OPTION, Format,
                                   Outputs, command, csv_option, json_option, parse_samples, progress_bar,
                                   stdout_console, workers_or_none)


@app.command()
@command
def sensitivity(
    design: str = typer.Argument(..., help=DESIGN_HELP),
    model: str = typer.Option("linear", "--model", help="linear | contact | elastic | transmission: the model whose "
                                                        "output is attributed (each factor drawn from its own random "
                                                        "stream)."),
    output: Optional[str] = typer.Option(None, "--output", help="Output to attribute: backlash, lost_motion, "
                                                                "rigidity, ... (default: the model's first)."),
    samples: str = typer.Option("16384", "--samples", "-n", help="Units per sample set N, a power of two (the "
                                                                 "model runs N (D + 2) times for D factors)."),
    seed: int = SEED_OPTION,
    json_out: Optional[str] = json_option(),
    csv_out: Optional[str] = csv_option("the indices"),
    plot: Optional[str] = typer.Option(None, "--plot", help="Write the bar chart (first order beside total, "
                                                             "95 % intervals) as SVG to FILE.", metavar="FILE"),
    fmt: Format = FORMAT_OPTION,
    force: bool = FORCE_OPTION,
    quiet: bool = QUIET_OPTION,
) -> None:
    """Global sensitivity: first-order and total Sobol indices per factor with 95 % bootstrap intervals."""
    import rvbacklash.api as api
    from rvbacklash.report.allocation_tables import print_sensitivity
    from rvbacklash.report.files import render_csv, render_json
    from rvbacklash.report.sensitivity_plots import sobol_svg

    n = parse_samples(samples)
    out = Outputs(fmt, force, quiet, json=json_out, csv=csv_out, plot=plot)
    problem = api.prepare(design)
    total = n * (int(problem.random_mask.sum()) + 2)
    with progress_bar(total, what="model runs") as progress:
        result = api.sensitivity(problem, model=model, output=output, samples=n, seed=seed, progress=progress)
    data, rows = result.to_dict(), result.rows()
    out.finish({"--json": lambda: render_json(data), "--csv": lambda: render_csv(rows),
                "--plot": lambda: sobol_svg(result)},
               lambda: print_sensitivity(result, stdout_console()), data, rows)
    if result.partial:
        raise typer.Exit(130)


@app.command()
@command
def allocate(
    design: str = typer.Argument(..., help=DESIGN_HELP),
    spec_arcmin: Optional[float] = typer.Option(None, "--spec-arcmin", help="Spec (upper limit) of the model's "
                                                "primary output: backlash, lost motion for the elastic model [arcmin] "
                                                "(required, except with --spec-accuracy-life-h)."),
    yield_target: float = typer.Option(..., "--yield", help="Target yield P: the share of units that must meet "
                                                            "the spec, 0.5 < P < 1 (e.g. 0.99)."),
    model: Optional[str] = typer.Option(None, "--model", help="linear (exact: MILP on the exact distribution; the "
                                        "default) | contact | elastic | transmission (Monte-Carlo search with common "
                                        "random numbers); with --spec-accuracy-life-h: elastic, the default."),
    spec_rigidity: Optional[float] = typer.Option(None, "--spec-rigidity-nm-per-arcmin",
                                                  help="Also require torsional rigidity >= K [N m/arcmin] "
                                                       "(models with a rigidity output)."),
    spec_preload: Optional[float] = typer.Option(None, "--spec-preload-um",
                                                 help="Also require the cycloid stage's preload <= P [um] (contact, "
                                                      "elastic): without it, coarser parts can 'meet' a lost-motion "
                                                      "spec by interference."),
    spec_te_arcsec: Optional[float] = typer.Option(None, "--spec-te-arcsec",
                                                   help="Also require the transmission error's peak-to-peak over one "
                                                        "output revolution <= X [arcsec]; turns --model contact into "
                                                        "--model transmission (docs/transmission-error.md)."),
    spec_life_h: Optional[float] = typer.Option(None, "--spec-life-h", help="Also require the reducer's L10 at the "
                                                "rated torque and speed >= L [h] (--model elastic; docs/capacity.md)."),
    spec_rated_torque_nm: Optional[float] = typer.Option(None, "--spec-rated-torque-nm", help="Also require the "
                                                         "derived rated torque >= T [N m] (--model elastic)."),
    spec_accuracy_life_h: Optional[float] = typer.Option(
        None, "--spec-accuracy-life-h", help="Keep the lost motion within --spec-lost-motion-arcmin for H hours of "
        "--duty-cycle: the share of units whose accuracy life reaches H, each unit with its own wear, as "
        "`service-life` reads it (elastic model, no other spec; -n from 100; docs/service-life.md)."),
    duty_cycle: Optional[str] = typer.Option(None, "--duty-cycle", help="The duty cycle of --spec-accuracy-life-h "
                                             "(CSV or TOML, as `service-life`'s, or a packaged cycle's name: "
                                             "robot-joint).", metavar="FILE"),
    spec_lost_motion_arcmin: Optional[float] = typer.Option(None, "--spec-lost-motion-arcmin", help="The lost-motion "
                                                            "spec of --spec-accuracy-life-h [arcmin] (or --spec-arcmin; "
                                                            "default 1.5, as `service-life`)."),
    angles: Optional[int] = typer.Option(None, "--angles", help="With --spec-accuracy-life-h: crank angles per "
                                         "revolution of each time step's loads (default 12), as `service-life`."),
    step_fraction: Optional[float] = typer.Option(None, "--step-fraction", help="With --spec-accuracy-life-h: the "
                                                  "largest wear depth per time step as a share of the reference "
                                                  "clearance (default 0.1), as `service-life`."),
    unit_wear: str = typer.Option("own", "--unit-wear", help="With --spec-accuracy-life-h: 'own' (each unit's own "
                                  "wear) or 'nominal' (the nominal unit's), as `service-life`."),
    write_design: Optional[str] = typer.Option(None, "--write-design", metavar="FILE",
                                                help="Write the chosen design (its grades set) as a TOML design "
                                                     "file that simulate re-runs."),
    json_out: Optional[str] = json_option(),
    csv_out: Optional[str] = csv_option("the cost-yield Pareto front"),
    plot: Optional[str] = typer.Option(None, "--plot", help="Write the cost-yield Pareto front as SVG to FILE.",
                                        metavar="FILE"),
    samples: str = typer.Option("65536", "--samples", "-n", help="Samples per candidate (Monte-Carlo models)."),
    select_classes: Optional[str] = typer.Option(
        None, "--select-classes", metavar="MENU", help="Grades and classes: the cheapest grades with each selective "
        "assembly of MENU (PINS:ROLLERS class counts, 2 um wide, e.g. 1:1,5:1,5:3; 'default': "
        "1:1,3:1,5:1,1:3,3:3,5:3), its measuring, classes and surplus costed by [costs.selection]; contact, "
        "elastic or transmission model (docs/selective-assembly.md)."),
    seed: int = SEED_OPTION,
    scheduler: str = typer.Option("inline", "--scheduler", help="Where Monte-Carlo candidates run: inline | local | "
                                                                "the address of a Dask scheduler (tcp://host:8786)."),
    workers: int = typer.Option(0, "--workers", help="Worker threads inline, worker processes on a local cluster "
                                                     "(0 = all cores); results do not depend on it."),
    fmt: Format = FORMAT_OPTION,
    force: bool = FORCE_OPTION,
    quiet: bool = QUIET_OPTION,
) -> None:
    """Tolerance allocation: the cheapest grade per part group that meets the spec at the target yield."""
    import rvbacklash.api as api
    from rvbacklash.report.allocation_plots import front_svg
    from rvbacklash.report.allocation_tables import print_allocation
    from rvbacklash.report.design_toml import design_toml
    from rvbacklash.report.files import render_csv, render_json

    n = parse_samples(samples)
    threads = workers_or_none(workers)
    life = spec_accuracy_life_h is not None
    if not life and spec_arcmin is None:
        raise InputError("--spec-arcmin", None, "required: the spec of the model's primary output [arcmin] (or "
                                                "--spec-accuracy-life-h with --duty-cycle)")
    out = Outputs(fmt, force, quiet, write_design=write_design, json=json_out, csv=csv_out, plot=plot)
    problem = api.prepare(design)
    if select_classes is not None:
        if life:
            raise InputError("--select-classes", select_classes, "not allowed with --spec-accuracy-life-h")
        model = model or "linear"
        if plot is not None:
            raise InputError("--plot", plot, "not drawn with --select-classes (its options' table is the result)")
        if spec_life_h is not None or spec_rated_torque_nm is not None:
            raise InputError("--select-classes", select_classes, "not allowed with a life spec (the precision "
                                                                 "outputs are selected against)")
        _allocate_classes(problem, design, select_classes, out, spec_arcmin, yield_target, model, spec_rigidity,
                          spec_preload, spec_te_arcsec, n, seed, threads)
        return
    exact = (model or ("elastic" if life else "linear")) == "linear"
    with progress_bar(None if exact else 200, what="candidates",
                      note="the first candidate (a first run compiles its kernels, ~1 min, once)" if life else None) \
            as progress:
        result = api.allocate(problem, spec_arcmin=spec_arcmin, yield_target=yield_target, model=model,
                              spec_rigidity_nm_per_arcmin=spec_rigidity, spec_preload_um=spec_preload,
                              spec_te_arcsec=spec_te_arcsec, spec_life_h=spec_life_h,
                              spec_rated_torque_nm=spec_rated_torque_nm, samples=n, seed=seed, scheduler=scheduler,
                              workers=threads, progress=progress, spec_accuracy_life_h=spec_accuracy_life_h,
                              duty_cycle=duty_cycle, spec_lost_motion_arcmin=spec_lost_motion_arcmin, angles=angles,
                              step_fraction=step_fraction, unit_wear=unit_wear)
    # every row of the Pareto front says whether the search was interrupted, as every other CSV
    data, rows = result.to_dict(), [{**r, "partial": result.partial} for r in result.front_rows()]
    header = (f"Written by rvbacklash allocate ({problem.source}): {result.binding.constraint}, {result.model} model.\n"
              f"Cost {result.cost:.6g} {result.unit}"
              + (f" against {result.baseline.cost:.6g} for uniform grade {result.baseline.grade}"
                 if result.baseline.cost is not None else "")
              + f"; yield {result.yield_.fraction:.6f}.\n"
              + (f"Re-run: rvbacklash simulate FILE --method exact --spec-arcmin {result.spec_arcmin:g}"
                 if result.model == "linear" else
                 f"Re-run: rvbacklash service-life FILE --duty-cycle {duty_cycle} --hours 0,"
                 f"{result.spec_accuracy_life_h:g} --spec-lost-motion-arcmin {result.spec_arcmin:g} -n {result.samples} "
                 f"--seed {result.seed}" + (f" --angles {angles}" if angles is not None else "")
                 + (f" --step-fraction {step_fraction:g}" if step_fraction is not None else "")
                 + (f" --unit-wear {unit_wear}" if unit_wear != "own" else "")
                 + " (accuracy_life_yield)" if life else
                 f"Re-run: rvbacklash simulate FILE --model {result.model} --spec-arcmin {result.spec_arcmin:g} "
                 f"-n {result.samples} --seed {result.seed}"
                 + (f" --spec-rigidity-nm-per-arcmin {spec_rigidity:g}" if spec_rigidity is not None else "")
                 + (f" --spec-preload-um {spec_preload:g}" if spec_preload is not None else "")
                 + (f" --spec-te-arcsec {spec_te_arcsec:g}" if spec_te_arcsec is not None else "")
                 + (f" --spec-life-h {spec_life_h:g}" if spec_life_h is not None else "")
                 + (f" --spec-rated-torque-nm {spec_rated_torque_nm:g}" if spec_rated_torque_nm is not None else "")))
    out.finish({"--write-design": lambda: design_toml(result.design, header), "--json": lambda: render_json(data),
                "--csv": lambda: render_csv(rows), "--plot": lambda: front_svg(result)},
               lambda: print_allocation(result, stdout_console()), data, rows)
    if result.partial:
        raise typer.Exit(130)


def parse_menu(text: str) -> tuple[tuple[int, int], ...]:
    """``--select-classes``: 'default' or PINS:ROLLERS class counts, comma-separated."""
    from rvbacklash.analysis.allocation.classes import DEFAULT_MENU
    from rvbacklash.analysis.selection.classes import MAX_CLASSES

    if text.strip().lower() == "default":
        return DEFAULT_MENU
    menu = []
    for item in text.split(","):
        pins, colon, rollers = item.strip().partition(":")
        try:
            pair = (int(pins), int(rollers))
        except ValueError:
            pair = None
        if not colon or pair is None or not all(1 <= k <= MAX_CLASSES for k in pair):
            raise InputError("--select-classes", text, f"'{item.strip()}': allowed PINS:ROLLERS class counts 1 to "
                                                       f"{MAX_CLASSES}, comma-separated (e.g. 1:1,5:3), or default")
        menu.append(pair)
    return tuple(menu)


def _allocate_classes(problem, design, select_classes, out, spec_arcmin, yield_target, model, spec_rigidity,
                      spec_preload, spec_te_arcsec, n, seed, threads) -> None:
    """``allocate --select-classes``: the cheapest grades and classes (analysis.allocation.classes)."""
    from rvbacklash.analysis.allocation.classes import allocate_grades_and_classes
    from rvbacklash.report.allocation_tables import print_class_allocation
    from rvbacklash.report.design_toml import design_toml
    from rvbacklash.report.files import render_csv, render_json

    menu = parse_menu(select_classes)
    if model == "linear":
        raise InputError("--select-classes", select_classes, "allowed with --model contact, elastic or transmission "
                                                             "(the linear model draws no parts)")
    with progress_bar(None, what="candidates") as progress:
        result = allocate_grades_and_classes(problem, model=model, spec_arcmin=spec_arcmin, yield_target=yield_target,
                                             menu=menu, spec_rigidity_nm_per_arcmin=spec_rigidity,
                                             spec_preload_um=spec_preload, spec_te_arcsec=spec_te_arcsec, samples=n,
                                             seed=seed, workers=threads, progress=progress)
    data, rows = result.to_dict(), [{**r, "partial": False} for r in result.rows()]

    def chosen_design() -> str:
        from rvbacklash.design.selection import SelectionInputs

        chosen = next(o for o in result.options if o.chosen)
        d = result.allocation.design
        if chosen.pin_classes > 1 or chosen.roller_classes > 1:
            d = d.model_copy(update={"selection": SelectionInputs(
                pins=f"{chosen.pin_classes}x2um" if chosen.pin_classes > 1 else None,
                rollers=f"{chosen.roller_classes}x2um" if chosen.roller_classes > 1 else None)})
        return design_toml(d, f"Written by rvbacklash allocate --select-classes ({problem.source}): grades and "
                              f"classes, {chosen.selection}, total cost {chosen.total_cost:.6g} {result.unit} per "
                              f"reducer built; {result.model} model.")

    if result.allocation is None:
        raise InputError("yield_target", yield_target, "no option of the menu meets the target under the "
                                                       f"{model} model; allowed: a lower yield or a larger spec")
    out.finish({"--write-design": chosen_design, "--json": lambda: render_json(data),
                "--csv": lambda: render_csv(rows)},
               lambda: print_class_allocation(result, stdout_console()), data, rows)
