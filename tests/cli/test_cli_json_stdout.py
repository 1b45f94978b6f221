"""`--format json` writes one JSON document to standard output and nothing else, for every
command that has it (issue 36 item 9): checked in a fresh interpreter, where anything a compiled
library prints to file descriptor 1 (past ``sys.stdout``) would show."""

from __future__ import annotations

import inspect
import json

import pytest

import rvbacklash as rb
from helpers import run_cli, run_cli_process
from rvbacklash.analysis.bench_synthetic import model_loop_samples, write_loop_csv
from rvbacklash.design.loading import example_text

# the reproducer of issue 36 item 9: a per-group cost makes HiGHS find an integer solution of the
# presolved MILP that it repairs, and print "HighsMipSolverData::transformNewIntegerFeasibleSolution
# tmpSolver.run();" on fd 1
PINS_COST = "\n[costs.groups.pins]\nprecision_cost = 20.0\n"

SWEEP = """
design = "rv80e"
model = "linear"
samples = 2000
seed = 2
spec_arcmin = 2.0

[[parameters]]
path = "second_stage.equidistance_modification_um"
start = 0
stop = 4
count = 2
"""


@pytest.fixture(scope="module")
def files(tmp_path_factory, rv80e):
    d = tmp_path_factory.mktemp("json-stdout")
    (d / "costs.toml").write_text(example_text("rv80e") + PINS_COST)
    (d / "sweep.toml").write_text(SWEEP)
    t, q, a = model_loop_samples(rb.prepare(rv80e), cycles=1, samples_per_branch=150, noise_arcmin=0.01, seed=3)
    write_loop_csv(d / "loop.csv", t, q, a)
    assert run_cli("assemble", "rv80e", "--generate", "3", "--seed", "1", "--units", d / "batch.toml",
                   "--parts", d / "parts.csv").returncode == 0
    return d


def invocations(d) -> dict[str, list]:
    """Every command with --format, and a cheap invocation of it."""
    return {
        "analyze": ["analyze", "sun2014"],
        "simulate": ["simulate", "sun2014", "-n", "2000"],
        "compare": ["compare", "rv80e", "--scenario", "x:all=5", "-n", "2000"],
        "report": ["report", "sun2014", "-n", "2000", "-o", d / "report.html", "--force"],
        "contact": ["contact", "rv80e"],
        "sensitivity": ["sensitivity", "sun2014"],
        "allocate": ["allocate", d / "costs.toml", "--spec-arcmin", "3", "--yield", "0.99"],
        "hysteresis": ["hysteresis", "rv80e", "--points", "5"],
        "transmission-error": ["transmission-error", "rv80e"],
        "capacity": ["capacity", "rv80e", "--angles", "8"],
        "bench": ["bench", d / "loop.csv"],
        "calibrate": ["calibrate", "rv80e", "--bench", d / "loop.csv", "-n", "0"],
        "sweep": ["sweep", d / "sweep.toml", "--out", d / "sweep-out", "--scheduler", "inline", "--force"],
        "efficiency": ["efficiency", "rv80e", "--angles", "4"],
        "assemble": ["assemble", "rv80e", "--units", d / "batch.toml", "--parts", d / "parts.csv"],
        "service-life": ["service-life", "rv80e", "--duty-cycle", "robot-joint", "--hours", "0,100", "-n", "20",
                         "--angles", "6"],
    }


def commands_with_format() -> set[str]:
    from rvbacklash.cli.app import app
    import rvbacklash.cli.entry  # noqa: F401  (registers every command)

    out = set()
    for c in app.registered_commands:
        if "fmt" in inspect.signature(c.callback).parameters:
            out.add(c.name or c.callback.__name__.replace("_", "-"))
    return out


def test_every_command_with_format_is_covered(tmp_path):
    assert commands_with_format() == set(invocations(tmp_path))


def test_json_stdout_parses_for_every_command(files, capfd):
    """The whole of stdout is one JSON document (json.loads of all of it), exit 0, and nothing
    reaches file descriptor 1 past ``sys.stdout`` (capfd, after the C library's buffers are
    flushed). In this interpreter, to spare a start-up per command; the allocate reproducer runs
    in a fresh one below."""
    import ctypes

    for name, args in invocations(files).items():
        p = run_cli(*args, "--format", "json")
        ctypes.CDLL(None).fflush(None)
        leaked = capfd.readouterr().out
        assert p.returncode == 0, (name, p.stderr[-2000:])
        assert leaked == "", f"{name}: written to fd 1 past sys.stdout: {leaked[:300]!r}"
        try:
            json.loads(p.stdout)
        except json.JSONDecodeError as e:
            pytest.fail(f"{name}: stdout is not one JSON document ({e}); it starts {p.stdout[:300]!r}")


def test_allocate_json_stdout_is_clean_with_a_group_cost_also_quiet(files):
    """The issue's reproducer: the MILP solver's debug lines never reach stdout."""
    args = ["allocate", files / "costs.toml", "--spec-arcmin", "3", "--yield", "0.99", "--format", "json"]
    p = run_cli_process(*args)
    assert p.returncode == 0, p.stderr
    assert "Highs" not in p.stdout
    assert json.loads(p.stdout)["cost"] > 0
    q = run_cli_process(*args, "-q")
    assert q.returncode == 0 and q.stdout == "", q.stdout[:300]


def test_the_solver_silencer_restores_stdout_and_is_reentrant_across_threads(capfd):
    """fd 1 is the same file after the solves, also when threads solve at once (the workbench)."""
    import os
    import threading

    from rvbacklash.analysis.allocation.milp import solver_output_silenced

    before = os.fstat(1)

    def solve():
        for _ in range(50):
            with solver_output_silenced():
                os.write(1, b"solver noise\n")

    threads = [threading.Thread(target=solve) for _ in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    after = os.fstat(1)
    assert (before.st_dev, before.st_ino) == (after.st_dev, after.st_ino)
    os.write(1, b"after\n")
    out = capfd.readouterr().out
    assert "solver noise" not in out and "after" in out
