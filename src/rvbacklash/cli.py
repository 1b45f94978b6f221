"""Command-line interface: a thin layer over the library.

Every command prints a rich table by default; ``--format json|csv`` prints the same result
as JSON or CSV instead, and ``--json OUT`` / ``--csv OUT`` write files. Bad input of any kind
ends with one line ``error: <field> = <value>: <allowed>`` on stderr and exit code 2, before
any output file is written; an existing output file is only replaced with ``--force``.
"""

from __future__ import annotations

import contextlib
import functools
import math
import sys
from enum import Enum
from pathlib import Path
from typing import Callable, Optional

import typer
from rich.console import Console

from rvbacklash import __version__
from rvbacklash.analysis.stackup import analyze as run_stackup
from rvbacklash.design.loading import available_examples, example_text, load_design
from rvbacklash.design.schema import Design
from rvbacklash.errors import InputError
from rvbacklash.report import tables
from rvbacklash.report.files import check_writable, render_csv, render_json, write_files

app = typer.Typer(
    add_completion=False,
    no_args_is_help=True,
    pretty_exceptions_enable=False,
    help="Design-stage backlash (lost motion) of RV reducers, after Sun et al. 2014.",
)
# Files and pipes get a wide, fixed layout (no wrapping of the tables); terminals their own width.
stdout = Console() if sys.stdout.isatty() else Console(width=160)

DESIGN_HELP = "TOML design file, or a built-in example name (see `rvbacklash examples`)."


class Format(str, Enum):
    table = "table"
    json = "json"
    csv = "csv"


FORMAT_OPTION = typer.Option(Format.table, "--format", help="What to print on stdout: table, json or csv.")
FORCE_OPTION = typer.Option(False, "--force", help="Replace existing output files.")
MODEL_OPTION = typer.Option("linear", "--model", help="linear (Eq. (2)) | contact (geometric cycloid-pin contact, "
                                                      "per-pin errors; docs/contact.md)")


def exits_cleanly_on_bad_input(fn: Callable) -> Callable:
    @functools.wraps(fn)
    def wrapper(*args, **kwargs):
        try:
            return fn(*args, **kwargs)
        except InputError as e:
            sys.stderr.write(f"error: {e}\n")
            raise typer.Exit(2) from None
    return wrapper


def emit(fmt: Format, table: Callable[[], None], data: dict, rows: list[dict]) -> None:
    """Print a result on stdout in the chosen format."""
    if fmt is Format.json:
        sys.stdout.write(render_json(data))
    elif fmt is Format.csv:
        sys.stdout.write(render_csv(rows))
    else:
        table()


def finish(files: dict[str, tuple[Optional[Path], Callable[[], str]]], force: bool, fmt: Format,
           table: Callable[[], None], data: dict, rows: list[dict], quiet: bool = False) -> None:
    """Write the requested files ({option: (path or None, render)}), all or none, then print
    the result in ``fmt`` and, for tables, which files were written."""
    outputs = {option: (path, render()) for option, (path, render) in files.items() if path is not None}
    write_files(outputs, force)
    if quiet:
        return
    emit(fmt, table, data, rows)
    if fmt is Format.table:
        for path, _ in outputs.values():
            stdout.print(f"wrote {path}")


def check_outputs(force: bool, **paths: Optional[Path]) -> None:
    for option, path in paths.items():
        if path is not None:
            check_writable(f"--{option}", path, force)


def parse_samples(text: str) -> int:
    """'10000000', '1e7' or '10_000_000' -> 10000000; anything not a whole number is an error."""
    try:
        value = float(text.replace("_", ""))
    except ValueError:
        raise InputError("--samples", text, "allowed: a whole number of samples >= 1") from None
    if not math.isfinite(value) or value != int(value):
        raise InputError("--samples", text, "allowed: a whole number of samples >= 1")
    return int(value)


@contextlib.contextmanager
def progress_bar(total: int | None):
    """A rich progress bar on stderr for long runs when stderr is a terminal; else nothing."""
    if total is None or total < 5_000_000 or not sys.stderr.isatty():
        yield None
        return
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TimeRemainingColumn

    with Progress("[progress.description]{task.description}", BarColumn(), MofNCompleteColumn(),
                  TimeRemainingColumn(), console=Console(stderr=True), transient=True) as bar:
        task = bar.add_task("sampling", total=total)
        yield lambda done: bar.update(task, completed=done)


@app.callback()
def _root(version: bool = typer.Option(False, "--version", help="Print the version and exit.")) -> None:
    if version:
        stdout.print(__version__)
        raise typer.Exit(0)


@app.command()
@exits_cleanly_on_bad_input
def analyze(
    design: str = typer.Argument(..., help=DESIGN_HELP),
    json_out: Optional[Path] = typer.Option(None, "--json", help="Write the full result as JSON."),
    csv_out: Optional[Path] = typer.Option(None, "--csv", help="Write the factor table as CSV."),
    fmt: Format = FORMAT_OPTION,
    force: bool = FORCE_OPTION,
    quiet: bool = typer.Option(False, "--quiet", "-q", help="Nothing on stdout."),
) -> None:
    """Stack-up and sensitivity of the linear model (Sun et al. 2014, Tables 2-3, Eq. (1)-(7))."""
    check_outputs(force, json=json_out, csv=csv_out)
    result = run_stackup(load_design(design))
    data = result.to_dict()
    rows = data["factors"]
    finish({"--json": (json_out, lambda: render_json(data)), "--csv": (csv_out, lambda: render_csv(rows))}, force, fmt,
           lambda: (tables.print_stackup(result, stdout), tables.print_sources(result, stdout)), data, rows, quiet)


@app.command()
@exits_cleanly_on_bad_input
def simulate(
    design: str = typer.Argument(..., help=DESIGN_HELP),
    samples: str = typer.Option("1000000", "--samples", "-n", help="Number of samples (e.g. 1e7)."),
    seed: int = typer.Option(0, "--seed", help="Seed (integer >= 0; 0 is valid); same seed, same numbers."),
    spec_arcmin: Optional[float] = typer.Option(None, "--spec-arcmin", help="Backlash spec (upper limit) [arcmin]."),
    method: str = typer.Option("default", "--method", help="default | box-muller | sobol | exact"),
    model: str = MODEL_OPTION,
    quantile: list[float] = typer.Option([], "--quantile", "-q", help="Extra quantile to report (0..1); repeatable."),
    workers: int = typer.Option(0, "--workers", help="Worker threads (0 = all cores); results do not depend on it."),
    json_out: Optional[Path] = typer.Option(None, "--json", help="Write the result as JSON."),
    csv_out: Optional[Path] = typer.Option(None, "--csv", help="Write the statistics as CSV."),
    fmt: Format = FORMAT_OPTION,
    force: bool = FORCE_OPTION,
    quiet: bool = typer.Option(False, "--quiet", help="Nothing on stdout."),
) -> None:
    """Monte-Carlo simulation of the output backlash, with confidence intervals and yield."""
    from rvbacklash.analysis.simulation import simulate as run_simulation

    n = parse_samples(samples) if method != "exact" else None
    if workers < 0:
        raise InputError("--workers", workers, "allowed: 0 (all cores) or a number of threads >= 1")
    check_outputs(force, json=json_out, csv=csv_out)
    d = load_design(design)
    with progress_bar(n) as progress:
        result = run_simulation(d, n, seed, method, spec_arcmin, tuple(quantile), workers or None,
                                model=model, progress=progress)
    data, rows = result.to_dict(), result.rows()
    finish({"--json": (json_out, lambda: render_json(data)), "--csv": (csv_out, lambda: render_csv(rows))}, force, fmt,
           lambda: tables.print_simulation(result, stdout), data, rows, quiet)
    if result.partial:
        raise typer.Exit(130)


def _scenarios(d: Design, scenario: list[str], paper: bool) -> list[tuple[str, dict]]:
    from rvbacklash.analysis.scenarios import paper_scenarios, parse_scenario

    chosen = [parse_scenario(text) for text in scenario]
    return (paper_scenarios(d) if paper else []) + chosen


SCENARIO_OPTION = typer.Option([], "--scenario", help="NAME:key=grade,... (keys: involute, cycloid, crank, all, "
                                                      "edition, or a factor key); repeatable.")


@app.command()
@exits_cleanly_on_bad_input
def compare(
    design: str = typer.Argument(..., help=DESIGN_HELP),
    scenario: list[str] = SCENARIO_OPTION,
    paper: bool = typer.Option(False, "--paper", help="Add the paper's Fig. 4 scenarios (a)-(d)."),
    samples: str = typer.Option("1000000", "--samples", "-n", help="Samples per scenario."),
    seed: int = typer.Option(0, "--seed", help="Seed (the same for every scenario)."),
    spec_arcmin: Optional[float] = typer.Option(None, "--spec-arcmin", help="Backlash spec [arcmin]."),
    method: str = typer.Option("default", "--method", help="default | box-muller | sobol | exact"),
    model: str = MODEL_OPTION,
    json_out: Optional[Path] = typer.Option(None, "--json", help="Write the scenario table as JSON."),
    csv_out: Optional[Path] = typer.Option(None, "--csv", help="Write the scenario table as CSV."),
    plot: Optional[Path] = typer.Option(None, "--plot", help="Write an SVG overlay of the distributions."),
    fmt: Format = FORMAT_OPTION,
    force: bool = FORCE_OPTION,
) -> None:
    """Compare precision-grade scenarios of one design (Sun et al. 2014, Fig. 4)."""
    from rvbacklash.analysis.scenarios import compare as run_compare
    from rvbacklash.report.plots import scenario_overlay_svg

    n = parse_samples(samples) if method != "exact" else None
    check_outputs(force, json=json_out, csv=csv_out, plot=plot)
    d = load_design(design)
    chosen = _scenarios(d, scenario, paper)
    if not chosen:
        raise InputError("--scenario", None, "allowed: at least one --scenario NAME:OVERRIDES, or --paper")
    results = run_compare(d, chosen, n, seed, method, spec_arcmin, model)
    data, rows = results.to_dict(), results.rows()
    finish({"--json": (json_out, lambda: render_json(data)), "--csv": (csv_out, lambda: render_csv(rows)),
            "--plot": (plot, lambda: scenario_overlay_svg(results, spec_arcmin, f"{d.name}: precision-grade scenarios"))},
           force, fmt, lambda: tables.print_scenarios(results, stdout), data, rows)


@app.command()
@exits_cleanly_on_bad_input
def report(
    design: str = typer.Argument(..., help=DESIGN_HELP),
    output: Path = typer.Option(..., "--output", "-o", help="The HTML file to write."),
    samples: str = typer.Option("1000000", "--samples", "-n", help="Monte-Carlo samples."),
    seed: int = typer.Option(0, "--seed", help="Seed (integer >= 0)."),
    spec_arcmin: Optional[float] = typer.Option(None, "--spec-arcmin", help="Backlash spec [arcmin]."),
    method: str = typer.Option("default", "--method", help="default | box-muller | sobol | exact"),
    model: str = MODEL_OPTION,
    scenario: list[str] = SCENARIO_OPTION,
    paper: bool = typer.Option(False, "--paper", help="Add the paper's Fig. 4 scenarios (a)-(d)."),
    json_out: Optional[Path] = typer.Option(None, "--json", help="Also write every number of the report as JSON."),
    fmt: Format = typer.Option(Format.table, "--format", help="table: print the path; json, csv: the key numbers."),
    force: bool = FORCE_OPTION,
) -> None:
    """One self-contained HTML report: design, factors, stack-up, charts, Monte-Carlo, scenarios."""
    from rvbacklash.analysis.scenarios import parse_scenario
    from rvbacklash.report.html import make_report, render_html

    n = parse_samples(samples) if method != "exact" else None
    check_outputs(force, output=output, json=json_out)
    chosen = [parse_scenario(text) for text in scenario]
    with progress_bar(n) as progress:
        data = make_report(design, n, seed, method, spec_arcmin, chosen, paper, progress, model)
    outputs = {"--output": (output, render_html(data))}
    if json_out is not None:
        outputs["--json"] = (json_out, render_json(data.to_dict()))
    write_files(outputs, force)
    summary = {"report": str(output.resolve()), **data.metadata(), "key_numbers": data.key_numbers()}
    rows = [{"key": k, "value": v} for k, v in data.key_numbers().items()]
    emit(fmt, lambda: stdout.print(f"report written to {output.resolve()}"), summary, rows)


@app.command()
@exits_cleanly_on_bad_input
def contact(
    design: str = typer.Argument(..., help=DESIGN_HELP),
    crank_angle_deg: float = typer.Option(0.0, "--crank-angle-deg", help="Crank angle of the measurement [deg]."),
    json_out: Optional[Path] = typer.Option(None, "--json", help="Write the result as JSON."),
    plot: Optional[Path] = typer.Option(None, "--plot", help="Write an SVG of the disc, the pins and the first contacts."),
    fmt: Format = FORMAT_OPTION,
    force: bool = FORCE_OPTION,
) -> None:
    """Play of the nominal design from the exact cycloid-pin geometry: per disc and direction,
    the first-contact pins, and the output lost motion."""
    from rvbacklash.analysis.contact import nominal_contact
    from rvbacklash.report.plots import contact_svg

    if not math.isfinite(crank_angle_deg):
        raise InputError("--crank-angle-deg", crank_angle_deg, "allowed: a finite angle [deg]")
    check_outputs(force, json=json_out, plot=plot)
    result = nominal_contact(load_design(design), math.radians(crank_angle_deg))
    data = result.to_dict()
    rows = [{"disc": i, **disc} for i, disc in enumerate(data["discs"])]
    finish({"--json": (json_out, lambda: render_json(data)), "--plot": (plot, lambda: contact_svg(result))}, force,
           fmt, lambda: tables.print_contact(result, stdout), data, rows)


tolerance_app = typer.Typer(help="Tolerances from precision grades (ISO 1328-1, ISO 286).", no_args_is_help=True)
app.add_typer(tolerance_app, name="tolerance")


@tolerance_app.command("iso1328")
@exits_cleanly_on_bad_input
def tolerance_iso1328(
    edition: str = typer.Option("1995", "--edition", help="1995 | 2013"),
    module: float = typer.Option(..., "--module", help="Module m [mm]."),
    diameter: float = typer.Option(..., "--diameter", help="Reference diameter d [mm]."),
    width: float = typer.Option(..., "--width", help="Face width b [mm]."),
    grade: int = typer.Option(..., "--grade", help="Grade (1995: 0-12) or class (2013: 1-11)."),
    as_json: bool = typer.Option(False, "--json", help="Shorthand for --format json."),
    fmt: Format = FORMAT_OPTION,
) -> None:
    """Gear tolerances f_pt, F_p, F_alpha, f_falpha, F_beta, F_r of one gear."""
    from rvbacklash.standards.iso1328 import iso1328_tolerances

    t = iso1328_tolerances(edition, module, diameter, width, grade)
    data = t.to_dict()

    def table() -> None:
        stdout.print(f"[bold]{t.standard}[/], grade {t.grade}: m = {module:g} mm, d = {diameter:g} mm, "
                     f"b = {width:g} mm ({t.note})")
        for k in ("fpt_um", "Fp_um", "Falpha_um", "ffalpha_um", "Fbeta_um", "Fr_um"):
            stdout.print(f"  {k:11s} {getattr(t, k):8.1f}")

    emit(Format.json if as_json else fmt, table, data, [data])


@tolerance_app.command("iso286")
@exits_cleanly_on_bad_input
def tolerance_iso286(
    size: float = typer.Option(..., "--size", help="Nominal size D [mm]."),
    grade: str = typer.Option(..., "--grade", help="IT1 .. IT12"),
    fit: Optional[str] = typer.Option(None, "--fit", help="A fit such as H7/g6."),
    as_json: bool = typer.Option(False, "--json", help="Shorthand for --format json."),
    fmt: Format = FORMAT_OPTION,
) -> None:
    """Standard tolerance IT and, optionally, the limits and clearance of a fit."""
    from rvbacklash.standards import iso286

    g = iso286.parse_it(grade)
    step = iso286.size_step_mm(size)
    data = {"standard": "ISO 286-1:2010", "size_mm": size, "grade": f"IT{g}", "size_step_mm": list(step),
            "IT_um": iso286.it_um(g, size)}
    if fit is not None:
        data["fit"] = iso286.fit(fit, size).to_dict()

    def table() -> None:
        stdout.print(f"[bold]ISO 286-1[/] IT{g} at {size:g} mm (step {step[0]:g}..{step[1]:g}): {data['IT_um']:g} um")
        if fit is not None:
            f = data["fit"]
            stdout.print(f"  fit {f['fit']}: hole {f['hole_lower_um']:+g}/{f['hole_upper_um']:+g} um, shaft "
                         f"{f['shaft_lower_um']:+g}/{f['shaft_upper_um']:+g} um, clearance {f['clearance_min_um']:g} .. "
                         f"{f['clearance_max_um']:g} um")

    row = {k: v for k, v in data.items() if k not in ("fit", "size_step_mm")} | (
        {f"fit_{k}": v for k, v in data["fit"].items()} if fit is not None else {})
    emit(Format.json if as_json else fmt, table, data, [row])


@app.command()
def schema() -> None:
    """Print the JSON schema of the design file."""
    sys.stdout.write(render_json(Design.model_json_schema()))


@app.command()
@exits_cleanly_on_bad_input
def examples(name: Optional[str] = typer.Argument(None, help="Print this example's TOML.")) -> None:
    """List the built-in example designs, or print one to start a design from."""
    if name is None:
        for n in available_examples():
            stdout.print(f"[bold]{n}[/]  {load_design(n).description}")
        return
    sys.stdout.write(example_text(name))


def main() -> None:
    app()


if __name__ == "__main__":
    main()
