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
