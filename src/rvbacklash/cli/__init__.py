"""Command-line interface: a thin layer that maps flags to API parameters and results to output.

Every command prints a table by default; ``--format json|csv`` prints the result as JSON or CSV
instead; ``--json FILE`` / ``--csv FILE`` write files (``-`` for standard output); ``-q/--quiet``
prints nothing. Bad input of any kind ends with one line ``error: <flag or field> = <value>:
<allowed>`` on stderr and exit code 2, before any file is written; Ctrl-C exits 130 with the
partial results marked as such.
"""

from __future__ import annotations


def main(argv: list[str] | None = None) -> None:
    """Entry point of the ``rvbacklash`` command: ``argv`` None reads ``sys.argv`` (the process is
    the command), a list runs those arguments in this process (tests). The Ctrl-C handling of the
    command line comes first, before typer, rich and the commands are imported: a Ctrl-C while
    they load ends the command at once with exit 130, as in every other phase
    (``rvbacklash.interrupt``)."""
    from rvbacklash.interrupt import exit_on_sigint

    with exit_on_sigint(process=argv is None):
        from rvbacklash.cli.entry import main as run

        run(argv)


__all__ = ["main"]
