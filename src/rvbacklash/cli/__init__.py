"""Command-line interface: a thin layer that maps flags to API parameters and results to output.

Every command prints a table by default; ``--format json|csv`` prints the result as JSON or CSV
instead; ``--json FILE`` / ``--csv FILE`` write files (``-`` for standard output); ``-q/--quiet``
prints nothing. Bad input of any kind ends with one line ``error: <flag or field> = <value>:
<allowed>`` on stderr and exit code 2, before any file is written; Ctrl-C exits 130 with the
partial results marked as such.

This module imports nothing at its top (nor does the package's ``__init__``): the entry points
(the ``rvbacklash`` script and ``python -m rvbacklash``) reach ``main`` within a millisecond of
Python's own start, and ``main`` handles Ctrl-C before it imports anything else.
"""


def _exit_130(signum, frame) -> None:
    """Ctrl-C while the command line's own handling loads: end the process as it would
    (``rvbacklash.interrupt``: nothing has been written yet)."""
    import os

    try:
        os.write(2, b"interrupted: nothing was written\n")
    finally:
        os._exit(130)


def _exit_if_the_import_lock_leaked() -> None:
    """A Ctrl-C in Python's own start, before any handler of ours, can land between importlib's
    ``_imp.acquire_lock()`` and its ``try`` and leak the global import lock; Python's start-up then
    swallows the KeyboardInterrupt ('Failed checking if argv[0] is an import path entry') and the
    command runs on, until its first worker thread imports something and waits for the lock
    forever (seen: a contact run hung with its threads in ``_PyImport_AcquireLock``). Here, with no
    other thread running and no import under way in this one, a held lock can only be that leak:
    the press asked to stop, so stop as the command line would, nothing written, exit 130."""
    import _imp
    import _thread

    if _imp.lock_held() and _thread._count() == 0:
        _exit_130(None, None)


def main(argv: list[str] | None = None) -> None:
    """Entry point of the ``rvbacklash`` command: ``argv`` None reads ``sys.argv`` (the process is
    the command), a list runs those arguments in this process (tests). The Ctrl-C handling of the
    command line comes first, before anything is imported: a Ctrl-C while the modules load ends
    the command at once with exit 130, as in every other phase (``rvbacklash.interrupt``). The
    first handler is set through ``_signal`` (the C module Python itself loads at start-up: no
    import to wait for) and lasts until ``rvbacklash.interrupt`` has loaded and installs its own."""
    if argv is None:  # the process is the command (in process, a test keeps its own handler)
        import _signal

        _signal.signal(_signal.SIGINT, _exit_130)
        _exit_if_the_import_lock_leaked()
    from rvbacklash.interrupt import exit_on_sigint

    code: object = 0
    with exit_on_sigint(process=argv is None):
        from rvbacklash.cli.entry import main as run

        if argv is not None:
            run(argv)
            return
        try:
            run(argv)
        except SystemExit as e:  # the command's end: its exit code
            code = e.code
    _end_process(code)


def _end_process(code: object) -> None:
    """End the process as Python's own exit would, without its teardown: the standard streams
    flushed, the other threads joined and the exit handlers run (``atexit``: temporary
    directories, worker pools, a sweep's cluster), then ``os._exit``. What is skipped is the
    interpreter freeing every module and object, and numba's compiled code with them: ~0.25 s of
    CPU after every command that loaded a kernel (issue 35), for nothing: every file a command
    writes is closed before it returns (atomic writes). Ctrl-C is ignored meanwhile, as in
    Python's own shutdown (``exit_on_sigint`` with ``process``). Without the private
    ``threading._shutdown`` (Python's own step here), Python's exit as usual."""
    import atexit
    import os
    import sys
    import threading

    if code is None:
        code = 0
    elif not isinstance(code, int):  # SystemExit("message"): printed, exit 1, as Python does
        print(code, file=sys.stderr)
        code = 1
    join_threads = getattr(threading, "_shutdown", None)
    if join_threads is None:  # pragma: no cover - a Python without it
        sys.exit(code)
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except Exception:  # noqa: BLE001 - a closed pipe (`| head`): nothing more to write there
            pass
    join_threads()
    atexit._run_exitfuncs()
    for stream in (sys.stdout, sys.stderr):  # what an exit handler printed
        try:
            stream.flush()
        except Exception:  # noqa: BLE001
            pass
    os._exit(code & 0xFF if code >= 0 else 1)


__all__ = ["main"]
