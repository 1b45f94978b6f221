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
    from rvbacklash.interrupt import exit_on_sigint

    with exit_on_sigint(process=argv is None):
        from rvbacklash.cli.entry import main as run

        run(argv)


__all__ = ["main"]
