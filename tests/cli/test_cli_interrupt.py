"""Ctrl-C in every long command, whatever phase it lands in: the kernels loading, sampling, writing
the partial results (a second press) — exit 130, partial results marked, no traceback."""

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

import rvbacklash
from helpers import interrupt_on_progress


def test_ctrl_c_in_simulate_keeps_what_was_sampled(tmp_path):
    out = tmp_path / "s.json"
    code, tty = interrupt_on_progress(["simulate", "sun2014", "--samples", "1e10", "--seed", "1", "--json", out],
                                         tmp_path)
    assert code == 130 and "Traceback" not in tty
    d = json.loads(out.read_text())
    o = d["outputs"]["backlash"]
    assert d["partial"] is True and 0 < d["samples_done"] < 10 ** 10
    h = o["histogram"]
    assert sum(h["counts"]) + h["underflow"] + h["overflow"] == d["samples_done"] == o["samples"]


def test_ctrl_c_in_compare_stops_every_scenario(tmp_path):
    """Regression (issue 9): compare ran the other scenarios, exited 0 and claimed every sample."""
    out = tmp_path / "c.json"
    code, tty = interrupt_on_progress(["compare", "rv80e", "--paper", "-n", "1e10", "--json", out], tmp_path)
    assert code == 130 and "Traceback" not in tty
    d = json.loads(out.read_text())
    assert d["partial"] is True and len(d["scenarios"]) == 1 and len(d["scenarios_requested"]) == 4
    assert d["scenarios"][0]["partial"] and d["scenarios"][0]["samples_done"] < 10 ** 10


def test_ctrl_c_in_report_marks_every_output(tmp_path):
    """Regression (issue 9): report exited 0 with no notice and a Run table claiming 1e9 samples."""
    html, js, csv = tmp_path / "r.html", tmp_path / "r.json", tmp_path / "r.csv"
    code, _ = interrupt_on_progress(["report", "rv80e", "--paper", "-n", "1e10", "-o", html, "--json", js,
                                        "--csv", csv], tmp_path)
    assert code == 130
    page = html.read_text()
    assert 'id="partial-banner"' in page and "PARTIAL RESULTS" in page
    d = json.loads(js.read_text())
    assert d["metadata"]["partial"] is True and d["metadata"]["samples_done"] < d["metadata"]["samples"]
    assert d["comparison"]["partial"] is True and d["comparison"]["scenarios"] == []
    assert "partial" in d["warnings"][-1] or "interrupted" in d["warnings"][-1]
    lines = csv.read_text().splitlines()  # the key numbers, each row marked
    assert lines[0] == "key,value,partial" and len(lines) > 5 and all(x.endswith(",True") for x in lines[1:])


@pytest.mark.parametrize("again_after", [0.05, 0.35])
def test_a_second_ctrl_c_does_not_break_writing_the_partial_results(tmp_path, again_after):
    """Regression: a second Ctrl-C 0.3-0.4 s after the first landed in a lazy `from scipy import
    stats` of the finishing code (NameError: name '_ndimage_api' is not defined), exit 1, nothing
    written. Once a stop is requested, further presses are ignored until the partial results are
    written; the CSV is marked partial too (it was not)."""
    out, csv_out = tmp_path / "out.json", tmp_path / "out.csv"
    code, tty = interrupt_on_progress(["simulate", "rv80e", "--model", "elastic", "-n", "1e7", "--json", out,
                                          "--csv", csv_out], tmp_path, again_after=again_after)
    assert code == 130 and "Traceback" not in tty and "Error" not in tty, tty[-2000:]
    d = json.loads(out.read_text())
    assert d["partial"] is True and 0 < d["samples_done"] < 10 ** 7
    lines = csv_out.read_text().splitlines()
    assert lines[0].endswith(",partial") and len(lines) > 10 and all(x.endswith(",True") for x in lines[1:])


PACKAGE_FRAME = f'File "{Path(rvbacklash.__file__).resolve().parent}{os.sep}'
SCRIPT = Path(sys.executable).with_name("rvbacklash")  # the console script pip wrote
ENTRY_POINTS = {"script": [str(SCRIPT)], "module": [sys.executable, "-m", "rvbacklash"]}


def _ctrl_c_after(delay: float, args: list[str], env: dict, entry: str = "module") -> subprocess.CompletedProcess:
    """Run the command as a user does (no terminal), send SIGINT ``delay`` seconds after its start."""
    proc = subprocess.Popen([*ENTRY_POINTS[entry], *map(str, args)], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, env=env)
    time.sleep(delay)
    proc.send_signal(signal.SIGINT)  # nothing if the command has already ended
    out, err = proc.communicate(timeout=600)  # a guard against a run that goes on, not a time limit
    return subprocess.CompletedProcess(args, proc.returncode, out, err)


def _assert_ended_as_a_ctrl_c_should(p: subprocess.CompletedProcess, out: Path) -> None:
    """Whatever phase the press landed in (the test never assumes one): exit 130, nothing written
    or the finished part marked partial; or exit 0 with the whole result (the command had ended).
    No traceback through the package's code. Python's own start, before the first line of the
    package runs, no program can handle: until Python has set its handler the process dies by
    SIGINT (a shell reports 130) and prints nothing; in its site module (.pth files), runpy or the
    script's loading it prints its own KeyboardInterrupt ('Fatal Python error: init_import_site',
    'Could not import runpy module', 'python: failed to set __main__.__loader__', exit 1 or -2;
    'Failed checking if argv[0] is an import path entry', and the command runs on) - here up to
    0.07 s after the start with the machine under load. The press used to land in the package's
    code: its __init__ imported importlib.metadata (up to 0.09 s here, half a second on a loaded
    machine), before the command line's handler was set."""
    assert PACKAGE_FRAME not in p.stderr, p.stderr[-3000:]
    if p.returncode == 0:
        assert json.loads(out.read_text())["partial"] is False
    elif p.returncode == 130:
        if out.exists():  # a block had finished before the press: kept, marked partial
            assert json.loads(out.read_text())["partial"] is True
        else:
            assert p.stdout == "" and p.stderr.strip().splitlines()[-1] == "interrupted: nothing was written"
    else:  # Python's own start (docstring)
        assert p.returncode in (-signal.SIGINT, 1) and p.stdout == "" and not out.exists(), (p.returncode, p.stderr)
        assert p.stderr == "" or p.stderr.strip().splitlines()[-1].startswith("KeyboardInterrupt"), p.stderr[-3000:]


# The sweep of delays, each with one entry point, alternated: both entry points see presses from
# Python's start through the package's import into the kernels' loading. The two differ only
# before the package's main() sets its handler (the console script's wrapper or runpy); after
# that their code paths are the same, so a press at a given delay through both entry points
# tested one phase twice (26 process starts, now 13).
SWEEP = [(0.0, "script"), (0.01, "module"), (0.02, "script"), (0.03, "module"), (0.05, "script"), (0.07, "module"),
         (0.1, "script"), (0.15, "module"), (0.2, "script"), (0.3, "module"), (0.5, "script"), (0.75, "module"),
         (1.0, "script")]


def test_the_sweep_presses_both_entry_points_early_and_late():
    for entry in ENTRY_POINTS:
        delays = [d for d, e in SWEEP if e == entry]
        assert min(delays) <= 0.01 and max(delays) >= 0.75 and len(delays) >= 6, (entry, delays)


@pytest.mark.parametrize("delay, entry", SWEEP)
def test_ctrl_c_at_any_moment_from_the_start_exits_130(tmp_path, delay, entry):
    """Regression (issue 35, 2.12): a Ctrl-C 0.02-0.5 s after the start (the package importing)
    printed a KeyboardInterrupt traceback and the process died by SIGINT (exit -2). Both entry
    points (the `rvbacklash` script and `python -m rvbacklash`), a sweep of delays from the start
    into the kernels' loading; the outcome is checked whatever phase the press lands in."""
    out = tmp_path / "out.json"
    p = _ctrl_c_after(delay, ["simulate", "rv80e", "--model", "contact", "-n", "1e6", "--json", out], dict(os.environ),
                      entry)
    _assert_ended_as_a_ctrl_c_should(p, out)


@pytest.mark.parametrize("delay, fresh_cache", [(0.5, False), (1.0, False), (2.0, False), (3.0, True), (15.0, True)])
def test_ctrl_c_while_the_kernels_load_exits_130_at_once(tmp_path, delay, fresh_cache):
    """Regression: Ctrl-C while the compiled kernels load (numba compiling, or loading its cache)
    was lost (the run went on to its end) or ended in a numba traceback, exit 1 ('no compiled
    object yet', 'PipelineTuningOptions'). Whatever the phase, exit 130 without a traceback; until
    a block has finished there is nothing to keep and nothing is written. With an empty numba
    cache the kernels compile for tens of seconds: 3 s usually lands in the main thread's
    compilation, 15 s in the first block's (a worker thread, inside the engine's stop window); a
    fast machine may have finished a block by then, which is kept, marked partial."""
    out = tmp_path / "out.json"
    env = {**os.environ, **({"NUMBA_CACHE_DIR": str(tmp_path / "numba")} if fresh_cache else {})}
    p = _ctrl_c_after(delay, ["simulate", "rv80e", "--model", "transmission", "-n", "1e7", "--json", out], env)
    _assert_ended_as_a_ctrl_c_should(p, out)


def test_a_ctrl_c_that_leaked_the_import_lock_at_start_up_exits_130(tmp_path):
    """Regression: a press in Python's own start can leak the global import lock (between
    importlib's ``_imp.acquire_lock()`` and its ``try``) while Python swallows the
    KeyboardInterrupt, and the command ran on until a worker thread waited for the lock forever (a
    contact run hung 600 s in this file's sweep). The leak is made by hand here: the command ends
    as a Ctrl-C before any work does, exit 130, nothing written."""
    out = tmp_path / "out.json"
    code = ("import _imp, sys; _imp.acquire_lock(); "
            f"sys.argv = ['rvbacklash', 'simulate', 'rv80e', '--model', 'contact', '-n', '2000', '--json', {str(out)!r}]; "
            "from rvbacklash.cli import main; main()")
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=600)
    assert p.returncode == 130, (p.returncode, p.stderr[-2000:])
    assert p.stderr.strip().splitlines()[-1] == "interrupted: nothing was written"
    assert not out.exists()
