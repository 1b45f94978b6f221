"""Command-line interface: a thin layer that maps flags to API parameters and results to output.

Every command prints a table by default; ``--format json|csv`` prints the result as JSON or CSV
instead; ``--json FILE`` / ``--csv FILE`` write files (``-`` for standard output); ``-q/--quiet``
prints nothing. Bad input of any kind ends with one line ``error: <flag or field> = <value>:
<allowed>`` on stderr and exit code 2, before any file is written; Ctrl-C exits 130 with the
partial results marked as such.
"""

from rvbacklash.cli.entry import main

__all__ = ["main"]
