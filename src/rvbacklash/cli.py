"""Command-line interface: a thin layer over the library.

Bad input of any kind ends with one line ``error: <field> = <value>: <allowed>`` on stderr
and exit code 2, before any output file is written.
"""

from __future__ import annotations

import contextlib
import functools
import json
import math
import sys
from pathlib import Path
from typing import Callable, Optional

import typer
from rich.console import Console
from rich.markup import escape

from rvbacklash import __version__
from rvbacklash.analysis.stackup import analyze as run_stackup
from rvbacklash.design.loading import available_examples, example_text, load_design
from rvbacklash.design.schema import Design
from rvbacklash.errors import InputError
from rvbacklash.report.files import check_writable, render_csv, render_json, write_files
from rvbacklash.report.tables import print_stackup

app = typer.Typer(
    add_completion=False,
    no_args_is_help=True,
    pretty_exceptions_enable=False,
    help="Design-stage backlash (lost motion) of RV reducers, after Sun et al. 2014.",
)
# Files and pipes get a wide, fixed layout (no wrapping of the tables); terminals their own width.
stdout = Console() if sys.stdout.isatty() else Console(width=160)

DESIGN_HELP = "TOML design file, or a built-in example name (see `rvbacklash examples`)."


def exits_cleanly_on_bad_input(fn: Callable) -> Callable:
    @functools.wraps(fn)
    def wrapper(*args, **kwargs):
        try:
            return fn(*args, **kwargs)
        except InputError as e:
            sys.stderr.write(f"error: {e}\n")
            raise typer.Exit(2) from None
    return wrapper


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
    quiet: bool = typer.Option(False, "--quiet", "-q", help="No tables on stdout."),
) -> None:
    """Stack-up and sensitivity of the linear model (Sun et al. 2014, Tables 2-3, Eq. (1)-(7))."""
    result = run_stackup(load_design(design))
    outputs = {}
    if json_out is not None:
        outputs["--json"] = (json_out, render_json(result.to_dict()))
    if csv_out is not None:
        outputs["--csv"] = (csv_out, render_csv(result.to_dict()["factors"]))
    write_files(outputs)
    if not quiet:
        print_stackup(result, stdout)
        for option, (path, _) in outputs.items():
            stdout.print(f"wrote {path} ({option[2:]})")


def parse_samples(text: str) -> int:
    """'10000000', '1e7' or '10_000_000' -> 10000000; anything not a whole number is an error."""
    try:
        value = float(text.replace("_", ""))
    except ValueError:
        raise InputError("--samples", text, "allowed: a whole number of samples >= 1") from None
    if not math.isfinite(value) or value != int(value):
        raise InputError("--samples", text, "allowed: a whole number of samples >= 1")
    return int(value)


@app.command()
@exits_cleanly_on_bad_input
def simulate(
    design: str = typer.Argument(..., help=DESIGN_HELP),
    samples: str = typer.Option("1000000", "--samples", "-n", help="Number of samples (e.g. 1e7)."),
    seed: int = typer.Option(0, "--seed", help="Seed (integer >= 0; 0 is valid); same seed, same numbers."),
    spec_arcmin: Optional[float] = typer.Option(None, "--spec-arcmin", help="Backlash spec (upper limit) [arcmin]."),
    method: str = typer.Option("default", "--method", help="default | box-muller | sobol | exact"),
    quantile: list[float] = typer.Option([], "--quantile", "-q", help="Extra quantile to report (0..1); repeatable."),
    workers: int = typer.Option(0, "--workers", help="Worker threads (0 = all cores); results do not depend on it."),
    json_out: Optional[Path] = typer.Option(None, "--json", help="Write the result as JSON."),
    quiet: bool = typer.Option(False, "--quiet", help="No summary on stdout."),
) -> None:
    """Monte-Carlo simulation of the output backlash, with confidence intervals and yield."""
    from rvbacklash.analysis.simulation import simulate as run_simulation
    from rvbacklash.report.simulation_tables import print_simulation

    n = parse_samples(samples) if method != "exact" else None
    if workers < 0:
        raise InputError("--workers", workers, "allowed: 0 (all cores) or a number of threads >= 1")
    d = load_design(design)
    if json_out is not None:
        check_writable("--json", json_out)
    with progress_bar(n) as progress:
        result = run_simulation(d, n, seed, method, spec_arcmin, tuple(quantile), workers or None,
                                progress=progress)
    outputs = {"--json": (json_out, render_json(result.to_dict()))} if json_out is not None else {}
    write_files(outputs)
    if not quiet:
        print_simulation(result, stdout)
        for option, (path, _) in outputs.items():
            stdout.print(f"wrote {path}")
    if result.partial:
        raise typer.Exit(130)


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


@app.command()
@exits_cleanly_on_bad_input
def compare(
    design: str = typer.Argument(..., help=DESIGN_HELP),
    scenario: list[str] = typer.Option([], "--scenario", help="NAME:key=grade,... (keys: involute, cycloid, crank, "
                                                             "all, edition, or a factor key); repeatable."),
    paper: bool = typer.Option(False, "--paper", help="Add the paper's Fig. 4 scenarios (a)-(d)."),
    samples: str = typer.Option("1000000", "--samples", "-n", help="Samples per scenario."),
    seed: int = typer.Option(0, "--seed", help="Seed (the same for every scenario)."),
    spec_arcmin: Optional[float] = typer.Option(None, "--spec-arcmin", help="Backlash spec [arcmin]."),
    method: str = typer.Option("default", "--method", help="default | box-muller | sobol | exact"),
    json_out: Optional[Path] = typer.Option(None, "--json", help="Write the scenario table as JSON."),
    plot: Optional[Path] = typer.Option(None, "--plot", help="Write an SVG overlay of the distributions."),
) -> None:
    """Compare precision-grade scenarios of one design (Sun et al. 2014, Fig. 4)."""
    from rvbacklash.analysis.scenarios import compare as run_compare
    from rvbacklash.analysis.scenarios import paper_scenarios, parse_scenario
    from rvbacklash.report.plots import scenario_overlay_svg

    n = parse_samples(samples) if method != "exact" else None
    d = load_design(design)
    chosen = [parse_scenario(text) for text in scenario]
    if paper:
        chosen = paper_scenarios(d) + chosen
    if not chosen:
        raise InputError("--scenario", None, "allowed: at least one --scenario NAME:OVERRIDES, or --paper")
    for option, path in (("--json", json_out), ("--plot", plot)):
        if path is not None:
            check_writable(option, path)
    results = run_compare(d, chosen, n, seed, method, spec_arcmin)
    outputs = {}
    if json_out is not None:
        outputs["--json"] = (json_out, render_json({"design": d.name, "spec_arcmin": spec_arcmin,
                                                    "scenarios": [r.to_dict() for r in results]}))
    if plot is not None:
        outputs["--plot"] = (plot, scenario_overlay_svg(results, spec_arcmin, f"{d.name}: precision-grade scenarios"))
    write_files(outputs)
    print_scenarios(results, spec_arcmin, stdout)
    for option, (path, _) in outputs.items():
        stdout.print(f"wrote {path}")


def print_scenarios(results, spec_arcmin, console) -> None:
    from rich.table import Table

    t = Table(title=escape("Scenarios: output backlash [arcmin]"), title_justify="left")
    for c in ["scenario", "factors changed", "mean", "sigma", "q 99.865 %", "yield"]:
        t.add_column(c, justify="left" if c == "scenario" else "right")
    for r in results:
        d = r.to_dict()
        y = d["yield"]
        ys = "-" if y is None else f"{y['fraction'] * 100:.3f} % [{y['ci95'][0] * 100:.3f}, {y['ci95'][1] * 100:.3f}]"
        t.add_row(r.name, str(r.tightened), f"{d['mean_arcmin']:.4f}", f"{d['sigma_arcmin']:.4f}",
                  f"{d['q99865_arcmin']:.4f}", ys)
    console.print(t)


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
    as_json: bool = typer.Option(False, "--json", help="Print JSON instead of a table."),
) -> None:
    """Gear tolerances f_pt, F_p, F_alpha, f_falpha, F_beta, F_r of one gear."""
    from rvbacklash.standards.iso1328 import iso1328_tolerances

    t = iso1328_tolerances(edition, module, diameter, width, grade)
    if as_json:
        sys.stdout.write(render_json(t.to_dict()))
        return
    stdout.print(f"[bold]{t.standard}[/], grade {t.grade}: m = {module:g} mm, d = {diameter:g} mm, b = {width:g} mm "
                 f"({t.note})")
    for k in ("fpt_um", "Fp_um", "Falpha_um", "ffalpha_um", "Fbeta_um", "Fr_um"):
        stdout.print(f"  {k:11s} {getattr(t, k):8.1f}")


@tolerance_app.command("iso286")
@exits_cleanly_on_bad_input
def tolerance_iso286(
    size: float = typer.Option(..., "--size", help="Nominal size D [mm]."),
    grade: str = typer.Option(..., "--grade", help="IT1 .. IT12"),
    fit: Optional[str] = typer.Option(None, "--fit", help="A fit such as H7/g6."),
    as_json: bool = typer.Option(False, "--json", help="Print JSON instead of a table."),
) -> None:
    """Standard tolerance IT and, optionally, the limits and clearance of a fit."""
    from rvbacklash.standards import iso286

    g = iso286.parse_it(grade)
    out = {"standard": "ISO 286-1:2010", "size_mm": size, "grade": f"IT{g}",
           "size_step_mm": list(iso286.size_step_mm(size)), "IT_um": iso286.it_um(g, size)}
    if fit is not None:
        out["fit"] = iso286.fit(fit, size).to_dict()
    if as_json:
        sys.stdout.write(render_json(out))
        return
    stdout.print(f"[bold]ISO 286-1[/] IT{g} at {size:g} mm (step {out['size_step_mm'][0]:g}..{out['size_step_mm'][1]:g}): "
                 f"{out['IT_um']:g} um")
    if fit is not None:
        f = out["fit"]
        stdout.print(f"  fit {f['fit']}: hole {f['hole_lower_um']:+g}/{f['hole_upper_um']:+g} um, shaft "
                     f"{f['shaft_lower_um']:+g}/{f['shaft_upper_um']:+g} um, clearance {f['clearance_min_um']:g} .. "
                     f"{f['clearance_max_um']:g} um")


@app.command()
def schema() -> None:
    """Print the JSON schema of the design file."""
    sys.stdout.write(json.dumps(Design.model_json_schema(), indent=2) + "\n")


@app.command()
@exits_cleanly_on_bad_input
def examples(name: Optional[str] = typer.Argument(None, help="Print this example's TOML.")) -> None:
    """List the built-in example designs, or print one to start a design from."""
    if name is None:
        for n in available_examples():
            d = load_design(n)
            stdout.print(f"[bold]{n}[/]  {d.description}")
        return
    sys.stdout.write(example_text(name))


def main() -> None:
    app()


if __name__ == "__main__":
    main()
