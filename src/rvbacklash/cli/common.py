"""What every command shares: the same flags with the same meaning, one-line errors that name
flags (not Python parameters), file outputs checked before any work, progress on a terminal."""

from __future__ import annotations

import contextlib
import functools
import math
import sys
from enum import Enum
from typing import Callable, Iterator, Optional

import typer

from rvbacklash.errors import InputError

DESIGN_HELP = "TOML design file, or a built-in example name (see `rvbacklash examples`)."

# Python parameter of the library -> the flag that sets it
FLAGS = {
    "samples": "--samples", "seed": "--seed", "method": "--method", "model": "--model",
    "spec_arcmin": "--spec-arcmin", "quantiles": "--quantile", "workers": "--workers",
    "crank_angle_deg": "--crank-angle-deg", "scenarios": "--scenario", "paper": "--paper", "measured": "--measured",
    "unit": "--unit", "error_model": "--error-model", "save_units": "--save-units",
    "module_mm": "--module", "diameter_mm": "--diameter", "width_mm": "--width", "grade": "--grade",
    "edition": "--edition", "size_mm": "--size", "fit": "--fit",
    "yield_target": "--yield", "output": "--output", "allocate_model": "--allocate-model",
    "allocate_samples": "--allocate-samples",
    "spec_lost_motion_arcmin": "--spec-lost-motion-arcmin", "spec_rigidity_nm_per_arcmin": "--spec-rigidity-nm-per-arcmin",
    "spec_preload_um": "--spec-preload-um", "sweep_dir": "--sweep",
    "points": "--points", "positions": "--positions", "load_direction": "--load-direction",
    "spec_te_arcsec": "--spec-te-arcsec",
    "rated_torque_nm": "--rated-torque-nm", "ratio": "--ratio", "bootstrap": "--bootstrap", "files": "FILE",
    "torque_unit": "--torque-unit", "angle_unit": "--angle-unit", "te_unit": "--te-unit", "time_unit": "--time-unit",
    "columns": "--columns", "format_profile": "--format-profile", "decimal": "--decimal",
    "duty_cycle": "--duty-cycle", "angles": "--angles", "life_method": "--life-method",
    "spec_life_h": "--spec-life-h", "spec_rated_torque_nm": "--spec-rated-torque-nm",
    "temperature_c": "--temperature", "output_speed_rpm": "--output-speed", "units": "--units",
    "spec_min_efficiency": "--spec-min-efficiency",
    "hours": "--hours", "step_fraction": "--step-fraction", "unit_wear": "--unit-wear",
    "spec_accuracy_life_h": "--spec-accuracy-life-h", "sensitivity_samples": "--sensitivity-samples",
    "out": "--out", "scheduler": "--scheduler", "x_parameter": "--x", "y_parameter": "--y", "figure": "--figure",
}


def flag_of(field: str) -> str:
    return FLAGS.get(field, field)


class Format(str, Enum):
    table = "table"
    json = "json"
    csv = "csv"


# --- the shared options: one meaning everywhere -------------------------------------------------

def json_option(what: str = "the full result"):
    return typer.Option(None, "--json", help=f"Write {what} as JSON to FILE ('-': standard output).",
                        metavar="FILE")


def csv_option(what: str = "the table"):
    return typer.Option(None, "--csv", help=f"Write {what} as CSV to FILE ('-': standard output).", metavar="FILE")


FORMAT_OPTION = typer.Option(Format.table, "--format", help="What to print on standard output: table, json or csv.")
FORCE_OPTION = typer.Option(False, "--force", help="Replace existing output files.")
QUIET_OPTION = typer.Option(False, "--quiet", "-q", help="Print nothing on standard output (files are still written).")
SAMPLES_OPTION = typer.Option("1000000", "--samples", "-n", help="Number of Monte-Carlo samples (e.g. 1e6).")
SEED_OPTION = typer.Option(0, "--seed", help="Seed (an integer >= 0; 0 is valid): same seed, same numbers.")
SPEC_OPTION = typer.Option(None, "--spec-arcmin", help="Spec (upper limit) of the model's primary output: "
                           "backlash; lost motion for the elastic model [arcmin].")
SPEC_LOST_MOTION_OPTION = typer.Option(None, "--spec-lost-motion-arcmin",
                                       help="Spec of the lost motion (upper limit) [arcmin]; --model elastic.")
SPEC_RIGIDITY_OPTION = typer.Option(None, "--spec-rigidity-nm-per-arcmin",
                                    help="Spec of the torsional rigidity (lower limit) [N m/arcmin]; --model elastic.")
SPEC_PRELOAD_OPTION = typer.Option(None, "--spec-preload-um",
                                   help="Spec of the cycloid stage's preload (upper limit; a unit with a free stage "
                                        "meets it) [um]; --model contact or elastic.")
METHOD_OPTION = typer.Option("default", "--method", help="default | box-muller | sobol | exact (linear model only).")
MODEL_OPTION = typer.Option("linear", "--model", help="linear (Eq. (2)) | contact (exact cycloid-pin contact, per-part "
                                                      "errors; docs/contact.md) | elastic (the test bench's hysteresis "
                                                      "loop: lost motion, backlash, rigidity; docs/elastic.md) | "
                                                      "transmission (the contact model's units turned through one output "
                                                      "revolution: TE peak-to-peak, backlash, largest lost motion; "
                                                      "docs/transmission-error.md).")
ERROR_MODEL_OPTION = typer.Option(None, "--error-model", help="contact/elastic models: long_wave (harmonics plus "
                                  "a per-element part, the default) | independent (every element on its own, the "
                                  "pessimistic bound); default: the design's [contact] error_model.")
WORKERS_OPTION = typer.Option(0, "--workers", help="Worker threads (0 = all cores); results do not depend on it.")


def command(fn: Callable) -> Callable:
    """Run a command: bad input -> one line naming the flag, exit 2; Ctrl-C -> exit 130."""

    @functools.wraps(fn)
    def wrapper(*args, **kwargs):
        try:
            return fn(*args, **kwargs)
        except InputError as e:
            sys.stderr.write(f"error: {e.renamed(flag_of(e.field))}\n")
            raise typer.Exit(2) from None
        except KeyboardInterrupt:
            sys.stderr.write("interrupted: nothing was written\n")
            raise typer.Exit(130) from None
    return wrapper


def parse_samples(text: str) -> int:
    """'10000000', '1e7' or '10_000_000' -> 10000000; anything not a whole number is an error."""
    try:
        value = float(text.replace("_", ""))
    except ValueError:
        raise InputError("samples", text, "allowed: a whole number of samples >= 1") from None
    if not math.isfinite(value) or value != int(value):
        raise InputError("samples", text, "allowed: a whole number of samples >= 1")
    return int(value)


def workers_or_none(workers: int) -> Optional[int]:
    if workers < 0:
        raise InputError("workers", workers, "allowed: 0 (all cores) or a number of threads >= 1")
    return workers or None


class Outputs:
    """The files and the standard output of one command, checked before any work is done. The
    paths come as the text typed (a trailing slash, which ``Path`` drops, names a directory)."""

    def __init__(self, fmt: Format, force: bool, quiet: bool, **paths: Optional[str]):
        from rvbacklash.report.files import check_distinct, check_writable, is_stdout, output_path

        self.fmt, self.force, self.quiet = fmt, force, quiet
        self.paths = {option: output_path(option, text) for option, text in
                      ((f"--{name.replace('_', '-')}", text) for name, text in paths.items()) if text is not None}
        check_distinct(self.paths)
        to_stdout = [o for o, p in self.paths.items() if is_stdout(p)]
        if to_stdout and fmt is not Format.table:
            raise InputError("--format", fmt.value, f"{to_stdout[0]} - already writes to standard output; allowed: "
                                                    f"one of them")
        self.stdout_taken = bool(to_stdout)
        for option, path in self.paths.items():
            check_writable(option, path, force)

    def finish(self, renders: dict[str, Callable[[], str | bytes]], table: Callable[[], None], data, rows) -> None:
        """Render every requested file, write them all (or none), then print the result."""
        from rvbacklash.report.files import is_stdout, render_csv, render_json, write_files

        contents = {o: (p, renders[o]()) for o, p in self.paths.items()}
        write_files(contents, self.force)
        if self.quiet or self.stdout_taken:
            return
        if self.fmt is Format.json:
            sys.stdout.write(render_json(data))
        elif self.fmt is Format.csv:
            sys.stdout.write(render_csv(rows))
        else:
            table()
            for p in (p for p in self.paths.values() if not is_stdout(p)):
                sys.stdout.write(f"wrote {p}\n")


def stdout_console():
    from rich.console import Console

    # files and pipes get a wide, fixed layout (no wrapping of the tables); terminals their own width
    return Console() if sys.stdout.isatty() else Console(width=160)


@contextlib.contextmanager
def progress_bar(total: int | None, what: str = "sampling", note: str | None = None,
                 enabled: bool = True) -> Iterator[Callable[[int], None]]:
    """The progress callback of a long run: a rich progress bar on stderr when stderr is a
    terminal. On any stream it tells ``rvbacklash.interrupt`` when the first work is finished:
    from then on a Ctrl-C stops the run and keeps that work (partial results); before, there is
    nothing to keep and a Ctrl-C ends the command at once. ``note`` is shown until the first step
    finishes (e.g. a one-time compilation of kernels)."""
    from rvbacklash.interrupt import mark_progress

    def keep(done: int) -> None:
        if done > 0:
            mark_progress()

    if not enabled or total is None or not sys.stderr.isatty():
        yield keep
        return
    from rich.console import Console
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TimeElapsedColumn, TimeRemainingColumn

    with Progress("[progress.description]{task.description}", BarColumn(), MofNCompleteColumn(),
                  TimeElapsedColumn(), TimeRemainingColumn(), console=Console(stderr=True), transient=True) as bar:
        task = bar.add_task(note or what, total=total)
        started = False

        def update(done: int) -> None:
            nonlocal started
            keep(done)
            if not started:
                bar.update(task, description=what)
                started = True
            bar.update(task, completed=done)

        yield update


CONTACT_NOTE = "starting (the first contact-model run compiles its kernels, ~15 s, once)"
