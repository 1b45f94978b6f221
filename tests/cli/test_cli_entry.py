"""The `rvbacklash` process's end (rvbacklash.cli.main): everything a command leaves is finished, then
the process ends without Python's teardown (issue 35: ~0.25 s of CPU after every command that
loaded a compiled kernel)."""

from __future__ import annotations

import subprocess
import sys
import textwrap


def _command_process(argv: list[str], before: str = "") -> subprocess.CompletedProcess:
    """The console script's three lines with ``before`` run first (in the same process)."""
    code = textwrap.dedent(before) + textwrap.dedent(f"""
        import sys
        sys.argv = ["rvbacklash", *{argv!r}]
        from rvbacklash.cli import main
        sys.exit(main())
    """)
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)


def test_the_process_ends_without_pythons_teardown():
    """Regression (issue 35): the interpreter's teardown freed every module and numba's compiled
    code after the command had finished. An object alive at the end is not torn down (its
    __del__ never runs) and the output is complete."""
    p = _command_process(["--version"], """
        class Alive:
            def __del__(self):
                print("torn down", flush=True)
        alive = Alive()
    """)
    assert p.returncode == 0 and p.stderr == ""
    assert p.stdout.startswith("rvbacklash ") and "torn down" not in p.stdout, p.stdout


def test_exit_handlers_and_threads_finish_first():
    """What Python's exit does before its teardown still happens, in its order: the other
    (non-daemon) threads are joined, the exit handlers run (temporary directories, worker pools),
    and what they print is flushed. The thread here starts its work only once the command has
    returned (no timing)."""
    p = _command_process(["--version"], """
        import atexit, threading
        import rvbacklash.cli.entry as entry
        returned = threading.Event()
        command = entry.main
        def run(argv):
            try:
                command(argv)
            finally:
                returned.set()
        entry.main = run
        def late():
            returned.wait()
            print("thread finished", flush=True)
        threading.Thread(target=late).start()
        atexit.register(lambda: print("exit handler ran"))
    """)
    assert p.returncode == 0 and p.stderr == ""
    assert p.stdout.splitlines()[1:] == ["thread finished", "exit handler ran"], p.stdout


def test_the_exit_code_is_the_commands():
    p = _command_process(["simulate", "rv80e", "--seed", "-1"])
    assert (p.returncode, p.stdout) == (2, "") and p.stderr.startswith("error: --seed")
