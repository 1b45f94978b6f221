"""The sweep commands: ``sweep`` runs a SWEEP.toml point by point on a scheduler (in process, a
local cluster, a Dask cluster) into a results directory that a re-run resumes; ``sweep-plot``
draws a figure of a results directory (docs/sweeps.md)."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Callable, Optional

import typer

from rvbacklash.cli.app import app
from rvbacklash.cli.common import FORCE_OPTION, FORMAT_OPTION, QUIET_OPTION, Format, command, stdout_console
from rvbacklash.errors import InputError

SCHEDULER_OPTION = typer.Option(
    None, "--scheduler", metavar="inline|local|ADDRESS",
    help="Where the points run: inline (this process), local (a local Dask cluster of processes) or the address of "
         "a running Dask scheduler (tcp://host:8786). Default: local for more than 4 points to run on more than one "
         "core, else inline.")
SWEEP_WORKERS_OPTION = typer.Option(
    0, "--workers", help="local: worker processes (0 = one per core); inline: threads of each point's run (0 = all "
                         "cores). Results do not depend on it.")
OUT_OPTION = typer.Option(None, "--out", metavar="DIR",
                          help="Results directory (default: ./<sweep name>); running the same sweep into it again "
                               "skips the finished points.")
PLOT_FILE = "plot.svg"
HTML_FILE = "sweep.html"


def _file_error(e: InputError, origin: str) -> InputError:
    """An error about the sweep file's content names the file: a field such as ``samples`` is not
    the --samples flag of other commands."""
    if e.field == "sweep":
        return e
    return e.renamed(f"{origin}: {e.field}")


def _rate_column():
    from rich.progress import ProgressColumn
    from rich.text import Text

    class Rate(ProgressColumn):
        def render(self, task) -> Text:
            speed = task.finished_speed or task.speed
            if not speed:
                return Text("-- s/point", style="progress.data.speed")
            return Text(f"{speed:.2f} points/s" if speed >= 1 else f"{1 / speed:.1f} s/point",
                        style="progress.data.speed")

    return Rate()


class _Bar:
    """Progress of the points on stderr when it is a terminal: done/total, rate, elapsed, ETA."""

    def __init__(self, enabled: bool, note: str):
        self.enabled = enabled and sys.stderr.isatty()
        self.note = note
        self.bar = None
        self.task = None

    def __enter__(self) -> Callable[[int, int], None] | None:
        if not self.enabled:
            return None
        from rich.console import Console
        from rich.progress import BarColumn, MofNCompleteColumn, Progress, TimeElapsedColumn, TimeRemainingColumn

        self.bar = Progress("[progress.description]{task.description}", BarColumn(), MofNCompleteColumn(),
                            _rate_column(), TimeElapsedColumn(), TimeRemainingColumn(),
                            console=Console(stderr=True), transient=True)
        self.bar.__enter__()
        return self.update

    def update(self, done: int, total: int) -> None:
        if self.task is None:  # start at the points already finished: the rate counts this run's only
            resumed = f" ({done} already done)" if done else ""
            self.task = self.bar.add_task(f"{self.note}{resumed}", total=total, completed=done)
        else:
            self.bar.update(self.task, completed=done)

    def __exit__(self, *exc) -> None:
        if self.bar is not None:
            self.bar.__exit__(*exc)


def _write_pictures(result, out: Path) -> list[Path]:
    """plot.svg (the default figure) and sweep.html in the results directory (its own files)."""
    from rvbacklash.report.files import atomic_write
    from rvbacklash.report.sweep import default_figures, render_sweep_html

    if not result.table:
        return []
    figures = default_figures(result)
    written = []
    if figures:
        atomic_write("--out", out / PLOT_FILE, figures[0][1])
        written.append(out / PLOT_FILE)
    atomic_write("--out", out / HTML_FILE, render_sweep_html(result, figures))
    written.append(out / HTML_FILE)
    return written


def print_sweep(result, console, top: int = 10) -> None:
    from rich.markup import escape
    from rich.table import Table

    from rvbacklash.report.sweep import format_value, label_of

    for line in result.summary():
        console.print(line, highlight=False, markup=False)
    fig = result.default_figure()
    rows = [r for r in result.table if isinstance(r.get(fig), (int, float))]
    sign = -1 if result.maximise(fig) else 1
    rows = sorted(rows, key=lambda r: (sign * r[fig], r["point"]))[:top]
    if not rows:
        return
    primary = result.outputs[0]
    extra = [c for c in (f"{primary}_mean", f"{primary}_q99865", "preload_fraction")
             if c != fig and c in result.columns]
    t = Table(title=escape(f"best {len(rows)} of {result.points_done} points by {fig}"), title_justify="left")
    t.add_column("point", justify="right")
    for p in result.parameters:
        t.add_column(escape(label_of(result, p)), justify="right")
    for c in (fig, *extra):
        t.add_column(escape(c), justify="right")
    for r in rows:
        t.add_row(str(r["point"]), *(escape(format_value(p, r.get(p))) for p in result.parameters),
                  *(escape(format_value(c, r.get(c))) for c in (fig, *extra)))
    console.print(t)


@app.command("sweep")
@command
def sweep(
    sweep_file: str = typer.Argument(..., metavar="SWEEP",
                                     help="SWEEP.toml file, or a built-in example sweep (see `rvbacklash examples`)."),
    scheduler: Optional[str] = SCHEDULER_OPTION,
    workers: int = SWEEP_WORKERS_OPTION,
    out: Optional[Path] = OUT_OPTION,
    fmt: Format = FORMAT_OPTION,
    force: bool = typer.Option(False, "--force", help="Start over in --out: its finished points are discarded (also "
                                                      "when it holds another sweep)."),
    quiet: bool = QUIET_OPTION,
) -> None:
    """Run a design sweep: one Monte-Carlo run per point, written point by point to --out
    (results.parquet, results.csv), with a heat map (plot.svg) and a page (sweep.html). A re-run
    resumes; Ctrl-C keeps the finished points (docs/sweeps.md)."""
    import rvbacklash.api as api
    from rvbacklash.analysis.sweep import plan_sweep
    from rvbacklash.interrupt import mark_progress
    from rvbacklash.report.files import render_csv, render_json

    if workers < 0:
        raise InputError("workers", workers, "allowed: 0 (one per core) or a number of workers >= 1")
    try:
        plan = plan_sweep(sweep_file)
    except InputError as e:
        raise _file_error(e, sweep_file) from None
    out_dir = out if out is not None else Path(plan.spec.name)
    # a Ctrl-C in the sweep is always a stop request: its results directory and worker processes are
    # closed in order, the finished points kept; they are on disk, so a second Ctrl-C stops at once
    # (rvbacklash.interrupt)
    mark_progress(on_disk=True)
    note = "sweep points" + (" (first contact-model runs compile kernels)" if plan.spec.model == "contact" else "")
    try:
        with _Bar(True, note) as progress:
            result = api.sweep(plan, out=out_dir, scheduler=scheduler, workers=workers or None, force=force,
                               progress=progress)
    except KeyboardInterrupt:
        sys.stderr.write(f"interrupted: the finished points are kept in {out_dir}; run the same command again to "
                         f"resume\n")
        raise typer.Exit(130) from None
    written = _write_pictures(result, out_dir)
    if not quiet:
        if fmt is Format.json:
            sys.stdout.write(render_json(result.to_dict()))
        elif fmt is Format.csv:
            sys.stdout.write(render_csv(result.rows()))
        else:
            console = stdout_console()
            print_sweep(result, console)
            ran = result.points_done - result.skipped
            sys.stdout.write(f"{ran} points run ({result.scheduler}), {result.skipped} found finished in {out_dir}\n")
            for name in ("results.parquet", "results.csv"):
                sys.stdout.write(f"wrote {out_dir / name}\n")
            for p in written:
                sys.stdout.write(f"wrote {p}\n")
    if result.partial:
        sys.stderr.write(f"interrupted: {result.points_done} of {result.points_total} points finished, kept in "
                         f"{out_dir}; run the same command again to resume\n")
        raise typer.Exit(130)


@app.command("sweep-plot")
@command
def sweep_plot(
    out: Path = typer.Argument(..., metavar="DIR", help="Results directory of a sweep (its --out)."),
    x: Optional[str] = typer.Option(None, "--x", metavar="PATH", help="Parameter on the x axis (path or label); "
                                                                      "default: the first."),
    y: Optional[str] = typer.Option(None, "--y", metavar="PATH", help="Parameter on the y axis of a heat map; "
                                                                      "default: the second."),
    figure: Optional[str] = typer.Option(None, "--figure", metavar="COLUMN",
                                         help="Column to draw (e.g. joint_yield, backlash_q99865); default: the "
                                              "joint yield, else the primary output's yield, else its 99.865 % "
                                              "quantile."),
    plot: Optional[str] = typer.Option(None, "--plot", metavar="FILE", help="Write the figure as SVG to FILE "
                                                                             "(default: DIR/plot.svg)."),
    html: Optional[str] = typer.Option(None, "--html", metavar="FILE",
                                        help="Also write the sweep's HTML page with this figure first to FILE."),
    force: bool = FORCE_OPTION,
    quiet: bool = QUIET_OPTION,
) -> None:
    """Draw a sweep's results: a heat map of a figure over two parameters, or a line over one."""
    from rvbacklash.analysis.sweep import load_sweep
    from rvbacklash.report.files import check_distinct, check_writable, output_path, write_files
    from rvbacklash.report.sweep import default_figures, defaults, plot_svg, render_sweep_html

    try:
        result = load_sweep(out)
    except InputError as e:
        raise e.renamed("DIR") from None  # the argument, not --out
    x_path, y_path, fig = defaults(result, x, y, figure)
    target = output_path("--plot", plot) if plot is not None else out / PLOT_FILE
    files = {"--plot": target} | ({"--html": output_path("--html", html)} if html is not None else {})
    check_distinct(files)
    for option, path in files.items():
        check_writable(option, path, force or (option == "--plot" and plot is None))
    svg = plot_svg(result, x_path, y_path, fig)
    contents: dict[str, tuple[Path, str]] = {"--plot": (target, svg)}
    if html is not None:
        rest = [f for f in default_figures(result) if not f[0].startswith(fig + " ")]
        contents["--html"] = (files["--html"],
                              render_sweep_html(result, [(f"{fig} over {x_path}, {y_path}", svg), *rest]))
    write_files(contents, True)
    if not quiet:
        best = result.best(fig)
        for p, _ in contents.values():
            sys.stdout.write(f"wrote {p}\n")
        if best is not None:
            where = ", ".join(f"{q} = {best.get(q)!r}" for q in result.parameters)
            sys.stdout.write(f"best {fig} = {best[fig]:.6g} at point {best['point']} ({where})\n")
