"""Every benchmark in bench/ runs at a tiny size (issue 18: bench_elastic.py crashed unnoticed
when UnitBatch gained preload_um, because nothing ran it). Only that it runs and prints its
figures is checked, never a time.

Most run their ``main()`` in this process, as ``python bench/X.py --tiny`` would (sys.argv, the
bench folder first on sys.path): a fresh interpreter per bench cost an import of the package and a
load of its kernels each, 1-4 s of CPU apiece. Run as scripts, as ``make bench`` runs them (AS_SCRIPT):
the benches of fresh processes (start-up, first run: they time new interpreters), bench_selection
(its own numba kernels are cached under its module's name, ``__main__`` as a script) and
bench_sweep (dask's worker processes unpickle its functions: by value from ``__main__``, by a name
they cannot import otherwise)."""

from __future__ import annotations

import importlib.util
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

BENCH = Path(__file__).resolve().parents[1] / "bench"
# The order the benches run in (one xdist worker runs this whole file, first: conftest.SLOW_FIRST).
# With an empty numba cache (CI), a bench's time is mostly the compilation of the kernels it
# calls, and two processes that need a kernel not yet in the cache both compile it. Meanwhile the
# other worker runs tests/cli/test_cli_interrupt.py, whose subprocesses compile the linear and the
# elastic kernels, then tests/report/test_html.py (every model's report, the transmission model's
# kernels). So the contact and the transmission kernels are compiled here first, then the benches
# of the linear and contact models run; those of the elastic model come after, when its kernels
# are in the cache (measured, empty cache: the elastic kernels were compiled twice at the same
# time, ~15 s of CPU, and the transmission ones twice, ~14 s). Only the order changes: every
# bench still runs, with the same checks.
COMPILE_FIRST = ("bench_contact", "bench_te", "bench_te_convergence", "bench_montecarlo", "bench_allocation")
BENCHES = sorted(BENCH.glob("bench_*.py"),
                 key=lambda p: (COMPILE_FIRST.index(p.stem) if p.stem in COMPILE_FIRST else len(COMPILE_FIRST), p.stem))
AS_SCRIPT = {"bench_first_run", "bench_startup", "bench_selection", "bench_sweep"}
ALL_ROWS = ("contact model production run", "elastic model production run", "`rvbacklash sensitivity",
            "`rvbacklash allocate", "linear engine (sun2014", "linear engine / numpy generation")


def test_the_benches_are_found():
    assert len(BENCHES) >= 6


def _run_in_process(script: Path, monkeypatch, capsys) -> str:
    """``python script --tiny`` in this process: its stdout. A bench that ends the process
    (``os._exit``, bench_app_stop when a job runs on for minutes) fails the test instead."""

    def no_exit(code):
        raise AssertionError(f"{script.name} called os._exit({code})")

    monkeypatch.syspath_prepend(str(BENCH))
    monkeypatch.setattr(sys, "argv", [str(script), "--tiny"])
    monkeypatch.setattr(os, "_exit", no_exit)
    spec = importlib.util.spec_from_file_location(f"_tiny_{script.stem}", script)
    module = importlib.util.module_from_spec(spec)
    monkeypatch.setitem(sys.modules, spec.name, module)  # dataclasses look their module up
    spec.loader.exec_module(module)
    capsys.readouterr()
    try:
        module.main()
    except SystemExit as e:
        assert e.code in (None, 0), (e.code, capsys.readouterr().err[-3000:])
    return capsys.readouterr().out


@pytest.mark.parametrize("script", BENCHES, ids=lambda p: p.stem)
def test_bench_runs_at_a_tiny_size_and_prints_figures(script, monkeypatch, capsys):
    if script.stem in AS_SCRIPT:
        # the timeout guards against a hang, it is no time limit: a cold compile on a loaded machine
        # took over 300 s (a helper's run at load 10-14)
        p = subprocess.run([sys.executable, str(script), "--tiny"], capture_output=True, text=True, timeout=1800)
        assert p.returncode == 0, p.stderr[-3000:]
        stdout = p.stdout
    else:
        stdout = _run_in_process(script, monkeypatch, capsys)
    figures = [line for line in stdout.splitlines() if re.search(r"\d", line)]
    assert len(figures) >= 2, stdout
    if script.stem == "bench_all":  # `make bench`: every row of the table, judged
        for row in ALL_ROWS:
            line = next((x for x in stdout.splitlines() if x.startswith(row)), None)
            assert line is not None and any(w in line.split() for w in ("pass", "FAIL")), (row, stdout)
            assert "FAILED" not in line.split(), (row, line)  # its command no longer runs


def test_the_benches_run_as_scripts_too():
    """The benches run in process above call the ``main()`` that ``python bench/X.py`` calls: each
    script ends in that call under ``if __name__ == "__main__"`` (``make bench`` runs them so)."""
    for script in BENCHES:
        text = script.read_text()
        assert re.search(r'^if __name__ == "__main__":\n    main\(', text, re.M), script.name


def test_a_bench_row_whose_command_fails_says_failed_not_a_time(monkeypatch):
    """Regression (issue 35): `make bench` timed the elastic allocation's refusal ("no design
    confirmed", exit 2) as if it were the allocation. A failing command gives no time: FAILED and
    its message."""
    monkeypatch.syspath_prepend(str(BENCH))
    import bench_all

    row = bench_all.command_row(["simulate", "rv80e", "--seed", "-1"], 30.0, skip=False)
    assert (row.value, row.verdict) == (None, "FAILED") and row.note.startswith("exit 2: error: --seed")
    assert "FAILED" in bench_all.table([row]).splitlines()[-1]
