"""rvbacklash.interrupt: the command line's Ctrl-C in each phase, with real signals, each case in a
fresh interpreter (the handler ends the process), no timing: the signal is sent by the process to
itself at the point under test."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap

import pytest

from rvbacklash import interrupt

PRELUDE = """
import os, signal, sys
from rvbacklash import interrupt

def ctrl_c():
    os.kill(os.getpid(), signal.SIGINT)

"""


def _run(body: str) -> subprocess.CompletedProcess:
    code = PRELUDE + "with interrupt.exit_on_sigint(process=True):\n" + textwrap.indent(textwrap.dedent(body), "    ")
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)


def test_outside_a_window_the_command_ends_at_once():
    p = _run("""
        print("before", flush=True)
        ctrl_c()
        print("after")  # never reached
    """)
    assert (p.returncode, p.stdout, p.stderr) == (130, "before\n", "interrupted: nothing was written\n")


def test_in_a_window_before_any_work_finished_the_command_ends_at_once():
    """E.g. the first block compiling its kernel in a worker thread: nothing to keep, no wait."""
    p = _run("""
        with interrupt.stop_requested() as stop:
            ctrl_c()
            print("after")
    """)
    assert (p.returncode, p.stdout, p.stderr) == (130, "", "interrupted: nothing was written\n")


def test_after_progress_a_ctrl_c_stops_the_loop_and_more_are_ignored():
    p = _run("""
        with interrupt.stop_requested() as outer:
            interrupt.mark_progress()
            with interrupt.stop_requested() as inner:
                ctrl_c()
                print("stop requested:", inner.is_set(), outer.is_set(), flush=True)
                ctrl_c()  # a second press: ignored, the partial results are being written
                ctrl_c()
        with interrupt.stop_requested() as later:  # a loop after the stop does not start its work
            print("later loop stopped:", later.is_set())
        print("finished")
        sys.exit(130)
    """)
    assert p.returncode == 130 and "Traceback" not in p.stderr
    assert p.stdout == "stop requested: True True\nlater loop stopped: True\nfinished\n"
    assert p.stderr.count("Ctrl-C again is ignored") == 1


def test_a_ctrl_c_while_writing_lets_the_files_be_written_first(tmp_path):
    out = tmp_path / "out.txt"
    p = _run(f"""
        from pathlib import Path
        from rvbacklash.atomic import atomic_write
        with interrupt.writing():
            ctrl_c()
            atomic_write("--json", Path({str(out)!r}), "whole")
            print("written", flush=True)
        print("after")  # never reached: the deferred Ctrl-C ends the command here
    """)
    assert (p.returncode, p.stdout) == (130, "written\n") and p.stderr == "interrupted after the files were written\n"
    assert out.read_text() == "whole" and sorted(x.name for x in tmp_path.iterdir()) == ["out.txt"]


def test_after_the_command_the_shutdown_ignores_ctrl_c():
    """With the command done (its partial results written), a press during the interpreter's
    shutdown killed the process by SIGINT (exit -2) instead of letting it exit 130."""
    code = PRELUDE + textwrap.dedent("""
        with interrupt.exit_on_sigint(process=True):
            pass
        ctrl_c()
        print("shutting down")
        sys.exit(130)
    """)
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert (p.returncode, p.stdout, p.stderr) == (130, "shutting down\n", "")


def test_in_process_the_previous_handler_comes_back():
    before = signal.getsignal(signal.SIGINT)
    with interrupt.exit_on_sigint():
        assert signal.getsignal(signal.SIGINT) is not before
    assert signal.getsignal(signal.SIGINT) is before


def test_library_use_a_second_ctrl_c_in_a_window_raises():
    """Without the command line's handler (a script, Jupyter): the first press sets the event,
    the second raises KeyboardInterrupt at once."""
    with interrupt.stop_requested() as stop:
        os.kill(os.getpid(), signal.SIGINT)
        assert stop.is_set()
        with pytest.raises(KeyboardInterrupt):
            os.kill(os.getpid(), signal.SIGINT)
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


def test_a_sweep_keeps_its_points_on_disk_so_a_second_ctrl_c_stops_at_once():
    p = _run("""
        interrupt.mark_progress(on_disk=True)
        with interrupt.stop_requested() as stop:
            ctrl_c()
            print("stop requested:", stop.is_set(), flush=True)
            try:
                ctrl_c()
            except KeyboardInterrupt:
                print("stopped at once")
        sys.exit(130)
    """)
    assert (p.returncode, p.stdout) == (130, "stop requested: True\nstopped at once\n") and p.stderr == ""


def test_after_progress_a_ctrl_c_between_loops_keeps_the_finished_work():
    """Between two loops, or after the last one (a report's later sections, the statistics, the
    rendering), a press once work has finished used to end the process with 'nothing was written',
    throwing that work away: it is a stop request (later loops start stopped), the command writes
    what it has and ends with exit 130 (stop_was_requested)."""
    p = _run("""
        with interrupt.stop_requested():
            interrupt.mark_progress()
        ctrl_c()  # between loops
        print("still running, stop requested:", interrupt.stop_was_requested(), flush=True)
        with interrupt.stop_requested() as later:
            print("later loop stopped:", later.is_set(), flush=True)
        with interrupt.writing():
            print("written", flush=True)
    """)
    assert p.returncode == 0 and "Traceback" not in p.stderr  # the caller (cli.entry) turns the request into 130
    assert p.stdout == "still running, stop requested: True\nlater loop stopped: True\nwritten\n"


def test_a_failed_write_lets_its_error_through_after_a_ctrl_c():
    """A press during a write that then fails: the command's error (one line, exit 2) is what the
    user sees, not 'interrupted after the files were written'."""
    p = _run("""
        try:
            with interrupt.writing():
                ctrl_c()
                raise ValueError("disk full")
        except ValueError as e:
            print("error:", e, flush=True)
            sys.exit(2)
    """)
    assert (p.returncode, p.stdout.strip()) == (2, "error: disk full")


def test_the_command_line_exits_130_when_a_finished_run_was_stopped(monkeypatch, capsys):
    """cli.entry: a command that returned normally after a stop request exits 130."""
    from rvbacklash.cli import entry

    monkeypatch.setattr(entry, "app", lambda **kwargs: 0)
    monkeypatch.setattr(entry, "stop_was_requested", lambda: True)
    with pytest.raises(SystemExit) as e:
        entry.main(["simulate", "rv80e"])
    assert e.value.code == 130 and "interrupted: what was finished is written" in capsys.readouterr().err


def _entry_point_with_ctrl_c_on_import(module: str, argv: list[str], run_as: str = "script") -> subprocess.CompletedProcess:
    """The command as a process runs it (``run_as``: the console script's three lines, or
    ``python -m rvbacklash``), with a Ctrl-C sent by the process to itself the moment ``module``
    starts to be imported (a meta-path hook): the phase under test, without timing."""
    hook = textwrap.dedent(f"""
        import os, signal, sys
        class CtrlCOnImport:
            def find_spec(self, name, path=None, target=None):
                if name == {module!r}:
                    os.kill(os.getpid(), signal.SIGINT)
                return None
        sys.meta_path.insert(0, CtrlCOnImport())
        sys.argv = ["rvbacklash", *{argv!r}]
    """)
    if run_as == "script":  # what pip writes into .venv/bin/rvbacklash
        code = hook + "from rvbacklash.cli import main\nsys.exit(main())\n"
    else:
        code = hook + "import runpy\nrunpy.run_module('rvbacklash', run_name='__main__', alter_sys=True)\n"
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)


@pytest.mark.parametrize("run_as", ["script", "module"])
@pytest.mark.parametrize("module", ["rvbacklash.interrupt", "rvbacklash.cli.entry", "typer", "numpy"])
def test_a_ctrl_c_while_the_command_line_imports_exits_130(module, run_as):
    """Regression (issue 35, 2.12): a Ctrl-C while the package imported ended in a KeyboardInterrupt
    traceback, exit -2 (it landed in the import of rvbacklash.interrupt, before the command line's
    handler existed, or of importlib.metadata, which the package's __init__ imported for
    __version__). The entry point sets a first handler before it imports anything."""
    p = _entry_point_with_ctrl_c_on_import(module, ["simulate", "rv80e", "-n", "1000"], run_as)
    assert (p.returncode, p.stdout, p.stderr) == (130, "", "interrupted: nothing was written\n")


def test_the_entry_points_import_nothing_before_the_ctrl_c_handling():
    """``import rvbacklash`` and ``rvbacklash.cli`` (what the console script imports before it calls
    ``main``) import no other module: every import before the handler is a window in which a Ctrl-C
    is a traceback. ``__version__`` is still there, imported on first use."""
    code = ("import sys\nbefore = set(sys.modules)\nimport rvbacklash.cli\n"
            "print(sorted(set(sys.modules) - before))\nimport rvbacklash\nprint(rvbacklash.__version__ != '')\n")
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert p.stdout.splitlines() == ["['rvbacklash', 'rvbacklash.cli']", "True"], p.stderr
